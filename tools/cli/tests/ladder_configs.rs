//! LinuxCNC's sample configurations that run ClassicLadder, started
//! through `linuxcnc` from a copy of the peer's directory: the sim one
//! unchanged, the parport and Mesa ones with the simulator word added to
//! their driver's `loadrt` line. The ladder (classicladder_rt, and the
//! project the `classicladder` loader hands it) carries their e-stop
//! chain, so estop-reset succeeds only when the rungs run.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::path::Path;

use machine::{Machine, Scratch};

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

/// Starts sample `rel` from a copy of its directory, with `(file, from,
/// to)` replacements made in the copy; checks the threads run and the
/// ladder is loaded and running.
fn start(rel: &str, tag: &str, edits: &[(&str, &str, &str)]) -> (Machine, Scratch) {
    let src = Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join(rel);
    let s = Scratch::new(tag);
    copy_dir(src.parent().unwrap(), &s.0);
    for (file, from, to) in edits {
        let p = s.0.join(file);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains(from), "{file} has '{from}'");
        std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
    }
    let m = Machine::start(&s.0.join(src.file_name().unwrap()), tag);
    assert!(m.threads_run(), "{rel}: threads run\n{}", m.stderr());
    assert_eq!(
        m.wait_getp("classicladder.ladder-state", "2"),
        "2",
        "{rel}: the ladder runs\n{}",
        m.stderr()
    );
    (m, s)
}

/// sim/axis/classicladder: the estop latch of rung 1 (estop-reset works
/// only through it, and an e-stop from task breaks it), and the
/// intermittent lube of rung 2: lube on runs the pump (out-01), and the
/// lube-level sensor (in-04) raises the low-lube warning on
/// iocontrol.0.lube_level while timer 2 runs.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn demo_sim_cl_runs_its_estop_chain_and_lube() {
    let (m, _s) = start("sim/axis/classicladder/demo_sim_cl.ini", "ladder-sim", &[]);
    m.task_ok(&["estop-reset"]);
    assert_eq!(m.getp("iocontrol.0.emc-enable-in"), "TRUE");
    m.task_ok(&["machine-on"]);
    m.task_ok(&["lube", "on"]);
    assert_eq!(
        m.wait_getp("classicladder.0.out-01", "TRUE"),
        "TRUE",
        "pump runs"
    );
    m.halcmd(&["sets", "lube-up", "1"]);
    assert_eq!(m.wait_getp("iocontrol.0.lube_level", "TRUE"), "TRUE");
    m.task_ok(&["estop"]);
    assert_eq!(
        m.wait_getp("classicladder.0.out-00", "FALSE"),
        "FALSE",
        "latch broken"
    );
    assert_eq!(m.getp("iocontrol.0.emc-enable-in"), "FALSE");
    m.stop();
}

/// by_interface/parport/classicladder/cl-estop on a simulated port: its
/// ladder joins the external e-stop, task's request and the panel's
/// reset into emc-enable-in.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn cl_estop_on_a_simulated_port() {
    let (m, _s) = start(
        "by_interface/parport/classicladder/cl-estop/cl-estop.ini",
        "ladder-clestop",
        &[("cl-estop.hal", "cfg=0x378", "cfg=\"0x378 sim\"")],
    );
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(m.getp("classicladder.0.out-00"), "TRUE");
    m.task_ok(&["estop"]);
    assert_eq!(m.wait_getp("iocontrol.0.emc-enable-in", "FALSE"), "FALSE");
    m.stop();
}

/// by_machine/smithy/924 on a simulated 5i20: the turret ladder (924.clp,
/// with %IW0 from iocontrol's tool-prep-number) loads into the default
/// sizes; tool-prepare is passed straight to tool-prepared (in-05 to
/// out-03).
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn smithy_924_on_a_simulated_5i20() {
    let (m, _s) = start(
        "by_machine/smithy/924.ini",
        "ladder-smithy",
        &[(
            "924.hal",
            "num_pwmgens=1 num_stepgens=2\"",
            "num_pwmgens=1 num_stepgens=2\" sim=5i20",
        )],
    );
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(
        m.getp("classicladder.0.out-03"),
        m.getp("iocontrol.0.tool-prepare")
    );
    m.stop();
}
