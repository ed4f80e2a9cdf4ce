//! `realtime start`, motmod loaded through halcmd, then `motion-cmd` from
//! other processes enables motion and jogs a joint, checked through
//! `motion-cmd status`.

mod common;

use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn run(bin: &str, args: &[&str], instance: &str) -> Output {
    Command::new(bin)
        .args(args)
        .env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .output()
        .expect("runs")
}

fn halcmd(args: &[&str], instance: &str) {
    let out = run(env!("CARGO_BIN_EXE_halcmd"), args, instance);
    assert!(
        out.status.success(),
        "halcmd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs motion-cmd; (exit code, stdout, stderr).
fn mcmd(args: &[&str], instance: &str) -> (i32, String, String) {
    let out = run(env!("CARGO_BIN_EXE_motion-cmd"), args, instance);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn accepted(args: &[&str], instance: &str) {
    let (code, out, err) = mcmd(args, instance);
    assert_eq!(code, 0, "motion-cmd {args:?}: {out}{err}");
    assert!(out.starts_with("accepted (serial "), "{out}");
}

fn wait_status(instance: &str, what: &str, f: impl Fn(&str) -> bool) -> String {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        let (code, out, err) = mcmd(&["status"], instance);
        assert_eq!(code, 0, "{err}");
        if f(&out) {
            return out;
        }
        assert!(Instant::now() < end, "timed out waiting for {what}:\n{out}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

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
    assert!(run(realtime, &["start"], &inst).status.success());
    halcmd(&["loadrt", "trivkins", "coordinates=xyz"], &inst);
    halcmd(&["loadrt", "motmod", "num_joints=3"], &inst);
    for j in 0..3 {
        let sig = format!("j{j}pos");
        halcmd(
            &[
                "net",
                &sig,
                &format!("joint.{j}.motor-pos-cmd"),
                &format!("joint.{j}.motor-pos-fb"),
            ],
            &inst,
        );
    }
    halcmd(&["addf", "motion-command-handler", "servo-thread"], &inst);
    halcmd(&["addf", "motion-controller", "servo-thread"], &inst);
    halcmd(&["start"], &inst);

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
    let (code, out, _) = mcmd(&["amp-enable", "0"], &inst);
    assert_eq!(code, 1);
    assert!(out.contains("not supported"), "{out}");

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
    let _ = std::fs::remove_file(hal_tools::launch::log_path(&inst));
}
