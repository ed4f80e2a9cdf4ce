//! The spindle on the simulated mill: a program's M3/M4/M5 and S drive
//! motion's `spindle.0.*` pins in program order, the feed move after a
//! start waits for `spindle.0.at-speed`, the override scales the speed,
//! `task-cmd spindle` and halui's `halui.spindle.0.*` pins switch it by
//! hand, and abort, machine-off and e-stop stop it.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{mill_copy, Machine, Scratch};
use std::time::{Duration, Instant};

fn float(m: &Machine, pin: &str) -> f64 {
    m.getp(pin).parse().unwrap()
}

/// Waits (up to 20 s) until `f` holds, else fails with `what`.
fn wait_for(m: &Machine, what: &str, f: impl Fn() -> bool) {
    let end = Instant::now() + Duration::from_secs(20);
    while !f() {
        assert!(
            Instant::now() < end,
            "{what}: not reached\n{}\n--- linuxcnc:\n{}",
            m.task_ok(&["status"]),
            m.stderr()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn spindle_is(m: &Machine, on: bool, forward: bool, reverse: bool, speed: f64) -> bool {
    let b = |pin: &str| m.getp(pin) == "TRUE";
    b("spindle.0.on") == on
        && b("spindle.0.forward") == forward
        && b("spindle.0.reverse") == reverse
        && (float(m, "spindle.0.speed-out") - speed).abs() < 1e-9
}

#[test]
fn a_program_drives_the_spindle_and_waits_for_it_at_speed() {
    let s = Scratch::new("spindle-prog");
    let ini = mill_copy(&s);
    let prog = s.write(
        "spin.ngc",
        "G21 G90\nG0 X1\nM3 S1200\nG1 X5 F600\nM4 S800\nG1 X6\nM5\nG0 X7\nM2\n",
    );
    let m = Machine::start(&ini, "spindle-prog");
    m.on_and_homed();
    m.halcmd(&["setp", "spindle.0.at-speed", "FALSE"]);
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    // The spindle starts once X1 is reached; the feed move waits for it.
    wait_for(&m, "spindle forward at 1200 rpm", || {
        spindle_is(&m, true, true, false, 1200.0)
    });
    assert_eq!(m.getp("spindle.0.brake"), "FALSE");
    assert!((float(&m, "spindle.0.speed-cmd-rps") - 20.0).abs() < 1e-9);
    assert!((float(&m, "spindle.0.speed-out-rps-abs") - 20.0).abs() < 1e-9);
    std::thread::sleep(Duration::from_millis(300));
    let x = float(&m, "joint.0.pos-cmd");
    assert!((x - 1.0).abs() < 1e-9, "X moved before at-speed: {x}");
    // No switching by hand while the program runs.
    let (ok, _, err) = m.task(&["spindle", "off"]);
    assert!(!ok && err.contains("runs"), "{err}");
    // The override scales the output, not the command.
    m.task_ok(&["spindle", "override", "0.5"]);
    wait_for(&m, "the override applied", || {
        (float(&m, "spindle.0.speed-out") - 600.0).abs() < 1e-9
    });
    assert!((float(&m, "spindle.0.speed-cmd-rps") - 20.0).abs() < 1e-9);
    m.task_ok(&["spindle", "override", "1"]);
    m.halcmd(&["setp", "spindle.0.at-speed", "TRUE"]);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    // M5 then the end: stopped, brake on, X7 reached after it.
    assert!(spindle_is(&m, false, false, false, 0.0));
    assert_eq!(m.getp("spindle.0.brake"), "TRUE");
    assert!((float(&m, "joint.0.pos-cmd") - 7.0).abs() < 1e-9);
    let status = m.task_ok(&["status"]);
    assert!(status.contains("spindle: stopped, brake on"), "{status}");
    m.stop();
}

#[test]
fn a_reverse_start_runs_before_the_next_move_and_abort_stops_it() {
    let s = Scratch::new("spindle-rev");
    let ini = mill_copy(&s);
    let prog = s.write("rev.ngc", "G21 G90\nM4 S900\nG1 X30 F60\nM2\n");
    let m = Machine::start(&ini, "spindle-rev");
    m.on_and_homed();
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    wait_for(&m, "spindle reverse at 900 rpm", || {
        spindle_is(&m, true, false, true, -900.0)
    });
    wait_for(&m, "X moving", || float(&m, "joint.0.pos-cmd") > 0.1);
    let status = m.task_ok(&["status"]);
    assert!(
        status.contains("spindle: counterclockwise 900 rpm"),
        "{status}"
    );
    m.task_ok(&["abort"]);
    wait_for(&m, "spindle stopped by abort", || {
        spindle_is(&m, false, false, false, 0.0)
    });
    m.stop();
}

#[test]
fn by_hand_and_from_halui_and_stopped_by_machine_off_and_estop() {
    let s = Scratch::new("spindle-hand");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "spindle-hand");
    assert!(m.threads_run());
    // Machine off: no start.
    let (ok, _, err) = m.task(&["spindle", "forward", "1000"]);
    assert!(!ok && err.contains("ESTOP"), "{err}");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["spindle", "reverse", "700"]);
    wait_for(&m, "reverse 700", || {
        spindle_is(&m, true, false, true, -700.0)
    });
    assert_eq!(m.wait_getp("halui.spindle.0.runs-backward", "TRUE"), "TRUE");
    assert_eq!(m.getp("halui.spindle.0.is-on"), "TRUE");
    // halui's buttons: faster, stop, forward (no S in effect: 500 rpm).
    let press = |pin: &str, until: &dyn Fn() -> bool| {
        m.halcmd(&["setp", pin, "TRUE"]);
        wait_for(&m, pin, until);
        m.halcmd(&["setp", pin, "FALSE"]);
    };
    press("halui.spindle.0.increase", &|| {
        spindle_is(&m, true, false, true, -800.0)
    });
    press("halui.spindle.0.stop", &|| {
        spindle_is(&m, false, false, false, 0.0) && m.getp("spindle.0.brake") == "TRUE"
    });
    assert_eq!(m.wait_getp("halui.spindle.0.brake-is-on", "TRUE"), "TRUE");
    press("halui.spindle.0.brake-off", &|| {
        m.getp("spindle.0.brake") == "FALSE"
    });
    press("halui.spindle.0.forward", &|| {
        spindle_is(&m, true, true, false, 500.0)
    });
    assert_eq!(m.wait_getp("halui.spindle.0.runs-forward", "TRUE"), "TRUE");
    // The override from counts: each count a tenth less.
    m.halcmd(&["setp", "halui.spindle.0.override.scale", "0.1"]);
    m.halcmd(&["setp", "halui.spindle.0.override.counts", "10"]);
    std::thread::sleep(Duration::from_millis(100));
    m.halcmd(&["setp", "halui.spindle.0.override.counts", "7"]);
    wait_for(&m, "override 0.7", || {
        (float(&m, "spindle.0.speed-out") - 350.0).abs() < 1e-6
    });
    wait_for(&m, "halui's override value", || {
        (float(&m, "halui.spindle.0.override.value") - 0.7).abs() < 1e-9
    });
    // Machine off stops it; so does the e-stop.
    m.task_ok(&["machine-off"]);
    wait_for(&m, "stopped by machine-off", || {
        spindle_is(&m, false, false, false, 0.0)
    });
    m.task_ok(&["machine-on"]);
    m.task_ok(&["spindle", "forward", "300"]);
    wait_for(&m, "forward again", || m.getp("spindle.0.on") == "TRUE");
    m.task_ok(&["estop"]);
    wait_for(&m, "stopped by e-stop", || {
        spindle_is(&m, false, false, false, 0.0) && m.getp("spindle.0.brake") == "TRUE"
    });
    m.stop();
}
