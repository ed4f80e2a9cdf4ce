//! Encoder family: `encoder` (software quadrature / pulse counter),
//! `sim_encoder` (simulated quadrature output) and `encoder_ratio`
//! (electronic-gearbox error between two encoders).
//!
//! The counting logic lives in plain structs ([`quadrature::QuadDecoder`],
//! [`encoder::Counter`], [`encoder::Capture`], [`sim_encoder::PulseGen`],
//! [`encoder_ratio::RatioSampler`], ...) that know nothing of pins, so they
//! can be driven and tested without a HAL host; each module's HAL glue
//! reads pins, calls them and writes pins.

// Each module is named after the component it implements, `encoder` too.
#[allow(clippy::module_inception)]
pub mod encoder;
pub mod encoder_ratio;
pub mod quadrature;
pub mod sim_encoder;

use hal_core::module::{ModuleArgs, ParamDecl, ParamKind};
use hal_core::{HalError, ModuleDef, Result};

/// Most channels one load of these modules creates.
pub const MAX_CHAN: usize = 8;

/// The module parameter table shared by the three modules: `num_chan=` and
/// `names=` (an array of [`MAX_CHAN`] strings).
pub const CHANNEL_PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "num_chan",
        kind: ParamKind::Int,
        help: "number of channels (1-8)",
    },
    ParamDecl {
        name: "names",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "names of the channels, comma separated",
    },
];

/// The channel prefixes a `num_chan=` / `names=` load asks for.
///
/// As in LinuxCNC: `num_chan=0` or no `num_chan` with no names means
/// `default` channels named `<base>.<i>`; a non-zero `num_chan` together
/// with a name is an error; with names, the channels are the leading
/// non-empty names. A non-empty name after an empty one (LinuxCNC would
/// silently drop it) is rejected, like halcompile's empty instance names.
pub fn channel_names(
    module: &str,
    base: &str,
    default: usize,
    args: &ModuleArgs,
) -> Result<Vec<String>> {
    let bad = |param: &str, reason: String| HalError::ModuleParam {
        module: module.to_string(),
        param: param.to_string(),
        reason,
    };
    let given = args.str_array("names");
    let leading = given.iter().take_while(|n| !n.is_empty()).count();
    if given[leading..].iter().any(|n| !n.is_empty()) {
        return Err(bad(
            "names",
            format!("empty channel name in '{}'", given.join(",")),
        ));
    }
    let num_chan = args.int("num_chan").unwrap_or(0);
    if num_chan != 0 && leading > 0 {
        return Err(HalError::ModuleLoad {
            module: module.to_string(),
            reason: "num_chan= and names= are mutually exclusive".into(),
        });
    }
    if leading > 0 {
        return Ok(given[..leading].to_vec());
    }
    let n = if num_chan == 0 {
        default as i64
    } else {
        num_chan
    };
    if !(1..=MAX_CHAN as i64).contains(&n) {
        return Err(bad("num_chan", format!("{n} is out of range 1-{MAX_CHAN}")));
    }
    Ok((0..n).map(|i| format!("{base}.{i}")).collect())
}

/// Every module of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![
        &encoder::MODULE,
        &sim_encoder::MODULE,
        &encoder_ratio::MODULE,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(a: &[&str]) -> Result<Vec<String>> {
        let args = ModuleArgs::parse("encoder", CHANNEL_PARAMS, a)?;
        channel_names("encoder", "encoder", 3, &args)
    }

    #[test]
    fn defaults_and_counts() {
        assert_eq!(names(&[]).unwrap(), ["encoder.0", "encoder.1", "encoder.2"]);
        assert_eq!(names(&["num_chan=0"]).unwrap().len(), 3);
        assert_eq!(names(&["num_chan=1"]).unwrap(), ["encoder.0"]);
        assert_eq!(names(&["num_chan=8"]).unwrap().len(), 8);
        assert_eq!(names(&["names="]).unwrap().len(), 3);
    }

    #[test]
    fn bad_counts_fail_naming_the_parameter() {
        for bad in ["num_chan=9", "num_chan=-1"] {
            match names(&[bad]) {
                Err(HalError::ModuleParam { param, .. }) => assert_eq!(param, "num_chan"),
                other => panic!("{bad}: {other:?}"),
            }
        }
        assert!(matches!(
            names(&["num_chan=x"]),
            Err(HalError::ModuleParam { .. })
        ));
    }

    #[test]
    fn names_give_prefixes() {
        assert_eq!(names(&["names=x,y.z"]).unwrap(), ["x", "y.z"]);
        assert_eq!(names(&["names=a,"]).unwrap(), ["a"]);
        let eight = "names=a,b,c,d,e,f,g,h";
        assert_eq!(names(&[eight]).unwrap().len(), 8);
        assert!(matches!(
            names(&["names=a,b,c,d,e,f,g,h,i"]),
            Err(HalError::ModuleParam { .. })
        ));
        assert!(matches!(
            names(&["names=a,,b"]),
            Err(HalError::ModuleParam { .. })
        ));
        // num_chan=0 is "not given", so it combines with names.
        assert_eq!(names(&["num_chan=0", "names=a"]).unwrap(), ["a"]);
    }

    #[test]
    fn num_chan_and_names_are_exclusive() {
        match names(&["num_chan=2", "names=a"]) {
            Err(HalError::ModuleLoad { reason, .. }) => assert!(reason.contains("exclusive")),
            other => panic!("{other:?}"),
        }
    }
}
