//! `motion-cmd` in teleop mode: `realtime start`, motmod loaded through
//! halcmd, then the axis subcommands from other processes, checked through
//! `motion-cmd status`.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::{accepted, mcmd, run, start_motion_instance, wait_status};

fn rejected(args: &[&str], instance: &str, why: &str) {
    let (code, out, err) = mcmd(args, instance);
    assert_eq!(code, 1, "motion-cmd {args:?}: {out}{err}");
    assert!(
        out.starts_with("rejected (serial ") && out.contains(why),
        "{out}"
    );
}

/// The status line of axis `letter`.
fn axis_line(status: &str, letter: &str) -> Option<String> {
    status
        .lines()
        .find(|l| l.starts_with(&format!("{letter} ")))
        .map(str::to_string)
}

#[test]
fn motion_cmd_jogs_axes_in_teleop_mode() {
    let inst = common::instance("mcmd-tel");
    // Usage: help and axis parsing need no instance.
    let (code, out, _) = mcmd(&["--help"], &inst);
    assert_eq!(code, 0);
    assert!(out.contains("axes (teleop mode):"), "{out}");
    for line in [
        "axis-jog-cont AXIS VEL",
        "axis-jog-incr AXIS VEL DIST",
        "axis-jog-abs AXIS VEL POS",
        "axis-jog-abort AXIS",
        "set-axis-limits AXIS MIN MAX",
        "set-axis-vel-limit AXIS VEL",
        "set-axis-acc-limit AXIS ACC",
    ] {
        assert!(out.contains(line), "{line}: {out}");
    }
    let (code, _, err) = mcmd(&["axis-jog-cont", "q", "1"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("AXIS must be one of x y z"), "{err}");
    let (code, _, err) = mcmd(&["axis-jog-abort"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("missing AXIS"), "{err}");
    let (code, _, err) = mcmd(&["axis-jog-incr", "x", "1"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("missing DIST"), "{err}");
    let (code, _, err) = mcmd(&["set-axis-vel-limit", "x", "1", "2"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("takes 2 argument(s), 3 given"), "{err}");

    let realtime = env!("CARGO_BIN_EXE_realtime");
    start_motion_instance(&inst);
    wait_status(&inst, "the first status", |s| s.contains("mode DISABLED"));
    for (j, l) in [("0", "x"), ("1", "Y"), ("2", "2")] {
        accepted(&["activate", j], &inst);
        accepted(&["set-limits", j, "-10", "10"], &inst);
        accepted(&["set-vel-limit", j, "20"], &inst);
        accepted(&["set-acc-limit", j, "500"], &inst);
        accepted(&["set-axis-limits", l, "-5", "5"], &inst);
        accepted(&["set-axis-vel-limit", l, "20"], &inst);
        accepted(&["set-axis-acc-limit", l, "500"], &inst);
    }
    rejected(
        &["set-axis-limits", "9", "0", "1"],
        &inst,
        "axis 9 does not exist",
    );
    rejected(
        &["set-axis-limits", "z", "1", "0"],
        &inst,
        "minimum limit 1 is above maximum limit 0",
    );
    accepted(&["teleop"], &inst);
    let s = wait_status(&inst, "the remembered mode", |s| {
        s.contains("mode on enable: TELEOP")
    });
    assert!(s.contains("mode DISABLED"), "{s}");
    rejected(&["axis-jog-cont", "x", "1"], &inst, "motion is not enabled");
    accepted(&["enable"], &inst);
    wait_status(&inst, "teleop", |s| s.contains("mode TELEOP  enabled yes"));
    rejected(&["jog-cont", "0", "1"], &inst, "motion is in teleop mode");
    rejected(&["axis-jog-cont", "a", "1"], &inst, "axis A is not one of");
    rejected(
        &["axis-jog-incr", "z", "1", "6"],
        &inst,
        "jog of axis Z to 6 would leave its limits [-5, 5]",
    );

    accepted(&["axis-jog-incr", "y", "10", "0.5"], &inst);
    let s = wait_status(&inst, "the incremental jog to end", |s| {
        s.contains("in-position yes") && axis_line(s, "Y").is_some_and(|l| l.contains("0.500000"))
    });
    // The joint followed.
    assert!(
        s.lines()
            .any(|l| l.starts_with("1     yes    yes") && l.contains("0.500000")),
        "{s}"
    );
    accepted(&["axis-jog-abs", "X", "10", "-7"], &inst);
    wait_status(&inst, "the absolute jog to the limit", |s| {
        s.contains("in-position yes") && axis_line(s, "X").is_some_and(|l| l.contains("-5.000000"))
    });
    accepted(&["axis-jog-cont", "2", "1"], &inst);
    wait_status(&inst, "the continuous jog to run", |s| {
        axis_line(s, "Z").is_some_and(|l| l.contains("moving jogging"))
    });
    rejected(&["free"], &inst, "motion is not in position");
    accepted(&["axis-jog-abort", "z"], &inst);
    wait_status(&inst, "the jog to stop", |s| s.contains("in-position yes"));
    accepted(&["coord"], &inst);
    wait_status(&inst, "coordinated mode", |s| s.contains("mode COORD"));
    rejected(&["axis-jog-cont", "x", "1"], &inst, "not in teleop mode");
    accepted(&["free"], &inst);
    wait_status(&inst, "free mode", |s| s.contains("mode FREE"));
    accepted(&["disable"], &inst);
    wait_status(&inst, "disabled", |s| s.contains("mode DISABLED"));

    assert!(run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}

#[test]
fn motion_cmd_sets_the_eoffset_ratio_and_its_status_shows_the_offsets() {
    let inst = common::instance("mcmd-eoff");
    let (code, out, _) = mcmd(&["--help"], &inst);
    assert_eq!(code, 0);
    assert!(out.contains("set-axis-eoffset-ratio AXIS RATIO"), "{out}");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    start_motion_instance(&inst);
    wait_status(&inst, "the first status", |s| s.contains("mode DISABLED"));
    for (j, l) in [("0", "x"), ("1", "y"), ("2", "z")] {
        accepted(&["activate", j], &inst);
        accepted(&["set-limits", j, "-10", "10"], &inst);
        accepted(&["set-vel-limit", j, "20"], &inst);
        accepted(&["set-acc-limit", j, "500"], &inst);
        accepted(&["set-homing-params", j, "HOME_SEQUENCE=0"], &inst);
        accepted(&["set-axis-limits", l, "-5", "5"], &inst);
        accepted(&["set-axis-vel-limit", l, "10"], &inst);
        accepted(&["set-axis-acc-limit", l, "100"], &inst);
    }
    rejected(
        &["set-axis-eoffset-ratio", "z", "0.95"],
        &inst,
        "bad external offset ratio (OFFSET_AV_RATIO, 0 to 0.9) 0.95",
    );
    accepted(&["set-axis-eoffset-ratio", "z", "0.2"], &inst);
    accepted(&["enable"], &inst);
    rejected(
        &["set-axis-eoffset-ratio", "z", "0.3"],
        &inst,
        "only be changed while motion is disabled",
    );
    accepted(&["home", "-1"], &inst);
    wait_status(&inst, "homed, in teleop", |s| {
        s.contains("all-homed yes") && s.contains("mode TELEOP")
    });
    common::halcmd(&["setp", "axis.z.eoffset-scale", "0.5"], &inst);
    common::halcmd(&["setp", "axis.z.eoffset-enable", "1"], &inst);
    common::halcmd(&["setp", "axis.z.eoffset-counts", "1"], &inst);
    let s = wait_status(&inst, "the offset", |s| {
        s.contains("external offsets: Z 0.500000 (request 0.500000) active")
    });
    // The joint carries it; the axis table shows the commanded pose.
    assert!(
        s.lines()
            .any(|l| l.starts_with("2     yes    yes") && l.contains("0.500000")),
        "{s}"
    );
    accepted(&["disable"], &inst);
    wait_status(&inst, "disabled", |s| s.contains("mode DISABLED"));
    assert!(run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}
