//! motion-logger in motion's place: LinuxCNC's motion-logger test setup
//! (a HAL file with `loadusr -W motion-logger out.motion-logger` and no
//! motmod) run by our `linuxcnc`; task's start-up configuration and MDI
//! moves are answered and logged one line per command in LinuxCNC's
//! words; `motion-logger.reopen-log` starts a new file.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::time::{Duration, Instant};

use machine::{text, tool, Machine, Scratch};

const INI: &str = "\
[EMC]
VERSION = 1.1
[DISPLAY]
DISPLAY = dummy
[TASK]
TASK = milltask
CYCLE_TIME = 0.001
[RS274NGC]
PARAMETER_FILE = sim.var
[EMCMOT]
COMM_TIMEOUT = 4.0
SERVO_PERIOD = 1000000
[EMCIO]
TOOL_TABLE = simpockets.tbl
[HAL]
HALFILE = mock-motion.hal
[TRAJ]
NO_FORCE_HOMING = 1
COORDINATES = X Y Z
LINEAR_UNITS = inch
ANGULAR_UNITS = degree
MAX_LINEAR_VELOCITY = 4
[KINS]
KINEMATICS = trivkins
JOINTS = 3
[AXIS_X]
MIN_LIMIT = -40.0
MAX_LIMIT = 40.0
MAX_VELOCITY = 4
MAX_ACCELERATION = 1000.0
[JOINT_0]
TYPE = LINEAR
MAX_VELOCITY = 4
MAX_ACCELERATION = 1000.0
MIN_LIMIT = -40.0
MAX_LIMIT = 40.0
[AXIS_Y]
MIN_LIMIT = -40.0
MAX_LIMIT = 40.0
MAX_VELOCITY = 4
MAX_ACCELERATION = 1000.0
[JOINT_1]
TYPE = LINEAR
MAX_VELOCITY = 4
MAX_ACCELERATION = 1000.0
MIN_LIMIT = -40.0
MAX_LIMIT = 40.0
[AXIS_Z]
MIN_LIMIT = -4.0
MAX_LIMIT = 4.0
MAX_VELOCITY = 4
MAX_ACCELERATION = 1000.0
[JOINT_2]
TYPE = LINEAR
MAX_VELOCITY = 4
MAX_ACCELERATION = 1000.0
MIN_LIMIT = -4.0
MAX_LIMIT = 4.0
[SPINDLE_0]
MAX_FORWARD_VELOCITY = 3000
MIN_FORWARD_VELOCITY = 100
MAX_REVERSE_VELOCITY = 2000
";

/// The lines of `path` once it holds one matching `last`.
fn lines_until(path: &std::path::Path, last: &str) -> Vec<String> {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if text.lines().any(|l| l == last) {
            return text.lines().map(str::to_string).collect();
        }
        assert!(
            Instant::now() < end,
            "no '{last}' in {}:\n{text}",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The test machine in `s` with motion-logger in motion's place: its
/// INI file and the log motion-logger writes.
fn logger_machine(s: &Scratch) -> (std::path::PathBuf, std::path::PathBuf) {
    let ini = s.write("test.ini", INI);
    s.write(
        "mock-motion.hal",
        "loadusr -W motion-logger out.motion-logger\nsetp iocontrol.0.emc-enable-in 1\n",
    );
    s.write("simpockets.tbl", "T1 P1 ;tool\n");
    let log = s.0.join("out.motion-logger");
    (ini, log)
}

#[test]
fn task_runs_against_motion_logger_and_every_command_is_logged() {
    let s = Scratch::new("motion-logger");
    let (ini, log) = logger_machine(&s);
    let m = Machine::start(&ini, "motion-logger");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "G0", "X1", "Y2", "Z3"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    // A rapid at the path speed the axes allow (Z's 3 inches at 4 in/s
    // set the time), as LinuxCNC's canon works it out.
    let line = "SET_LINE x=1, y=2, z=3, a=0, b=0, c=0, u=0, v=0, w=0, id=0, motion_type=1, \
                vel=4.98888, ini_maxvel=4.98888, acc=1247.22, turn=-1";
    let lines = lines_until(&log, line);
    // Task's start-up configuration, joint by joint, in LinuxCNC's words.
    for want in [
        "SET_JOINT_POSITION_LIMITS joint=0, min=-40, max=40",
        "SET_JOINT_VEL_LIMIT joint=2, vel=4",
        "JOINT_ACTIVATE joint=2",
        "SET_AXIS_POSITION_LIMITS axis=2, min=-4, max=4",
        "SET_VEL_LIMIT vel=4",
    ] {
        assert!(lines.iter().any(|l| l == want), "no '{want}' in {lines:#?}");
    }
    // Machine on, then the move in coordinated mode.
    let at = |w: &str| lines.iter().position(|l| l == w).unwrap();
    assert!(
        at("ENABLE") < at("COORD") && at("COORD") < at(line),
        "{lines:#?}"
    );
    // reopen-log: the file is closed; the next command starts a new one.
    m.halcmd(&["setp", "motion-logger.reopen-log", "1"]);
    m.wait_getp("motion-logger.reopen-log", "FALSE");
    std::fs::rename(&log, s.0.join("result.first")).unwrap();
    m.task_ok(&["mdi", "G1", "X0.5", "F60"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    // Nothing moved (the logger runs no move), so task's position after
    // the MDI line is where motion says the machine is: the origin.
    let second = "SET_LINE x=0.5, y=0, z=0, a=0, b=0, c=0, u=0, v=0, w=0, id=0, motion_type=2, \
                  vel=1, ini_maxvel=4, acc=1000, turn=-1";
    let lines = lines_until(&log, second);
    assert!(!lines.iter().any(|l| l == line), "{lines:#?}");
    // G43.1 and G49 give motion the tool offset, in machine units.
    m.task_ok(&["mdi", "G43.1", "Z0.25"]);
    m.task_ok(&["mdi", "G49"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    let zero = "SET_OFFSET x=0, y=0, z=0, a=0, b=0, c=0 u=0, v=0, w=0";
    let lines = from_line(&log, second, zero);
    assert_eq!(
        lines[1..],
        [
            "SET_OFFSET x=0, y=0, z=0.25, a=0, b=0, c=0 u=0, v=0, w=0",
            zero
        ],
        "{lines:#?}"
    );
    m.stop();
}

/// Every line of `path` from the first one equal to `from` on.
fn from_line(path: &std::path::Path, from: &str, last: &str) -> Vec<String> {
    let lines = lines_until(path, last);
    let at = lines.iter().position(|l| l == from).unwrap_or_else(|| {
        panic!("no '{from}' in {lines:#?}");
    });
    lines[at..].to_vec()
}

/// What LinuxCNC 2.9's task sends motion at start-up (the joint and
/// spindle counts and planner settings, then each joint, then each axis,
/// then each spindle's speed range; no jerk when the INI sets none), on
/// entering e-stop (abort, disable, volatile homes cleared, free mode),
/// on an abort in e-stop (the moves only), on e-stop reset (abort),
/// machine on (enable) and entering MDI
/// (coordinated mode, abort): the motion-logger log shows it in order.
#[test]
fn task_sends_linuxcnc_startup_and_state_sequences() {
    let s = Scratch::new("motion-logger-seq");
    let (ini, log) = logger_machine(&s);
    let m = Machine::start(&ini, "motion-logger-seq");
    let start = lines_until(&log, "FREE");
    let joint = |j: u32, min: i32, max: i32| {
        [
            format!("SET_JOINT_BACKLASH joint={j}, backlash=0"),
            // The lower limit first, with the upper one task had (0).
            format!("SET_JOINT_POSITION_LIMITS joint={j}, min={min}, max=0"),
            format!("SET_JOINT_POSITION_LIMITS joint={j}, min={min}, max={max}"),
            format!("SET_JOINT_MAX_FERROR joint={j}, maxFerror=1"),
            format!("SET_JOINT_MIN_FERROR joint={j}, minFerror=1"),
            format!(
                "SET_JOINT_HOMING_PARAMS joint={j}, offset=0 home=0, final_vel=-1, search_vel=0, \
                 latch_vel=0, flags=0x00000000, sequence=999, volatile=0"
            ),
            format!("SET_JOINT_VEL_LIMIT joint={j}, vel=4"),
            format!("SET_JOINT_ACC_LIMIT joint={j}, acc=1000"),
            format!("JOINT_ACTIVATE joint={j}"),
        ]
    };
    let axis = |a: u32, min: i32, max: i32| {
        [
            format!("SET_AXIS_POSITION_LIMITS axis={a}, min={min}, max=0"),
            format!("SET_AXIS_POSITION_LIMITS axis={a}, min={min}, max={max}"),
            format!("SET_AXIS_VEL_LIMIT axis={a} vel=4"),
            format!("SET_AXIS_ACC_LIMIT axis={a}, acc=1000"),
            format!("SET_AXIS_LOCKING_JOINT axis={a}, locking_joint=-1"),
        ]
    };
    // Every joint number motion can have, as LinuxCNC's task aborts.
    let abort: Vec<String> = (0..16)
        .map(|j| format!("JOG_ABORT joint={j}"))
        .chain(["ABORT".to_string()])
        .collect();
    let mut want: Vec<String> = [
        "SET_NUM_JOINTS 3",
        "SET_NUM_SPINDLES 1",
        "SET_VEL vel=0, ini_maxvel=1",
        "SET_VEL_LIMIT vel=4",
        "SET_ACC acc=1e+99",
        "SETUP_ARC_BLENDS",
        "SET_MAX_FEED_OVERRIDE 1",
        "SETUP_SET_PROBE_ERR_INHIBIT 0 0",
        "SET_WORLD_HOME x=0, y=0, z=0, a=0, b=0, c=0, u=0, v=0, w=0",
    ]
    .map(String::from)
    .to_vec();
    want.extend(joint(0, -40, 40));
    want.extend(joint(1, -40, 40));
    want.extend(joint(2, -4, 4));
    want.extend(axis(0, -40, 40));
    want.extend(axis(1, -40, 40));
    want.extend(axis(2, -4, 4));
    // [SPINDLE_0]: MIN_REVERSE_VELOCITY defaults to the forward one.
    want.push("SET_SPINDLE_PARAMS, 3.00e+03, 1.00e+02, -2.00e+03, -1.00e+02".into());
    want.extend(abort.iter().cloned());
    // Each joint's DISABLE_AMPLIFIER before DISABLE, as LinuxCNC's task.
    want.push("SPINDLE_OFF".into());
    want.extend(["DISABLE_AMPLIFIER"; 3].map(String::from));
    want.extend(["DISABLE", "JOINT_UNHOME joint=-2", "FREE"].map(String::from));
    assert_eq!(start, want);
    // An abort in e-stop stops the moves only (the spindles are stopped).
    m.task_ok(&["abort"]);
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["mode", "mdi"]);
    // Each request's commands are answered before its reply: all logged.
    let after = from_line(&log, "FREE", "COORD");
    let mut want = vec!["FREE".to_string()];
    want.extend(abort.iter().cloned());
    want.extend(abort.iter().cloned());
    want.extend(["SPINDLE_OFF", "ENABLE"].map(String::from));
    want.extend(["ENABLE_AMPLIFIER"; 3].map(String::from));
    want.push("COORD".into());
    want.extend(abort.iter().cloned());
    assert_eq!(after, want);
    m.stop();
}

/// RS274NGC_STARTUP_CODE runs while the machine is in e-stop: its modal
/// settings hold, but none of its moves reaches motion (LinuxCNC's
/// startup-gcode-abort test shows none), so the machine stays where it is.
#[test]
fn the_startup_code_moves_nothing_while_the_machine_is_off() {
    let s = Scratch::new("motion-logger-startup");
    let (ini, log) = logger_machine(&s);
    let text = std::fs::read_to_string(&ini).unwrap().replace(
        "PARAMETER_FILE = sim.var",
        "PARAMETER_FILE = sim.var\nRS274NGC_STARTUP_CODE = G0 X1",
    );
    std::fs::write(&ini, text).unwrap();
    let m = Machine::start(&ini, "motion-logger-startup");
    lines_until(&log, "FREE");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "G0", "Y1"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    let y = "SET_LINE x=0, y=1, z=0, a=0, b=0, c=0, u=0, v=0, w=0, id=0, motion_type=1, \
             vel=4, ini_maxvel=4, acc=1000, turn=-1";
    let lines = lines_until(&log, y);
    assert_eq!(
        lines.iter().filter(|l| l.starts_with("SET_LINE")).count(),
        1,
        "{lines:#?}"
    );
    m.stop();
}

#[test]
fn motion_logger_refuses_bad_arguments_and_a_missing_instance() {
    let inst = machine::instance("motion-logger-args");
    let bin = env!("CARGO_BIN_EXE_motion-logger");
    let (ok, _, err) = text(&tool(bin, &["a", "b"], &inst, None));
    assert!(!ok && err.contains("at most one LOGFILE"), "{err}");
    let (ok, out, _) = text(&tool(bin, &["--help"], &inst, None));
    assert!(ok && out.contains("reopen-log"), "{out}");
    // No instance: a clear error, no log file made.
    let (ok, _, err) = text(&tool(bin, &["never.log"], &inst, None));
    assert!(!ok && err.contains("motion-logger:"), "{err}");
}

#[test]
fn motion_logger_does_not_start_beside_motmod() {
    let host = hal_host::testing::InProcessHost::start("motion-logger-beside");
    let (ok, _, err) = host.run(
        "motmod.hal",
        "loadrt trivkins\nloadrt motmod servo_period_nsec=1000000 num_joints=1\n",
        false,
    );
    assert!(ok, "{err}");
    let bin = env!("CARGO_BIN_EXE_motion-logger");
    let out = tool(bin, &[], &host.instance, None);
    let (ok, _, err) = text(&out);
    assert!(!ok && err.contains("exists already"), "{err}");
    assert_eq!(out.status.code(), Some(2));
    // Nothing of it stays: no component of its name.
    assert!(host
        .instance()
        .component("motion-logger")
        .unwrap()
        .is_none());
}
