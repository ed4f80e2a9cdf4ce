//! Programs executed by task: the simulated mill runs the shipped
//! CAM-style program (work offset, tool changes with length offsets,
//! spindle, coolant, cutter compensation, a drilling cycle, G28, named
//! parameters) through `task-cmd`, and MDI lines run in MDI mode.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{mill_copy, Machine, Scratch};

/// The machine on and homed, ready for AUTO or MDI.
fn ready(m: &Machine) {
    assert!(m.threads_run(), "threads run");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    // No AUTO before homing.
    let (ok, _, err) = m.task(&["mode", "auto"]);
    assert!(!ok && err.contains("needs the machine homed"), "{err}");
    m.motion(&["home", "-1"]);
    m.motion(&["-t", "60", "wait", "all-homed"]);
    m.motion(&["-t", "30", "wait", "in-position"]);
}

fn pos(m: &Machine, joint: usize) -> f64 {
    m.getp(&format!("joint.{joint}.pos-cmd")).parse().unwrap()
}

#[test]
fn the_mill_runs_a_cam_program_through_task() {
    let s = Scratch::new("task-cam");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-cam");
    ready(&m);
    // MDI: a move, then the modal state shows in the status.
    assert_eq!(m.task_ok(&["mode", "mdi"]).trim(), "mode MDI");
    m.task_ok(&["mdi", "G0", "X2", "Y1"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    assert!(
        (pos(&m, 0) - 2.0).abs() < 1e-6,
        "{}",
        m.task_ok(&["status"])
    );
    assert!((pos(&m, 1) - 1.0).abs() < 1e-6);
    // Programs need AUTO.
    let prog = s.0.join("cam-part.ngc");
    let prog = prog.to_str().unwrap();
    m.task_ok(&["open", prog]);
    let (ok, _, err) = m.task(&["run"]);
    assert!(!ok && err.contains("MDI mode"), "{err}");
    assert_eq!(m.task_ok(&["mode", "auto"]).trim(), "mode AUTO");
    m.task_ok(&["run"]);
    // No MDI and no mode change while it runs.
    let (ok, _, err) = m.task(&["mode", "mdi"]);
    assert!(!ok && err.contains("runs"), "{err}");
    let status = m.task_ok(&["status"]);
    assert!(status.contains("interp: RUNNING"), "{status}");
    let (ok, out, err) = m.task(&["-t", "300", "wait-done"]);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    assert!(out.contains("cam-part.ngc: done"), "{out}");
    // The last hole (G54 X16 Y11 is machine X26 Y16), then G28 Z0.
    let status = m.task_ok(&["status"]);
    for (joint, want) in [(0, 26.0), (1, 16.0), (2, 0.0)] {
        let got = pos(&m, joint);
        assert!(
            (got - want).abs() < 1e-6,
            "joint {joint}: {got}, not {want}\n{status}"
        );
    }
    assert!(status.contains("tool in spindle: 3"), "{status}");
    assert_eq!(m.getp("iocontrol.0.tool-number"), "3");
    assert!(
        status.contains("offsets: g5x 10.0000 5.0000 -45.0000"),
        "{status}"
    );
    // M9 and M5 at the end: coolant and spindle off.
    assert!(status.contains("coolant: mist off, flood off"), "{status}");
    assert!(status.contains("spindle: stopped"), "{status}");
    assert_eq!(m.halcmd(&["gets", "constraints-ok"]).trim(), "TRUE");
    m.stop();
    // The work offset the program set is kept in the parameter file.
    let var = std::fs::read_to_string(s.0.join("sim.var")).unwrap();
    assert!(var.contains("5221\t10.000000"), "{var}");
    assert!(var.contains("5223\t-45.000000"), "{var}");
}

#[test]
fn a_program_error_stops_the_run_and_names_the_line() {
    let s = Scratch::new("task-err");
    let ini = mill_copy(&s);
    let prog = s.write("bad.ngc", "G21 G90\nG0 X1\nT42 M6\nG0 X2\nM2\n");
    let m = Machine::start(&ini, "task-err");
    ready(&m);
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(!ok, "the run failed: {out}\n{}", m.stderr());
    assert!(err.contains("bad.ngc:3"), "{err}");
    let status = m.task_ok(&["status"]);
    assert!(status.contains("interp: IDLE"), "{status}");
    // X2 never ran.
    assert!(pos(&m, 0) < 1.5, "{status}");
    m.stop();
}

#[test]
fn gcode_run_runs_through_task_when_one_runs() {
    let s = Scratch::new("task-gcode-run");
    let ini = mill_copy(&s);
    let prog = s.write(
        "square.ngc",
        "G21 G90 G54\n#<side> = 3\nG1 X#<side> F600\nY#<side>\nX0\nY0\nG0 X1.5 Y2.5\nM2\n",
    );
    let m = Machine::start(&ini, "task-gcode-run");
    ready(&m);
    let out = machine::tool(
        env!("CARGO_BIN_EXE_gcode-run"),
        &["--no-keys", prog.to_str().unwrap()],
        &m.instance,
        None,
    );
    let (ok, stdout, stderr) = machine::text(&out);
    assert!(ok, "{stdout}{stderr}\n--- linuxcnc:\n{}", m.stderr());
    assert!(
        stdout.contains("square.ngc: done (through task)"),
        "{stdout}"
    );
    assert!((pos(&m, 0) - 1.5).abs() < 1e-6);
    assert!((pos(&m, 1) - 2.5).abs() < 1e-6);
    assert!(m.task_ok(&["status"]).contains("mode: AUTO"));
    // Task runs the machine: motion-cmd may not turn it off, nor move it
    // in AUTO mode; reading stays open.
    let motion_cmd = |args: &[&str]| {
        machine::text(&machine::tool(
            env!("CARGO_BIN_EXE_motion-cmd"),
            args,
            &m.instance,
            None,
        ))
    };
    let (ok, out, err) = motion_cmd(&["disable"]);
    assert!(
        !ok && err.contains("task alone turns the machine on and off"),
        "{out}{err}"
    );
    let (ok, out, err) = motion_cmd(&["rapid", "1", "X=5"]);
    assert!(!ok && err.contains("task is in AUTO mode"), "{out}{err}");
    assert!(motion_cmd(&["status"]).0);
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE");
    // --canon prints the canonical calls in the machine's units.
    let out = machine::tool(
        env!("CARGO_BIN_EXE_gcode-run"),
        &[
            "--canon",
            "-I",
            ini.to_str().unwrap(),
            prog.to_str().unwrap(),
        ],
        &m.instance,
        None,
    );
    let (ok, stdout, stderr) = machine::text(&out);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("STRAIGHT_FEED(3.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)"),
        "{stdout}"
    );
    m.stop();
}

/// Polls `task-cmd status` until it holds `needle` (30 s at most).
fn wait_status(m: &Machine, needle: &str) -> String {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(30);
    loop {
        let status = m.task_ok(&["status"]);
        if status.contains(needle) {
            return status;
        }
        assert!(
            std::time::Instant::now() < end,
            "no '{needle}' in\n{status}"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

#[test]
fn pause_resume_m0_and_abort_act_on_the_running_program() {
    let s = Scratch::new("task-pause");
    let ini = mill_copy(&s);
    let prog = s.write("long.ngc", "G21 G90\nG1 X20 F300\nM0\nG1 X0\nG1 X10\nM2\n");
    let m = Machine::start(&ini, "task-pause");
    ready(&m);
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    wait_status(&m, "motion line: 2");
    assert_eq!(m.task_ok(&["pause"]).trim(), "paused");
    wait_status(&m, "interp: PAUSED");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let held = pos(&m, 0);
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert_eq!(pos(&m, 0), held, "X holds while paused");
    assert!(held > 0.0 && held < 20.0, "{held}");
    // Resume: X20, then the M0 holds the run.
    m.task_ok(&["resume"]);
    wait_status(&m, "interp: HELD");
    assert!((pos(&m, 0) - 20.0).abs() < 1e-6);
    m.task_ok(&["resume"]);
    wait_status(&m, "motion line: 4");
    // Abort along the way back: the run ends, the rest never runs.
    m.task_ok(&["abort"]);
    let (ok, _, err) = m.task(&["-t", "30", "wait-done"]);
    assert!(!ok && err.contains("aborted"), "{err}");
    let status = wait_status(&m, "interp: IDLE");
    m.motion(&["-t", "30", "wait", "in-position"]);
    let stopped = pos(&m, 0);
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert_eq!(pos(&m, 0), stopped, "{status}");
    assert!(stopped > 0.0 && stopped < 20.0, "{stopped}");
    m.stop();
}

#[test]
fn run_from_a_line_keeps_the_modes_of_the_lines_it_skips() {
    let s = Scratch::new("task-run-line");
    let ini = mill_copy(&s);
    // Line 3 sets incremental mode, G1 and the feed; line 4's move and
    // line 5's M3 are skipped; line 6 moves Y by 3 from where the skipped
    // lines left the interpreter (X3), straight from where the machine is.
    let prog = s.write(
        "from.ngc",
        "G21 G90\nG0 X1\nG91 G1 F600\nX2\nM3 S1000\nY3\nM0\nM2\n",
    );
    let m = Machine::start(&ini, "task-run-line");
    ready(&m);
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run", "6"]);
    // At the M0: the skipped M3 started nothing.
    let status = wait_status(&m, "HELD");
    assert_eq!(m.getp("spindle.0.on"), "FALSE", "{status}");
    assert!(status.contains("spindle: stopped"), "{status}");
    assert!(status.contains("G91"), "{status}");
    for (joint, want) in [(0, 3.0), (1, 3.0)] {
        let got = pos(&m, joint);
        assert!(
            (got - want).abs() < 1e-6,
            "joint {joint}: {got}, not {want}\n{status}"
        );
    }
    m.task_ok(&["resume"]);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    m.stop();
}

#[test]
fn a_motion_fault_aborts_the_run_names_the_line_and_nothing_moves() {
    let s = Scratch::new("task-fault");
    let ini = mill_copy(&s);
    let prog = s.write("fault.ngc", "G21 G90\nG0 X1\nG1 X40 F300\nG1 X0\nM2\n");
    let m = Machine::start(&ini, "task-fault");
    ready(&m);
    m.task_ok(&["mode", "auto"]);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    wait_status(&m, "motion line: 3");
    // X's positive limit switch trips: motion disables itself; task ends
    // the run at the line that was moving and turns the machine off.
    m.halcmd(&["setp", "joint.0.pos-lim-sw-in", "TRUE"]);
    let (ok, out, err) = m.task(&["-t", "30", "wait-done"]);
    assert!(!ok, "{out}");
    assert!(
        err.contains("fault.ngc:3: joint 0 on limit switch error"),
        "{err}\n--- linuxcnc:\n{}",
        m.stderr()
    );
    let status = wait_status(&m, "state: OFF");
    assert!(status.contains("interp: IDLE"), "{status}");
    assert!(status.contains("mode: MANUAL"), "{status}");
    let stopped = pos(&m, 0);
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert_eq!(pos(&m, 0), stopped, "{status}");
    assert!(stopped > 1.0 && stopped < 40.0, "{stopped}");
    let needle = "disabled itself (last fault: joint 0 on limit switch error)";
    let err = m.stderr_with(needle);
    assert!(err.contains(needle), "{err}");
    // Task printed motion's message once, as it saw it.
    let fault = "task: motion error: joint 0 on limit switch error\n";
    assert_eq!(err.matches(fault).count(), 1, "{err}");
    // A following error during an MDI line: Y's feedback is cut.
    m.halcmd(&["setp", "joint.0.pos-lim-sw-in", "FALSE"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["mode", "mdi"]);
    m.halcmd(&["unlinkp", "joint.1.motor-pos-fb"]);
    m.task_ok(&["mdi", "G1", "Y30", "F300"]);
    let (ok, out, err) = m.task(&["-t", "30", "wait-done"]);
    assert!(!ok, "{out}");
    assert!(
        err.contains("MDI 'G1 Y30 F300': joint 1 following error"),
        "{err}\n--- linuxcnc:\n{}",
        m.stderr()
    );
    let status = wait_status(&m, "state: OFF");
    // The fault says how large the error was, and task's messages name it.
    let needle = "disabled itself (last fault: joint 1 following error (error ";
    let err = m.stderr_with(needle);
    assert!(err.contains(needle), "{err}");
    let fault = "task: motion error: joint 1 following error (error ";
    assert_eq!(err.matches(fault).count(), 1, "{err}");
    let stopped = pos(&m, 1);
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert_eq!(pos(&m, 1), stopped, "{status}");
    assert!(stopped < 30.0, "{stopped}");
    m.stop();
}

/// Polls pin `name` until it is within 1e-3 of `want` (10 s at most).
fn wait_near(m: &Machine, name: &str, want: f64) {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    loop {
        let got: f64 = m.getp(name).parse().unwrap();
        if (got - want).abs() < 1e-3 {
            return;
        }
        assert!(
            std::time::Instant::now() < end,
            "{name} is {got}, not {want}\n{}",
            m.task_ok(&["status"])
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
fn feed_per_revolution_follows_speed_in_and_surface_speed_follows_x() {
    let s = Scratch::new("task-g95");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-g95");
    ready(&m);
    m.task_ok(&["mode", "mdi"]);
    // G95: 0.2 mm per revolution at 10 rev/s is 2 mm/s, at 5 rev/s 1 mm/s.
    m.halcmd(&["setp", "spindle.0.speed-in", "10"]);
    m.task_ok(&["mdi", "G21", "G90", "G95", "M3", "S600"]);
    m.task_ok(&["mdi", "G1", "X30", "F0.2"]);
    wait_near(&m, "motion.current-vel", 2.0);
    m.halcmd(&["setp", "spindle.0.speed-in", "5"]);
    wait_near(&m, "motion.current-vel", 1.0);
    m.task_ok(&["abort"]);
    let _ = m.task(&["-t", "30", "wait-done"]);
    m.task_ok(&["mdi", "G94", "G0", "X10"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    // G96: 30 m/min at a radius of 10 mm is 477.46 rpm; at 2 mm it would
    // be 2387 rpm, over the D limit of 1000.
    m.task_ok(&["mdi", "G96", "D1000", "S30", "M3"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    wait_near(
        &m,
        "spindle.0.speed-out",
        30_000.0 / std::f64::consts::TAU / 10.0,
    );
    m.task_ok(&["mdi", "G0", "X2"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    wait_near(&m, "spindle.0.speed-out", 1000.0);
    m.task_ok(&["mdi", "G97", "S300"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    wait_near(&m, "spindle.0.speed-out", 300.0);
    m.stop();
}

/// The case that lost its cause: a following error while Z homes disables
/// motion, and homing's abort message comes after it in the same cycle.
/// Task prints both, once, the fault first, and its machine-off message
/// names the fault, not the homing message.
#[test]
fn a_following_error_while_homing_is_named_not_the_homing_abort_after_it() {
    let s = Scratch::new("task-home-fault");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-home-fault");
    assert!(m.threads_run(), "threads run");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    // Z (HOME_SEQUENCE 0) homes first; its feedback no longer follows.
    m.halcmd(&["unlinkp", "joint.2.motor-pos-fb"]);
    m.motion(&["home", "-1"]);
    let status = wait_status(&m, "state: OFF");
    let needle = "disabled itself (last fault: joint 2 following error (error ";
    let err = m.stderr_with(needle);
    assert!(err.contains(needle), "{status}\n{err}");
    let fault = "task: motion error: joint 2 following error (error ";
    let abort = "task: motion: homing of joint 2 aborted";
    assert_eq!(err.matches(fault).count(), 1, "{err}");
    assert_eq!(err.matches(abort).count(), 1, "{err}");
    assert!(err.find(fault) < err.find(abort), "{err}");
    // motion-cmd's status keeps the fault beside the last message.
    let st = m.motion(&["status"]);
    assert!(
        st.contains("last fault: joint 2 following error (error "),
        "{st}"
    );
    m.stop();
}

/// Runs `prog` in AUTO to its end; returns whether it succeeded and the
/// error text.
fn run_program(m: &Machine, prog: &std::path::Path) -> (bool, String) {
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    (ok, format!("{out}{err}"))
}

#[test]
fn iov2_gives_a_change_up_on_a_changer_fault_soft_or_hard() {
    let s = Scratch::new("task-iov2");
    let ini = mill_copy(&s);
    let text = std::fs::read_to_string(&ini).unwrap();
    let text = text
        .replace("[EMCIO]\n", "[EMCIO]\nEMCIO = iov2 -support-start-change\n")
        .replace("[TASK]\n", "[TASK]\nIO_ERROR = Toolchanger fault %d\n");
    std::fs::write(&ini, text).unwrap();
    let m = Machine::start(&ini, "task-iov2");
    // The changer of this test acknowledges aborts and change starts at once.
    m.halcmd(&[
        "net",
        "abort",
        "iocontrol.0.emc-abort",
        "iocontrol.0.emc-abort-ack",
    ]);
    m.halcmd(&[
        "net",
        "start",
        "iocontrol.0.start-change",
        "iocontrol.0.start-change-ack",
    ]);
    assert_eq!(m.getp("iocontrol.0.state"), "0");
    ready(&m);
    m.task_ok(&["mode", "auto"]);
    let fault = |reason: &str| {
        m.halcmd(&["setp", "iocontrol.0.toolchanger-reason", reason]);
        m.halcmd(&["setp", "iocontrol.0.toolchanger-fault", "TRUE"]);
        m.wait_getp("iocontrol.0.toolchanger-fault-ack", "TRUE");
        m.halcmd(&["setp", "iocontrol.0.toolchanger-fault", "FALSE"]);
        m.wait_getp("iocontrol.0.toolchanger-fault-ack", "FALSE");
    };
    // A soft fault (reason > 0): the M6 is given up, the program goes on.
    fault("5");
    let prog = s.write("soft.ngc", "G21 G90\nT1 M6\nG0 X1\nM2\n");
    let (ok, out) = run_program(&m, &prog);
    assert!(ok, "{out}\n--- linuxcnc:\n{}", m.stderr());
    assert!((pos(&m, 0) - 1.0).abs() < 1e-6);
    assert_eq!(m.getp("iocontrol.0.tool-number"), "0", "no tool was loaded");
    assert_eq!(m.getp("iocontrol.0.toolchanger-faulted"), "TRUE");
    let needle = "M6: toolchanger soft fault=1, reason=5";
    assert!(m.stderr_with(needle).contains(needle), "{}", m.stderr());
    // The program sees the fault and its reason in #5600 and #5601.
    let branch = s.write(
        "branch.ngc",
        "G21 G90\nO1 if [[#5600 EQ 1] AND [#5601 EQ 5]]\nG0 X4\nO1 else\nG0 X6\nO1 endif\nM2\n",
    );
    let (ok, out) = run_program(&m, &branch);
    assert!(ok, "{out}\n--- linuxcnc:\n{}", m.stderr());
    assert!((pos(&m, 0) - 4.0).abs() < 1e-6, "X {}", pos(&m, 0));
    // Cleared, the same change goes through.
    m.halcmd(&["setp", "iocontrol.0.toolchanger-clear-fault", "TRUE"]);
    m.wait_getp("iocontrol.0.toolchanger-faulted", "FALSE");
    m.halcmd(&["setp", "iocontrol.0.toolchanger-clear-fault", "FALSE"]);
    let (ok, out) = run_program(&m, &prog);
    assert!(ok, "{out}\n--- linuxcnc:\n{}", m.stderr());
    assert_eq!(m.getp("iocontrol.0.tool-number"), "1");
    // A hard fault (reason < 0): the run stops with [TASK]IO_ERROR's text
    // and the move after the M6 never runs.
    fault("-3");
    let prog = s.write("hard.ngc", "G21 G90\nT2 M6\nG0 X2\nM2\n");
    let (ok, out) = run_program(&m, &prog);
    assert!(!ok, "{out}");
    assert!(out.contains("Toolchanger fault -3"), "{out}");
    // M6 went to the mill's [EMCIO]TOOL_CHANGE_POSITION (0 0 0) before
    // the change, as LinuxCNC's does; the X2 after it never ran.
    assert!(pos(&m, 0).abs() < 1e-6, "X {}: X2 ran", pos(&m, 0));
    assert_eq!(m.getp("iocontrol.0.tool-number"), "1");
    assert_eq!(m.getp("iocontrol.0.emc-reason"), "8", "the run's abort");
    m.stop();
}

/// MDI lines queued while a move runs are read as soon as the moves
/// before them are in motion's queue, as LinuxCNC's task reads them, so
/// under G64 the corner between two lines is blended: Y starts moving
/// while X is still short of the corner. (Before, each line waited for
/// the machine to stop, and every corner was an exact stop.)
#[test]
fn queued_mdi_lines_blend_their_corner() {
    let s = Scratch::new("task-mdi-blend");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-mdi-blend");
    ready(&m);
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "G21", "G90", "G64", "P1"]);
    m.task_ok(&["mdi", "G1", "X10", "Y0", "F60"]);
    m.task_ok(&["mdi", "G1", "X10", "Y10", "F60"]);
    // Y moving while X has not reached the corner: the blend arc. Y is
    // read first, X after it (X only grows on this path).
    let mut blended = false;
    let start = std::time::Instant::now();
    while start.elapsed() < std::time::Duration::from_secs(30) {
        let y = pos(&m, 1);
        let x = pos(&m, 0);
        if y > 0.01 && x < 9.99 {
            blended = true;
            break;
        }
        if y > 9.0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(blended, "the corner at X10 Y0 was an exact stop");
    m.task_ok(&["-t", "60", "wait-done"]);
    assert!((pos(&m, 0) - 10.0).abs() < 1e-6 && (pos(&m, 1) - 10.0).abs() < 1e-6);
    // A dwell between two lines: the lines after it still run in order
    // and end where they say.
    m.task_ok(&["mdi", "G1", "X0", "F600"]);
    m.task_ok(&["mdi", "G4", "P0.1"]);
    m.task_ok(&["mdi", "G1", "Y0", "F600"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    assert!(pos(&m, 0).abs() < 1e-6 && pos(&m, 1).abs() < 1e-6);
}

/// `RS274NGC_STARTUP_CODE` runs when task starts and again after
/// `reset-interpreter`, before anything else; a move in it is sent to
/// motion like any other and refused in e-stop, with the error shown.
#[test]
fn startup_code_sets_the_modes_at_start_and_after_an_interpreter_reset() {
    let s = Scratch::new("task-startup-code");
    let ini = mill_copy(&s);
    let text = std::fs::read_to_string(&ini).unwrap().replace(
        "[RS274NGC]\n",
        "[RS274NGC]\nRS274NGC_STARTUP_CODE = G0 G20 G91 G64 P0.02 F12\n",
    );
    std::fs::write(&ini, text).unwrap();
    let m = Machine::start(&ini, "task-startup-code");
    let modal = |m: &Machine| {
        let status = m.task_ok(&["status"]);
        status
            .lines()
            .find(|l| l.starts_with("modal:"))
            .unwrap_or_default()
            .to_string()
    };
    let started = wait_status(&m, "G91");
    assert!(
        started.contains("G20") && started.contains("F12"),
        "{started}"
    );
    ready(&m);
    // `G0` without axis words goes nowhere: nothing is sent to motion,
    // so the start-up code ran without a refusal though in e-stop.
    let status = m.task_ok(&["status"]);
    assert!(!status.contains("last run:"), "{status}");
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "G21", "G90"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    let changed = modal(&m);
    assert!(
        changed.contains("G90") && changed.contains("G21"),
        "{changed}"
    );
    m.task_ok(&["reset-interpreter"]);
    let again = wait_status(&m, "G91");
    assert!(again.contains("G20"), "{again}");
    m.stop();

    // A move in the start-up code while in e-stop: its modes hold, the
    // move is not sent (as LinuxCNC's task), nothing moves, nothing fails.
    let text = std::fs::read_to_string(&ini).unwrap().replace(
        "RS274NGC_STARTUP_CODE = G0 G20 G91 G64 P0.02 F12",
        "RS274NGC_STARTUP_CODE = G20 G91 G0 X5",
    );
    std::fs::write(&ini, text).unwrap();
    let m = Machine::start(&ini, "task-startup-move");
    let started = wait_status(&m, "G91");
    assert!(started.contains("G20"), "{started}");
    assert!(!started.contains("last run:"), "{started}");
    assert_eq!(pos(&m, 0), 0.0);
    m.stop();
}

/// As in LinuxCNC, task changes mode with the machine off or in e-stop:
/// motion keeps the mode and enters it when the machine comes on, where
/// an MDI line then runs.
#[test]
fn the_mode_changes_with_the_machine_off_or_in_estop() {
    let s = Scratch::new("task-mode-off");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-mode-off");
    m.on_and_homed();
    m.task_ok(&["machine-off"]);
    assert_eq!(m.task_ok(&["mode", "mdi"]).trim(), "mode MDI");
    assert_eq!(m.task_ok(&["mode", "manual"]).trim(), "mode MANUAL");
    m.task_ok(&["estop"]);
    assert_eq!(m.task_ok(&["mode", "auto"]).trim(), "mode AUTO");
    assert_eq!(m.task_ok(&["mode", "mdi"]).trim(), "mode MDI");
    let status = m.task_ok(&["status"]);
    assert!(status.contains("mode: MDI"), "{status}");
    // The line itself still needs the machine on.
    let (ok, _, err) = m.task(&["mdi", "G0", "X1"]);
    assert!(!ok, "an MDI line ran in e-stop: {err}");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["mdi", "G0", "X1"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    assert!((pos(&m, 0) - 1.0).abs() < 1e-6, "X {}", pos(&m, 0));
    m.stop();
}
