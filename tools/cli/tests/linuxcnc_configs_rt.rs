//! Configurations of issue 29 that load realtime modules LinuxCNC's
//! configurations load beside their machine: `scope_rt` (halscope's
//! realtime half, the cooltool shape, tests/linuxcnc-configs/scope-rt)
//! with halscope capturing a jog through it, and LinuxCNC's own
//! parport/stepper/sim_inch.ini with `hal_speaker` on the step signals.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::process::{Command, Stdio};
use std::time::Duration;

use machine::{root, Machine, Scratch};

/// Starts the INI file `ini`, turns the machine on.
fn machine_on(ini: &std::path::Path, tag: &str) -> Machine {
    let m = Machine::start(ini, tag);
    assert!(m.threads_run(), "{tag}: threads run\n{}", m.stderr());
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE", "{tag}");
    m
}

#[test]
fn scope_rt_shape_records_a_jog_through_halscope() {
    let ini = root().join("tests/linuxcnc-configs/scope-rt/stepper.ini");
    let m = machine_on(&ini, "cfg-scope-rt");
    let show = m.halcmd(&["show", "thread", "servo-thread"]);
    assert!(show.contains("scope.sample"), "{show}");
    let dir = Scratch::new("cfg-scope-rt-files");
    let csv = dir.0.join("jog.csv");
    // halscope waits for joint 0's command to pass 0.1 going up; the jog
    // comes after it armed.
    let scope = Command::new(env!("CARGO_BIN_EXE_halscope"))
        .args([
            "--pins",
            "joint.0.pos-cmd,motion.motion-enabled",
            "--trigger",
            "joint.0.pos-cmd:rising:0.1",
            "--samples",
            "200",
            "--pre",
            "25%",
            "--timeout",
            "30",
            "--out",
            csv.to_str().unwrap(),
        ])
        .env("HAL_INSTANCE", &m.instance)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(500));
    m.motion(&["jog-incr", "0", "1", "0.5"]);
    let out = scope.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 200, "{text}");
    // The servo thread's period, 1 ms, between samples; the trigger at
    // 50 (25 %), where the command first reached 0.1.
    assert!((rows[51][1] - rows[50][1] - 1.0).abs() < 1e-9, "{text}");
    assert!(rows[50][1].abs() < 1e-9, "{text}");
    assert!(rows[49][2] < 0.1 && rows[50][2] >= 0.1, "{text}");
    // Motion stayed enabled throughout.
    assert!(rows.iter().all(|r| r[3] == 1.0), "{text}");
    m.motion(&["-t", "30", "wait", "in-position"]);
    m.stop();
}

/// Copies the directory `from` into `to`, recursively.
fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
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

/// LinuxCNC's sim_inch.ini, unchanged: sim_pinout.hal loads hal_speaker
/// and nets the step and direction signals to its pins.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_stepper_sim_inch_runs_with_hal_speaker() {
    let src =
        std::path::Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join("by_interface/parport/stepper");
    let s = Scratch::new("cfg-speaker");
    copy_dir(&src, &s.0);
    let m = machine_on(&s.0.join("sim_inch.ini"), "cfg-speaker");
    assert!(m
        .halcmd(&["show", "sig", "Xstep"])
        .contains("==> speaker.0.pin-03-out"));
    let base = m.halcmd(&["show", "thread", "base-thread"]);
    assert!(base.contains("speaker.0.write"), "{base}");
    m.stop();
}
