//! halui on the simulated mill (`[HAL]HALUI = halui`): its buttons drive
//! task as a panel's would (e-stop reset, machine on, homing, an
//! `[HALUI]MDI_COMMAND`, a program started, paused, resumed and stopped,
//! coolant, jogging, the feed override), and its status pins follow. A
//! held `selected` jog moves to a newly selected joint, and a held jog
//! follows a changed jog speed, as in LinuxCNC.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{mill_copy, Machine, Scratch};
use std::time::{Duration, Instant};

/// configs/sim/mill, copied, with two MDI commands for halui.
fn mill_with_mdi(s: &Scratch) -> std::path::PathBuf {
    mill_with_commands(s, &["G0 X3 Y2", "G0 X0 Y0"])
}

/// configs/sim/mill, copied, with these `[HALUI]MDI_COMMAND`s.
fn mill_with_commands(s: &Scratch, commands: &[&str]) -> std::path::PathBuf {
    let ini = mill_copy(s);
    let mut text = std::fs::read_to_string(&ini).unwrap();
    text.push_str("\n[HALUI]\n");
    for c in commands {
        text.push_str(&format!("MDI_COMMAND = {c}\n"));
    }
    std::fs::write(&ini, text).unwrap();
    ini
}

/// A button press: the pin TRUE until `until` holds, then FALSE again.
fn press(m: &Machine, pin: &str, until: impl Fn() -> bool) {
    m.halcmd(&["setp", pin, "TRUE"]);
    let end = Instant::now() + Duration::from_secs(30);
    while !until() {
        assert!(
            Instant::now() < end,
            "{pin}: no effect\n--- linuxcnc:\n{}",
            m.stderr()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    m.halcmd(&["setp", pin, "FALSE"]);
}

/// A button held for several of halui's 20 ms cycles, then released.
fn pulse(m: &Machine, pin: &str) {
    m.halcmd(&["setp", pin, "TRUE"]);
    std::thread::sleep(Duration::from_millis(150));
    m.halcmd(&["setp", pin, "FALSE"]);
    std::thread::sleep(Duration::from_millis(150));
}

fn pos(m: &Machine, joint: usize) -> f64 {
    m.getp(&format!("joint.{joint}.pos-cmd")).parse().unwrap()
}

#[test]
fn halui_buttons_run_the_mill() {
    let s = Scratch::new("halui-mill");
    let ini = mill_with_mdi(&s);
    let prog = s.write("slow.ngc", "G21 G90\nG1 X20 F60\nM2\n");
    let m = Machine::start(&ini, "halui-mill");
    assert!(m.threads_run());
    assert_eq!(m.wait_getp("halui.estop.is-activated", "TRUE"), "TRUE");
    let is = |pin: &str| m.getp(pin) == "TRUE";
    press(&m, "halui.estop.reset", || !is("halui.estop.is-activated"));
    press(&m, "halui.machine.on", || is("halui.machine.is-on"));
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE");
    press(&m, "halui.home-all", || {
        (0..3).all(|j| is(&format!("halui.joint.{j}.is-homed")))
    });
    m.motion(&["-t", "30", "wait", "in-position"]);

    // An MDI command from MANUAL: MDI mode, the line, MANUAL again.
    assert!(is("halui.mode.is-manual"));
    press(&m, "halui.mdi-command-00", || is("halui.mode.is-mdi"));
    assert_eq!(
        m.wait_getp("halui.mode.is-manual", "TRUE"),
        "TRUE",
        "{}\n--- linuxcnc:\n{}",
        m.task_ok(&["status"]),
        m.stderr()
    );
    assert!((pos(&m, 0) - 3.0).abs() < 1e-6 && (pos(&m, 1) - 2.0).abs() < 1e-6);
    let x: f64 = m.getp("halui.axis.x.pos-commanded").parse().unwrap();
    assert!((x - 3.0).abs() < 1e-6, "{x}");

    // A program: run (AUTO by itself), pause, resume, stop.
    m.task_ok(&["open", prog.to_str().unwrap()]);
    press(&m, "halui.program.run", || is("halui.program.is-running"));
    assert!(is("halui.mode.is-auto"));
    std::thread::sleep(Duration::from_millis(300));
    press(&m, "halui.program.pause", || is("halui.program.is-paused"));
    std::thread::sleep(Duration::from_millis(300));
    let held = pos(&m, 0);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(pos(&m, 0), held, "paused: X holds");
    assert!(held > 3.0 && held < 20.0, "{held}");
    press(&m, "halui.program.resume", || {
        is("halui.program.is-running")
    });
    std::thread::sleep(Duration::from_millis(200));
    assert!(pos(&m, 0) > held, "resumed: X moves on");
    press(&m, "halui.program.stop", || is("halui.program.is-idle"));
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert!(pos(&m, 0) < 20.0, "stopped before the end");

    // Coolant, the feed override by counts, a jog by an increment.
    press(&m, "halui.flood.on", || is("halui.flood.is-on"));
    assert_eq!(m.getp("iocontrol.0.coolant-flood"), "TRUE");
    press(&m, "halui.flood.off", || !is("halui.flood.is-on"));
    m.halcmd(&["setp", "halui.feed-override.scale", "0.01"]);
    m.halcmd(&["setp", "halui.feed-override.counts", "-50"]);
    assert_eq!(m.wait_getp("halui.feed-override.value", "0.5"), "0.5");
    let before = pos(&m, 2);
    // Homed, MANUAL is teleop: the axis is jogged (speed in units/min).
    m.halcmd(&["setp", "halui.axis.jog-speed", "120"]);
    m.halcmd(&["setp", "halui.axis.z.increment", "1.5"]);
    press(&m, "halui.axis.z.increment-minus", || {
        (pos(&m, 2) - before).abs() > 1e-9
    });
    m.motion(&["-t", "30", "wait", "in-position"]);
    let after = pos(&m, 2);
    assert!((after - (before - 1.5)).abs() < 1e-6, "{before} -> {after}");

    press(&m, "halui.machine.off", || !is("halui.machine.is-on"));
    // postgui.hal put halui.estop.activate on the signal remote-estop.
    m.halcmd(&["sets", "remote-estop", "TRUE"]);
    assert_eq!(m.wait_getp("halui.estop.is-activated", "TRUE"), "TRUE");
    assert_eq!(m.getp("iocontrol.0.user-enable-out"), "FALSE");
    let err = m.stop();
    assert!(!err.contains("halui:"), "halui reported nothing: {err}");
}

/// Waits (up to 30 s) until `until` holds.
fn wait_for(m: &Machine, what: &str, mut until: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(30);
    while !until() {
        assert!(
            Instant::now() < end,
            "{what}: not reached\n--- linuxcnc:\n{}",
            m.stderr()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn float(m: &Machine, pin: &str) -> f64 {
    m.getp(pin).parse().unwrap()
}

#[test]
fn halui_selection_jog_modes_analog_switches_and_tool_pins() {
    let s = Scratch::new("halui-panel");
    let ini = mill_with_mdi(&s);
    let prog = s.write("skip.ngc", "G21 G90\n/G0 X9\nG0 Y4\nM1\nG0 Y6\nM2\n");
    let m = Machine::start(&ini, "halui-panel");
    let is = |pin: &str| m.getp(pin) == "TRUE";
    assert_eq!(m.wait_getp("halui.estop.is-activated", "TRUE"), "TRUE");
    // LinuxCNC's pins, its types and directions.
    let pins = m.halcmd(&["show", "pin", "halui"]);
    for (pin, kind) in [
        ("halui.tool.length_offset.w", "float OUT"),
        ("halui.tool.diameter", "float OUT"),
        ("halui.joint.selected", "u32   OUT"),
        ("halui.axis.selected", "u32   OUT"),
        ("halui.joint.jog-deadband", "float IN"),
        ("halui.axis.z.analog", "float IN"),
        ("halui.axis.x.pos-relative", "float OUT"),
        ("halui.joint.2.on-soft-max-limit", "bit   OUT"),
        ("halui.joint.selected.override-limits", "bit   OUT"),
        ("halui.mode.teleop", "bit   IN"),
        ("halui.program.block-delete.is-on", "bit   OUT"),
    ] {
        let line = pins.lines().find(|l| l.ends_with(pin));
        let line = line.unwrap_or_else(|| panic!("no {pin}:\n{pins}"));
        assert!(line.contains(kind), "{pin}: {line}");
    }
    assert_eq!(m.getp("halui.joint.jog-deadband"), "0.2");
    press(&m, "halui.estop.reset", || !is("halui.estop.is-activated"));
    press(&m, "halui.machine.on", || is("halui.machine.is-on"));

    // Not homed: joint mode. The selected joint jogs by its increment.
    wait_for(&m, "joint mode", || {
        is("halui.mode.is-joint") && !is("halui.mode.is-teleop")
    });
    assert!(is("halui.joint.0.is-selected"));
    press(&m, "halui.joint.1.select", || {
        m.getp("halui.joint.selected") == "1"
    });
    assert!(is("halui.joint.1.is-selected") && !is("halui.joint.0.is-selected"));
    m.halcmd(&["setp", "halui.joint.jog-speed", "600"]);
    m.halcmd(&["setp", "halui.joint.selected.increment", "2"]);
    let before = pos(&m, 1);
    press(&m, "halui.joint.selected.increment-plus", || {
        pos(&m, 1) != before
    });
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert!((pos(&m, 1) - (before + 2.0)).abs() < 1e-6, "{}", pos(&m, 1));

    // A joystick on joint 0: jogs outside the deadband, stops inside.
    let x0 = pos(&m, 0);
    m.halcmd(&["setp", "halui.joint.0.analog", "0.5"]);
    wait_for(&m, "analog jog", || pos(&m, 0) > x0 + 0.5);
    m.halcmd(&["setp", "halui.joint.0.analog", "0.1"]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    let held = pos(&m, 0);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(pos(&m, 0), held, "inside the deadband: stopped");

    // Homed: teleop, joint mode and back; the selected axis jogs.
    press(&m, "halui.home-all", || {
        (0..3).all(|j| is(&format!("halui.joint.{j}.is-homed")))
    });
    m.motion(&["-t", "30", "wait", "in-position"]);
    press(&m, "halui.mode.joint", || is("halui.mode.is-joint"));
    press(&m, "halui.mode.teleop", || is("halui.mode.is-teleop"));
    press(&m, "halui.axis.y.select", || {
        m.getp("halui.axis.selected") == "1"
    });
    assert!(is("halui.axis.y.is-selected") && !is("halui.axis.x.is-selected"));
    assert!(is("halui.joint.selected.is-homed"));
    m.halcmd(&["setp", "halui.axis.jog-speed", "600"]);
    m.halcmd(&["setp", "halui.axis.selected.increment", "1"]);
    let y = pos(&m, 1);
    press(&m, "halui.axis.selected.increment-minus", || {
        pos(&m, 1) != y
    });
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert!((pos(&m, 1) - (y - 1.0)).abs() < 1e-6, "{}", pos(&m, 1));
    // The simulated loop's feedback follows the command within a while.
    wait_for(&m, "pos-feedback", || {
        (float(&m, "halui.axis.y.pos-feedback") - (y - 1.0)).abs() < 1e-4
    });

    // Tool 2 (no changer here: M61) with its length offset, and a G92
    // offset on X.
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "M61 Q2"]);
    m.task_ok(&["wait-done"]);
    m.task_ok(&["mdi", "G43"]);
    m.task_ok(&["wait-done"]);
    m.task_ok(&["mdi", "G92 X1"]);
    m.task_ok(&["wait-done"]);
    // halui reads task's state every cycle: wait for the one after G92.
    wait_for(&m, "relative X", || {
        (float(&m, "halui.axis.x.pos-relative") - 1.0).abs() < 1e-6
    });
    assert_eq!(m.getp("halui.tool.diameter"), "6");
    assert_eq!(m.getp("halui.tool.number"), "2");
    assert_eq!(m.getp("halui.tool.length_offset.z"), "20.5");
    assert_eq!(m.getp("halui.tool.length_offset.x"), "0");

    // Block delete skips the / line; optional stop holds at M1.
    press(&m, "halui.program.block-delete.on", || {
        is("halui.program.block-delete.is-on")
    });
    press(&m, "halui.program.optional-stop.on", || {
        is("halui.program.optional-stop.is-on")
    });
    m.task_ok(&["mdi", "G92.1"]);
    m.task_ok(&["wait-done"]);
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    let x_start = pos(&m, 0);
    press(&m, "halui.program.run", || is("halui.program.is-running"));
    wait_for(&m, "M1 holds", || is("halui.program.is-paused"));
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert!((pos(&m, 1) - 4.0).abs() < 1e-6, "Y {}", pos(&m, 1));
    assert_eq!(pos(&m, 0), x_start, "the / line was skipped");
    press(&m, "halui.program.resume", || is("halui.program.is-idle"));
    assert!((pos(&m, 1) - 6.0).abs() < 1e-6, "Y {}", pos(&m, 1));
    press(&m, "halui.program.optional-stop.off", || {
        !is("halui.program.optional-stop.is-on")
    });
    let err = m.stop();
    assert!(!err.contains("halui:"), "halui reported nothing: {err}");
}

/// A held `halui.joint.selected.minus` goes with the selection: the joint
/// selected before stops and the new one jogs (LinuxCNC's tests/halui/
/// jogging); a held plus/minus jog restarts at a changed jog speed.
#[test]
fn halui_held_jogs_follow_the_selection_and_the_jog_speed() {
    let s = Scratch::new("halui-handover");
    let ini = mill_with_mdi(&s);
    let m = Machine::start(&ini, "halui-handover");
    let is = |pin: &str| m.getp(pin) == "TRUE";
    let vel = |j: usize| float(&m, &format!("joint.{j}.vel-cmd"));
    assert_eq!(m.wait_getp("halui.estop.is-activated", "TRUE"), "TRUE");
    press(&m, "halui.estop.reset", || !is("halui.estop.is-activated"));
    press(&m, "halui.machine.on", || is("halui.machine.is-on"));
    // Units per minute: 60 is one unit a second.
    m.halcmd(&["setp", "halui.joint.jog-speed", "60"]);
    assert!(is("halui.joint.0.is-selected"));
    m.halcmd(&["setp", "halui.joint.selected.minus", "TRUE"]);
    wait_for(&m, "joint 0 jogs", || (vel(0) + 1.0).abs() < 1e-6);
    press(&m, "halui.joint.1.select", || {
        is("halui.joint.1.is-selected")
    });
    wait_for(&m, "joint 1 takes the jog over", || {
        (vel(1) + 1.0).abs() < 1e-6 && vel(0) == 0.0
    });
    assert_eq!(vel(2), 0.0, "joint 2 was not selected");
    m.halcmd(&["setp", "halui.joint.selected.minus", "FALSE"]);
    wait_for(&m, "joint 1 stops", || vel(1) == 0.0);

    m.halcmd(&["setp", "halui.joint.2.plus", "TRUE"]);
    wait_for(&m, "joint 2 jogs at 1/s", || (vel(2) - 1.0).abs() < 1e-6);
    m.halcmd(&["setp", "halui.joint.jog-speed", "120"]);
    wait_for(&m, "joint 2 jogs at 2/s", || (vel(2) - 2.0).abs() < 1e-6);
    m.halcmd(&["setp", "halui.joint.2.plus", "FALSE"]);
    wait_for(&m, "joint 2 stops", || vel(2) == 0.0);
    assert_eq!(vel(0), 0.0, "joint 0 stayed stopped");
    let err = m.stop();
    assert!(!err.contains("halui:"), "halui reported nothing: {err}");
}

/// `halui.halui-mdi-is-running` (LinuxCNC's, made when MDI commands are
/// configured) is TRUE from the press until the line and any queued
/// behind it ran and the mode is back; a line task refuses puts the mode
/// back at once; a mode button for the mode task is in sends nothing.
#[test]
fn halui_mdi_commands_show_running_and_come_back_from_a_refusal() {
    let s = Scratch::new("halui-mdi-run");
    let ini = mill_with_commands(&s, &["G0 X0 Y0", "G1 X4 F120", "G1 X0 F120"]);
    let m = Machine::start(&ini, "halui-mdi-run");
    let is = |pin: &str| m.getp(pin) == "TRUE";
    let pins = m.halcmd(&["show", "pin", "halui.halui-mdi-is-running"]);
    assert!(pins.contains("bit   OUT"), "{pins}");
    m.on_and_homed();
    m.task_ok(&["mode", "manual"]);
    wait_for(&m, "manual", || is("halui.mode.is-manual"));
    assert!(!is("halui.halui-mdi-is-running"));

    // Two seconds out, queued two seconds back: one run, then MANUAL.
    press(&m, "halui.mdi-command-01", || {
        is("halui.halui-mdi-is-running")
    });
    wait_for(&m, "MDI", || is("halui.mode.is-mdi"));
    wait_for(&m, "under way", || pos(&m, 0) > 0.5);
    pulse(&m, "halui.mdi-command-02");
    // Already in MDI: no request (task would refuse a mode change now).
    pulse(&m, "halui.mode.mdi");
    let mut furthest = 0.0f64;
    wait_for(&m, "back in MANUAL", || {
        furthest = furthest.max(pos(&m, 0));
        is("halui.mode.is-manual")
    });
    assert!(
        // The first line ran on (it turns at X4; X is above 3 for half a
        // second, which polling through halcmd sees even on a loaded
        // machine), then the queued one brought X back.
        furthest > 3.0 && pos(&m, 0).abs() < 1e-6,
        "furthest {furthest}, X {}\n{}",
        pos(&m, 0),
        m.stderr()
    );
    assert!(!is("halui.halui-mdi-is-running"));

    // In e-stop task takes MDI mode but refuses the line: back to MANUAL.
    m.task_ok(&["estop"]);
    pulse(&m, "halui.mdi-command-01");
    wait_for(&m, "the refusal", || {
        m.stderr().contains("halui: mdi G1 X4 F120:")
    });
    wait_for(&m, "MANUAL again", || is("halui.mode.is-manual"));
    assert!(!is("halui.halui-mdi-is-running"));
    assert_eq!(m.task_ok(&["status"]).lines().nth(1), Some("mode: MANUAL"));
    let err = m.stop();
    assert!(
        !err.contains("halui: mode"),
        "no mode request refused: {err}"
    );
}

/// As in LinuxCNC: no `[HALUI]MDI_COMMAND`, no `halui-mdi-is-running`;
/// no `[JOINT_n]HOME_SEQUENCE`, no `home-all`.
#[test]
fn halui_has_no_mdi_running_or_home_all_pin_without_their_settings() {
    let s = Scratch::new("halui-no-mdi");
    // The simulated mill has [HAL]HALUI = halui and no [HALUI] section.
    let ini = mill_copy(&s);
    let text = std::fs::read_to_string(&ini).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with("HOME_SEQUENCE"))
        .collect();
    assert!(
        kept.len() < text.lines().count(),
        "the mill has home sequences"
    );
    std::fs::write(&ini, kept.join("\n")).unwrap();
    let m = Machine::start(&ini, "halui-no-mdi");
    assert_eq!(m.wait_getp("halui.estop.is-activated", "TRUE"), "TRUE");
    let pins = m.halcmd(&["show", "pin", "halui"]);
    assert!(pins.contains("halui.machine.on"), "{pins}");
    assert!(!pins.contains("mdi-is-running"), "{pins}");
    assert!(!pins.contains("halui.home-all"), "{pins}");
    m.stop();
}

/// As LinuxCNC's halui: the input pins of all nine axis letters exist on
/// an X-Y-Z machine, so a pendant's HAL file netting `halui.axis.a.plus`
/// loads; the status pins exist only for the machine's own axes; a press
/// on an absent axis moves nothing.
#[test]
fn every_axis_letter_has_input_pins_and_only_real_axes_have_status_pins() {
    let s = Scratch::new("halui-axis-letters");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "halui-axis-letters");
    assert_eq!(m.wait_getp("halui.estop.is-activated", "TRUE"), "TRUE");
    let pins = m.halcmd(&["show", "pin", "halui.axis"]);
    for letter in ["x", "a", "w"] {
        for (name, kind) in [
            ("select", "bit   IN"),
            ("plus", "bit   IN"),
            ("minus", "bit   IN"),
            ("increment-plus", "bit   IN"),
            ("increment-minus", "bit   IN"),
            ("analog", "float IN"),
            ("increment", "float IN"),
        ] {
            let pin = format!("halui.axis.{letter}.{name}");
            let line = pins.lines().find(|l| l.ends_with(&pin));
            let line = line.unwrap_or_else(|| panic!("no {pin}:\n{pins}"));
            assert!(line.contains(kind), "{pin}: {line}");
        }
    }
    assert!(pins.contains("halui.axis.z.pos-commanded"), "{pins}");
    assert!(!pins.contains("halui.axis.a.pos-commanded"), "{pins}");
    assert!(!pins.contains("halui.axis.a.is-selected"), "{pins}");
    m.halcmd(&["net", "pendant-a-plus", "halui.axis.a.plus"]);
    m.on_and_homed();
    let before: Vec<f64> = (0..3).map(|j| pos(&m, j)).collect();
    m.halcmd(&["sets", "pendant-a-plus", "1"]);
    std::thread::sleep(Duration::from_millis(300));
    m.halcmd(&["sets", "pendant-a-plus", "0"]);
    let after: Vec<f64> = (0..3).map(|j| pos(&m, j)).collect();
    assert_eq!(
        before, after,
        "a press on the absent A axis moved the machine"
    );
    m.stop();
}

/// A tripped hard limit overridden: task reports one flag for every
/// joint (`stat`'s `joint.N.override_limits`, halui's
/// `joint.N.override-limits`), as LinuxCNC's does, until a jog ends.
#[test]
fn an_overridden_limit_shows_on_every_joint() {
    let s = Scratch::new("halui-override");
    let ini = mill_with_mdi(&s);
    let m = Machine::start(&ini, "halui-override");
    let is = |pin: &str| m.getp(pin) == "TRUE";
    m.on_and_homed();
    m.task_ok(&["mode", "manual"]);
    m.halcmd(&["setp", "joint.0.pos-lim-sw-in", "TRUE"]);
    wait_for(&m, "the limit", || is("halui.joint.0.on-hard-max-limit"));
    assert!(!is("halui.joint.1.override-limits"));
    m.task_ok(&["override-limits"]);
    wait_for(&m, "the override", || {
        (0..3).all(|j| is(&format!("halui.joint.{j}.override-limits")))
    });
    assert!(is("halui.joint.selected.override-limits"));
    let stat = m.task_ok(&["stat"]);
    for j in 0..3 {
        let line = format!("joint.{j}.override_limits=i:1");
        assert!(stat.lines().any(|l| l == line), "{line}:\n{stat}");
    }
    // The trip turned the machine off; the override stays.
    m.halcmd(&["setp", "joint.0.pos-lim-sw-in", "FALSE"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["teleop", "off"]);
    assert!(is("halui.joint.2.override-limits"));
    m.task_ok(&["jog-incr", "0", "10", "-0.5"]);
    wait_for(&m, "the override ends with the jog", || {
        !is("halui.joint.2.override-limits")
    });
    m.stop();
}

/// The override scales start as LinuxCNC's halui has them (0.1 for feed,
/// rapid and spindle, 0 for max-velocity), so counts and increase act at
/// once; `spindle.N.override.reset` puts the spindle override back to 1.
#[test]
fn override_scales_start_at_a_tenth_and_the_spindle_override_resets() {
    let s = Scratch::new("halui-scales");
    let ini = mill_with_mdi(&s);
    let m = Machine::start(&ini, "halui-scales");
    m.on_and_homed();
    for (pin, want) in [
        ("halui.feed-override.scale", "0.1"),
        ("halui.rapid-override.scale", "0.1"),
        ("halui.spindle.0.override.scale", "0.1"),
        ("halui.max-velocity.scale", "0"),
    ] {
        assert_eq!(m.getp(pin), want, "{pin}");
    }
    m.halcmd(&["setp", "halui.feed-override.counts", "-2"]);
    assert_eq!(m.wait_getp("halui.feed-override.value", "0.8"), "0.8");
    pulse(&m, "halui.spindle.0.override.decrease");
    assert_eq!(m.wait_getp("halui.spindle.0.override.value", "0.9"), "0.9");
    pulse(&m, "halui.spindle.0.override.reset");
    assert_eq!(m.wait_getp("halui.spindle.0.override.value", "1"), "1");
    let err = m.stop();
    assert!(!err.contains("halui:"), "halui reported nothing: {err}");
}
