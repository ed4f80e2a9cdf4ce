//! `threads`: creates up to three threads (`loadrt threads name1=servo
//! period1=1000000 ...`). It exports nothing itself; the threads outlive it.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, Result};

const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "name1",
        kind: ParamKind::Str,
        help: "name of thread 1",
    },
    ParamDecl {
        name: "period1",
        kind: ParamKind::Long,
        help: "period of thread 1 (ns)",
    },
    ParamDecl {
        name: "fp1",
        kind: ParamKind::Int,
        help: "thread 1 uses floating point (ignored)",
    },
    ParamDecl {
        name: "name2",
        kind: ParamKind::Str,
        help: "name of thread 2",
    },
    ParamDecl {
        name: "period2",
        kind: ParamKind::Long,
        help: "period of thread 2 (ns)",
    },
    ParamDecl {
        name: "fp2",
        kind: ParamKind::Int,
        help: "thread 2 uses floating point (ignored)",
    },
    ParamDecl {
        name: "name3",
        kind: ParamKind::Str,
        help: "name of thread 3",
    },
    ParamDecl {
        name: "period3",
        kind: ParamKind::Long,
        help: "period of thread 3 (ns)",
    },
    ParamDecl {
        name: "fp3",
        kind: ParamKind::Int,
        help: "thread 3 uses floating point (ignored)",
    },
];

/// The `threads` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "threads",
    params: PARAMS,
    help: "creates up to three realtime threads",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let comp = host.new_rt_component("threads")?;
    // The component is made first so that its id precedes the threads'.
    comp.ready()?;
    for k in 1..=3 {
        let name = args
            .str(&format!("name{k}"))
            .map(str::to_string)
            .or_else(|| (k == 1).then(|| "thread1".to_string()))
            .unwrap_or_default();
        let period = args
            .int(&format!("period{k}"))
            .unwrap_or(if k == 1 { 1_000_000 } else { 0 });
        let fp = args.int(&format!("fp{k}")).unwrap_or(1) != 0;
        if period > 0 && !name.is_empty() {
            host.create_thread(&name, period, fp, None)?;
        }
    }
    Ok(())
}
