//! Task is the one authority over the machine: a machine-on the motion
//! controller answers late (its servo thread stalled) leaves task and
//! motion agreeing, and nothing moves.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::time::Duration;

use machine::{root, text, tool, Machine};
use nix::sys::signal::{kill, Signal};
use nix::unistd::Pid;

/// The pid of the `hal-host` serving `instance` (its command line is
/// `hal-host --instance NAME`).
fn host_pid(instance: &str) -> Pid {
    let wanted = format!("--instance\0{instance}\0");
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Some(pid) = entry.file_name().to_str().and_then(|s| s.parse().ok()) else {
            continue;
        };
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let cmdline = String::from_utf8_lossy(&cmdline);
        let program = cmdline.split('\0').next().unwrap_or("");
        if program.ends_with("hal-host") && cmdline.contains(&wanted) {
            return Pid::from_raw(pid);
        }
    }
    panic!("no hal-host process for instance {instance}");
}

/// The machine state line of `task-cmd status`.
fn state(m: &Machine) -> String {
    let status = m.task_ok(&["status"]);
    status.lines().next().unwrap_or("").to_string()
}

#[test]
fn a_machine_on_during_a_stalled_host_leaves_task_and_motion_agreeing() {
    let m = Machine::start(&root().join("configs/sim/mill/mill.ini"), "stall");
    assert!(m.threads_run(), "threads run");
    m.task_ok(&["estop-reset"]);
    let before: Vec<String> = (0..3)
        .map(|j| m.getp(&format!("joint.{j}.pos-cmd")))
        .collect();
    let host = host_pid(&m.instance);
    kill(host, Signal::SIGSTOP).unwrap();
    let instance = m.instance.clone();
    let on = std::thread::spawn(move || {
        text(&tool(
            env!("CARGO_BIN_EXE_task-cmd"),
            &["machine-on"],
            &instance,
            None,
        ))
    });
    // Longer than task's wait for motion's answer (2 s), so the enable is
    // still in motion's command ring when task gives up on it.
    std::thread::sleep(Duration::from_millis(2500));
    kill(host, Signal::SIGCONT).unwrap();
    let (ok, out, err) = on.join().unwrap();
    eprintln!("machine-on: ok {ok}: {out}{err}");
    // Let motion take what is in its ring and task see it.
    std::thread::sleep(Duration::from_millis(500));
    let task_state = state(&m);
    let enabled = m.getp("motion.motion-enabled");
    if ok {
        assert!(out.contains("machine on"), "{out}");
        assert_eq!(task_state, "state: ON");
        assert_eq!(enabled, "TRUE");
    } else {
        assert!(err.contains("machine on did not complete"), "{err}");
        assert_eq!(task_state, "state: OFF", "{}", m.stderr());
        assert_eq!(enabled, "FALSE", "{}", m.stderr());
        // Motion is off, so it does not home either.
        let (homed, _, _) = text(&tool(
            env!("CARGO_BIN_EXE_motion-cmd"),
            &["home", "-1"],
            &m.instance,
            None,
        ));
        assert!(!homed, "motion homed while task says OFF");
    }
    let after: Vec<String> = (0..3)
        .map(|j| m.getp(&format!("joint.{j}.pos-cmd")))
        .collect();
    assert_eq!(before, after, "nothing moved");
    // The machine comes on normally afterwards.
    m.task_ok(&["machine-on"]);
    assert_eq!(state(&m), "state: ON");
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE");
    m.stop();
}
