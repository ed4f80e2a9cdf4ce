//! `realtime start`, motmod loaded through halcmd, then `motion-cmd` from
//! other processes enables motion and jogs a joint, checked through
//! `motion-cmd status`.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::{accepted, mcmd, run, start_motion_instance, wait_status};

#[test]
fn motion_cmd_enables_and_jogs_a_joint_of_a_running_instance() {
    let inst = common::instance("mcmd");
    // Usage errors need no instance.
    let (code, out, _) = mcmd(&["--help"], &inst);
    assert_eq!(code, 0);
    assert!(out.contains("jog-incr JOINT VEL DISTANCE"), "{out}");
    let (code, _, err) = mcmd(&["jog-cont", "x", "1"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("JOINT must be an integer"), "{err}");
    let (code, _, err) = mcmd(&["status"], &inst);
    assert_eq!(code, 2, "no instance running: {err}");

    let realtime = env!("CARGO_BIN_EXE_realtime");
    start_motion_instance(&inst);

    let s = wait_status(&inst, "the first status", |s| s.contains("mode DISABLED"));
    assert!(s.contains("last command: none"), "{s}");
    for j in ["0", "1", "2"] {
        accepted(&["activate", j], &inst);
        accepted(&["set-limits", j, "-10", "10"], &inst);
        accepted(&["set-vel-limit", j, "20"], &inst);
        accepted(&["set-acc-limit", j, "500"], &inst);
    }
    // Rejected with its reason.
    let (code, out, _) = mcmd(&["jog-cont", "0", "1"], &inst);
    assert_eq!(code, 1);
    assert!(
        out.starts_with("rejected (serial ") && out.contains("motion is not enabled"),
        "{out}"
    );
    // The amplifier commands are taken and change nothing (the amplifier
    // follows ENABLE/DISABLE), as in LinuxCNC; a joint beyond the
    // machine's is refused.
    accepted(&["amp-enable", "0"], &inst);
    let (code, out, _) = mcmd(&["amp-disable", "7"], &inst);
    assert_eq!(code, 1);
    assert!(out.contains("joint"), "{out}");
    // [KINS]JOINTS beyond what motmod was loaded with is refused, naming it.
    let (code, out, _) = mcmd(&["set-num-joints", "9"], &inst);
    assert_eq!(code, 1);
    assert!(out.contains("motmod's num_joints"), "{out}");
    accepted(&["set-num-joints", "3"], &inst);
    accepted(
        &["spindle-params", "0", "3000", "100", "-3000", "-100"],
        &inst,
    );
    accepted(&["set-vel", "0", "1.2"], &inst);
    accepted(&["arc-blends", "1", "0", "50", "4", "100"], &inst);
    accepted(&["probe-err-inhibit", "0", "0"], &inst);

    accepted(&["enable"], &inst);
    wait_status(&inst, "enabled", |s| {
        s.contains("mode FREE  enabled yes") && s.contains("last command: serial")
    });
    accepted(&["jog-incr", "1", "10", "0.5"], &inst);
    let s = wait_status(&inst, "the jog to end", |s| {
        s.contains("in-position yes")
            && s.lines()
                .any(|l| l.starts_with("1     yes    yes") && l.contains("0.500000"))
    });
    assert!(s.contains("accepted (code 0)"), "{s}");
    accepted(&["jog-abs", "0", "5", "-0.25"], &inst);
    wait_status(&inst, "the absolute jog to end", |s| {
        s.lines()
            .any(|l| l.starts_with("0 ") && l.contains("-0.250000") && l.contains("inpos"))
    });
    let (code, out, _) = mcmd(&["watch", "-n", "10", "-c", "2"], &inst);
    assert_eq!(code, 0);
    assert_eq!(out.matches("\x1b[H\x1b[2J").count(), 2, "{out}");
    accepted(&["disable"], &inst);
    wait_status(&inst, "disabled", |s| s.contains("mode DISABLED"));

    assert!(run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}
