//! The instances of a halcompile-style module: `count=` or `names=`
//! (mutually exclusive) give the instance prefixes, `<name-with-dashes>.<i>`
//! or the names themselves. Shared by the components written in that
//! style and by the kinematics modules LinuxCNC builds with halcompile.

use crate::error::{HalError, Result};
use crate::module::{ModuleArgs, ParamDecl, ParamKind};

/// Longest instance name `names=` accepts (LinuxCNC's limit).
pub const MAX_INSTANCE_NAME: usize = 47;
/// Most instances one load may create: far more than any machine needs,
/// and enough for configurations of 10^5 pins (the object index makes
/// loading them linear); a mistyped count fails cleanly here, and a count
/// the segment cannot hold fails with the segment's out-of-memory error
/// and leaves nothing loaded.
pub const MAX_INSTANCES: i64 = 65536;

/// `count=`: the number of instances.
pub const COUNT: ParamDecl = ParamDecl {
    name: "count",
    kind: ParamKind::Int,
    help: "number of instances",
};

/// `names=`: the instance names.
pub const NAMES: ParamDecl = ParamDecl {
    name: "names",
    kind: ParamKind::Str,
    help: "names of the instances, comma separated",
};

/// The module parameters of a module with instances: `count=` and
/// `names=`.
pub const INSTANCE_PARAMS: &[ParamDecl] = &[COUNT, NAMES];

/// The HAL name of a loadrt name: `_` becomes `-`, a leading `hal_` goes.
pub fn hal_name(loadrt_name: &str) -> String {
    loadrt_name
        .strip_prefix("hal_")
        .unwrap_or(loadrt_name)
        .replace('_', "-")
}

/// The instance prefixes `count=`/`names=` ask for.
pub fn instance_names(module: &str, args: &ModuleArgs) -> Result<Vec<String>> {
    let bad = |param: &str, reason: String| HalError::ModuleParam {
        module: module.to_string(),
        param: param.to_string(),
        reason,
    };
    let names = args.str("names").filter(|n| !n.is_empty());
    let count = args.int("count").filter(|&c| c != 0);
    match (count, names) {
        (Some(_), Some(_)) => Err(HalError::ModuleLoad {
            module: module.to_string(),
            reason: "count= and names= are mutually exclusive".into(),
        }),
        (_, Some(names)) => names
            .split(',')
            .map(|n| {
                if n.is_empty() {
                    Err(bad("names", format!("empty instance name in '{names}'")))
                } else if n.len() > MAX_INSTANCE_NAME {
                    Err(bad(
                        "names",
                        format!("'{n}' is too long (at most {MAX_INSTANCE_NAME} characters)"),
                    ))
                } else {
                    Ok(n.to_string())
                }
            })
            .collect(),
        (Some(c), None) if c < 0 => Err(bad("count", format!("{c} is negative"))),
        (Some(c), None) if c > MAX_INSTANCES => Err(bad(
            "count",
            format!("{c} is more than the {MAX_INSTANCES} instances one load may create"),
        )),
        (count, None) => {
            let base = hal_name(module);
            Ok((0..count.unwrap_or(1))
                .map(|i| format!("{base}.{i}"))
                .collect())
        }
    }
}
