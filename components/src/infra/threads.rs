//! `threads`: creates up to three threads (`loadrt threads name1=servo
//! period1=1000000 ...`). It exports nothing itself; the threads outlive it.
//!
//! Beyond LinuxCNC's `nameN`/`periodN`/`fpN`, each thread takes the
//! integrator switches: `timingN=0` turns off its functions' `.time` and
//! `.tmax` measurement (two clock reads per cycle instead of one per
//! function), `cpuN=K` runs it on CPU K (default: `RTAPI_CPU_NUMBER`, else
//! the last CPU under realtime, else any), `missedN=catch-up` runs late
//! cycles back to back as LinuxCNC does instead of skipping them
//! (`missedN=skip`, the default).

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, MissedDeadline, Result};

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
    ParamDecl {
        name: "timing1",
        kind: ParamKind::Int,
        help: "thread 1 times its functions (1, default) or not (0)",
    },
    ParamDecl {
        name: "cpu1",
        kind: ParamKind::Int,
        help: "CPU thread 1 runs on (default: RTAPI_CPU_NUMBER or automatic)",
    },
    ParamDecl {
        name: "missed1",
        kind: ParamKind::Str,
        help: "thread 1's missed deadlines: skip (default) or catch-up",
    },
    ParamDecl {
        name: "timing2",
        kind: ParamKind::Int,
        help: "thread 2 times its functions (1, default) or not (0)",
    },
    ParamDecl {
        name: "cpu2",
        kind: ParamKind::Int,
        help: "CPU thread 2 runs on (default: RTAPI_CPU_NUMBER or automatic)",
    },
    ParamDecl {
        name: "missed2",
        kind: ParamKind::Str,
        help: "thread 2's missed deadlines: skip (default) or catch-up",
    },
    ParamDecl {
        name: "timing3",
        kind: ParamKind::Int,
        help: "thread 3 times its functions (1, default) or not (0)",
    },
    ParamDecl {
        name: "cpu3",
        kind: ParamKind::Int,
        help: "CPU thread 3 runs on (default: RTAPI_CPU_NUMBER or automatic)",
    },
    ParamDecl {
        name: "missed3",
        kind: ParamKind::Str,
        help: "thread 3's missed deadlines: skip (default) or catch-up",
    },
];

/// One thread's request, checked before any thread is made.
struct ThreadSpec {
    name: String,
    period: i64,
    fp: bool,
    timing: bool,
    cpu: Option<usize>,
    missed: MissedDeadline,
}

/// Reads and checks thread `k`'s arguments; `None` if it is not asked for.
fn spec(args: &ModuleArgs, k: usize) -> Result<Option<ThreadSpec>> {
    let bad = |param: String, reason: String| HalError::ModuleParam {
        module: "threads".into(),
        param,
        reason,
    };
    let name = args
        .str(&format!("name{k}"))
        .map(str::to_string)
        .or_else(|| (k == 1).then(|| "thread1".to_string()))
        .unwrap_or_default();
    let period = args
        .int(&format!("period{k}"))
        .unwrap_or(if k == 1 { 1_000_000 } else { 0 });
    if period <= 0 || name.is_empty() {
        return Ok(None);
    }
    let cpu = match args.int(&format!("cpu{k}")) {
        None => None,
        Some(c) => Some(
            usize::try_from(c)
                .map_err(|_| bad(format!("cpu{k}"), format!("{c} is not a CPU number")))?,
        ),
    };
    let missed = match args.str(&format!("missed{k}")) {
        None => MissedDeadline::Skip,
        Some(w) => MissedDeadline::from_name(w).ok_or_else(|| {
            bad(
                format!("missed{k}"),
                format!("'{w}' is neither 'skip' nor 'catch-up'"),
            )
        })?,
    };
    Ok(Some(ThreadSpec {
        name,
        period,
        fp: args.int(&format!("fp{k}")).unwrap_or(1) != 0,
        timing: args.int(&format!("timing{k}")).unwrap_or(1) != 0,
        cpu,
        missed,
    }))
}

/// The `threads` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "threads",
    params: PARAMS,
    help: "creates up to three realtime threads",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let specs = (1..=3).map(|k| spec(args, k)).collect::<Result<Vec<_>>>()?;
    let comp = host.new_rt_component("threads")?;
    // The component is made first so that its id precedes the threads'.
    comp.ready()?;
    for t in specs.into_iter().flatten() {
        host.create_thread(&t.name, t.period, t.fp, t.cpu)?;
        host.set_thread_timing(&t.name, t.timing)?;
        host.set_missed_deadline(&t.name, t.missed)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::HostConfig;

    fn load_with(host: &Host, words: &[&str]) -> Result<()> {
        load(host, &ModuleArgs::parse("threads", PARAMS, words)?)
    }

    #[test]
    fn switches_reach_the_threads() {
        let host = Host::create(HostConfig::for_tests("threads-switches")).unwrap();
        let cpu = hal_core::realtime::allowed_cpus()[0];
        let cpu_arg = format!("cpu2={cpu}");
        load_with(
            &host,
            &[
                "name1=fast",
                "period1=100000",
                "timing1=0",
                "missed1=catch-up",
                "name2=slow",
                "period2=1000000",
                &cpu_arg,
            ],
        )
        .unwrap();
        assert_eq!(
            host.thread_options("fast").unwrap(),
            (false, MissedDeadline::CatchUp)
        );
        assert_eq!(
            host.thread_options("slow").unwrap(),
            (true, MissedDeadline::Skip)
        );
        let mut placed = None;
        for _ in 0..3000 {
            placed = host.thread_affinity("slow").unwrap();
            if placed.is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        assert_eq!(placed, Some(vec![cpu]));
    }

    #[test]
    fn bad_switches_are_refused_before_any_thread_is_made() {
        let host = Host::create(HostConfig::for_tests("threads-bad")).unwrap();
        let e = load_with(
            &host,
            &["name1=a", "name2=b", "period2=2000000", "missed2=later"],
        )
        .unwrap_err();
        assert!(e.to_string().contains("missed2"), "{e}");
        let e = load_with(&host, &["name1=a", "cpu1=-1"]).unwrap_err();
        assert!(e.to_string().contains("cpu1"), "{e}");
        assert!(host.instance().threads().unwrap().is_empty());
    }
}
