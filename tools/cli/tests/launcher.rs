//! `linuxcnc MACHINE.ini` end to end: the sim configurations start, run
//! their threads, take task requests (e-stop reset, machine on, homing and
//! jogging through motion-cmd, tool changes, coolant) and stop cleanly; a
//! configuration that cannot load fails with one clear error.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{root, Machine, Scratch};

#[test]
fn the_mill_homes_jogs_changes_tools_and_stops_cleanly() {
    let m = Machine::start(&root().join("configs/sim/mill/mill.ini"), "mill");
    assert!(m.threads_run(), "threads run");
    // The task pins start at the INI values.
    assert_eq!(m.getp("ini.0.max_velocity"), "5");
    assert_eq!(m.getp("ini.z.max_limit"), "5");
    assert_eq!(m.getp("ini.2.home_sequence"), "0");
    // Starts in e-stop; machine-on is refused until the e-stop is reset.
    assert!(m.task_ok(&["status"]).starts_with("state: ESTOP"));
    let (ok, _, err) = m.task(&["machine-on"]);
    assert!(!ok && err.contains("e-stop"), "{err}");
    assert_eq!(m.getp("iocontrol.0.user-enable-out"), "FALSE");
    assert!(m.task_ok(&["estop-reset"]).contains("machine off"));
    assert_eq!(m.getp("iocontrol.0.emc-enable-in"), "TRUE");
    m.task_ok(&["machine-on"]);
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE");
    // Home on the simulated switches, then jog X in teleop mode.
    m.motion(&["home", "-1"]);
    m.motion(&["-t", "60", "wait", "all-homed"]);
    // The homed flags rise with the final move's command; the stepgen
    // feedback settles a few cycles later, and a mode change waits for it.
    m.motion(&["-t", "30", "wait", "in-position"]);
    m.motion(&["teleop"]);
    m.motion(&["axis-jog-incr", "x", "5", "12.5"]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert_eq!(m.getp("joint.0.pos-fb"), "12.5");
    assert_eq!(m.halcmd(&["gets", "constraints-ok"]).trim(), "TRUE");
    // Tool change through the (looped-back) handshakes.
    assert_eq!(m.task_ok(&["tool-change", "3"]).trim(), "tool 3 in spindle");
    assert_eq!(m.getp("iocontrol.0.tool-number"), "3");
    let (ok, _, err) = m.task(&["tool-change", "42"]);
    assert!(
        !ok && err.contains("tool 42 is not in the tool table"),
        "{err}"
    );
    m.task_ok(&["coolant", "flood", "on"]);
    assert_eq!(m.halcmd(&["gets", "coolant-flood"]).trim(), "TRUE");
    // [HAL]HALUI = halui: halui runs and shows what task does.
    assert_eq!(m.wait_getp("halui.flood.is-on", "TRUE"), "TRUE");
    assert_eq!(m.getp("halui.tool.number"), "3");
    // The e-stop drops everything.
    m.task_ok(&["estop"]);
    assert_eq!(m.getp("iocontrol.0.coolant-flood"), "FALSE");
    assert_eq!(m.getp("motion.motion-enabled"), "FALSE");
    let err = m.stop();
    // What was not started, and the pins that left alone, were said.
    assert!(err.contains("GUI 'axis' ([DISPLAY]DISPLAY)"), "{err}");
    assert!(
        !err.contains("halui ([HAL]HALUI"),
        "halui is started: {err}"
    );
    assert!(
        err.contains("postgui.hal:4: net spindle-rpm => pyvcp.spindle-rpm"),
        "{err}"
    );
    assert!(
        err.contains("spindle.0.speed-out (signal spindle-rpm; pyvcp.spindle-rpm not created)"),
        "{err}"
    );
    assert!(err.contains("stopping: e-stop, motion disabled"), "{err}");
}

#[test]
fn the_lathe_runs_its_tcl_hal_file_and_turret() {
    let m = Machine::start(&root().join("configs/sim/lathe/lathe.ini"), "lathe");
    // lathe.tcl made a switch per joint from [TRAJ]COORDINATES.
    let pins = m.halcmd(&["list", "pin", "home_*.out"]);
    assert_eq!(pins.trim(), "home_x.out home_z.out");
    assert!(m.threads_run());
    // trivkins got its coordinates from the INI value with spaces.
    assert!(m
        .halcmd(&["show", "pin", "joint.1"])
        .contains("joint.1.home-sw-in <== zhome"));
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(m.task_ok(&["tool-change", "2"]).trim(), "tool 2 in spindle");
    assert_eq!(m.getp("iocontrol.0.tool-number"), "2");
    m.stop();
}

#[test]
fn sigint_stops_the_machine_as_sigterm_does() {
    let m = Machine::start(&root().join("configs/sim/lathe/lathe.ini"), "lathe-int");
    let inst = m.instance.clone();
    let (status, err) = m.stop_with(nix::sys::signal::Signal::SIGINT);
    assert!(status.success(), "{err}");
    assert!(hal_core::Instance::attach(&inst).is_err());
}

#[test]
fn a_config_with_a_module_this_suite_lacks_fails_naming_it_file_and_line() {
    let s = Scratch::new("lacking");
    let ini = s.write(
        "m.ini",
        "[EMCMOT]\nEMCMOT = motmod\nBASE_PERIOD = 0\nSERVO_PERIOD = 1000000\n[KINS]\nKINEMATICS = trivkins\nJOINTS = 3\n\
         [TRAJ]\nCOORDINATES = X Y Z\n[HAL]\nHALFILE = core_sim.hal\nHALFILE = board.hal\n",
    );
    s.write(
        "board.hal",
        "# a board driver this suite does not have\nloadrt hal_nosuchboard\n",
    );
    let m = Machine::spawn(&ini, "lacking", &[]);
    let inst = m.instance.clone();
    let (status, err) = m.wait_exit();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("HAL: ERROR: module 'hal_nosuchboard' not found"),
        "{err}"
    );
    assert!(
        err.contains("board.hal:2: insmod for hal_nosuchboard failed"),
        "{err}"
    );
    assert!(
        err.contains("m.ini:12: [HAL] file board.hal failed"),
        "{err}"
    );
    assert!(
        hal_core::Instance::attach(&inst).is_err(),
        "nothing is left running"
    );
}

#[test]
fn a_missing_hal_file_and_a_bad_ini_value_are_named() {
    let s = Scratch::new("badini");
    let ini = s.write(
        "m.ini",
        "[KINS]\nJOINTS = 1\n[HAL]\nHALFILE = nowhere.hal\n",
    );
    let (status, err) = Machine::spawn(&ini, "badini", &[]).wait_exit();
    assert_eq!(status.code(), Some(1));
    assert!(
        err.contains("m.ini:4: [HAL]HALFILE = nowhere.hal: file not found"),
        "{err}"
    );
    let ini = s.write(
        "j.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=x\nJOINTS = 1\n[EMCMOT]\nSERVO_PERIOD = 1000000\n\
         [JOINT_0]\nMAX_VELOCITY = fast\n[HAL]\nHALCMD = loadrt [KINS]KINEMATICS\n\
         HALCMD = loadrt motmod num_joints=1\n",
    );
    let (status, err) = Machine::spawn(&ini, "badvalue", &[]).wait_exit();
    assert_eq!(status.code(), Some(1));
    assert!(
        err.contains("j.ini:7: [JOINT_0]MAX_VELOCITY = \"fast\" is not a number"),
        "{err}"
    );
}

/// A random-changer machine on `table` (bytes of `tools.tbl`), with
/// tool-prepared looped back and tool-changed left to the test.
fn changer(s: &Scratch, table: &[u8]) -> std::path::PathBuf {
    std::fs::write(s.0.join("tools.tbl"), table).unwrap();
    s.write(
        "io.hal",
        "loadrt threads name1=servo-thread period1=1000000\n\
         net estop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in\n\
         net prep iocontrol.0.tool-prepare => iocontrol.0.tool-prepared\n",
    );
    s.write(
        "r.ini",
        "[EMC]\nMACHINE = changer\n[EMCIO]\nTOOL_TABLE = tools.tbl\nRANDOM_TOOLCHANGER = 1\n\
         [HAL]\nHALFILE = io.hal\n",
    )
}

/// Changes to `tool` on a changer machine, completing the handshake;
/// `pocket` is the pocket it must be prepared from.
fn change_tool(m: &Machine, tool: &str, pocket: &str) {
    // tool-changed is not looped back: the change waits for it.
    let (ok, _, err) = m.task(&["-t", "0.5", "tool-change", tool]);
    assert!(!ok && err.contains("no answer within"), "{err}");
    assert_eq!(m.getp("iocontrol.0.tool-prep-pocket"), pocket);
    assert_eq!(m.getp("iocontrol.0.tool-change"), "TRUE");
    m.halcmd(&["setp", "iocontrol.0.tool-changed", "1"]);
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    while m.getp("iocontrol.0.tool-number") != tool {
        assert!(std::time::Instant::now() < end, "the change did not end");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert_eq!(m.getp("iocontrol.0.tool-change"), "FALSE");
    m.halcmd(&["setp", "iocontrol.0.tool-changed", "0"]);
}

#[test]
fn a_random_tool_changer_swaps_pockets_and_saves_its_table() {
    let s = Scratch::new("random");
    let ini = changer(&s, b"T5 P0 ;in the spindle\nT7 P12 ;drill\n");
    let m = Machine::start(&ini, "random");
    assert_eq!(m.getp("iocontrol.0.tool-number"), "5");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    change_tool(&m, "7", "12");
    let table = std::fs::read_to_string(s.0.join("tools.tbl")).unwrap();
    assert_eq!(table, "T7 P0 ;drill\nT5 P12 ;in the spindle\n");
    m.stop();
}

#[test]
fn a_latin1_tool_table_keeps_every_tool_and_comment_byte_for_byte() {
    // The report's line: a Latin-1 comment (0xf8, 'ø'), a comment line
    // in Latin-1, and a word this reader does not know.
    let s = Scratch::new("latin1");
    let ini = changer(
        &s,
        b"T1 P1 D6 Z0.1 ;Bohrer \xf86mm\n; Werkzeuge f\xfcr Alu\nT2 P2 K9 ;\xb5-Fr\xe4ser\n",
    );
    let m = Machine::start(&ini, "latin1");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    change_tool(&m, "2", "2");
    let table = std::fs::read(s.0.join("tools.tbl")).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&table),
        String::from_utf8_lossy(
            b"T2 P0 K9 ;\xb5-Fr\xe4ser\n; Werkzeuge f\xfcr Alu\nT1 P1 D6.000000 Z+0.100000 ;Bohrer \xf86mm\n"
        )
    );
    assert_eq!(
        table,
        b"T2 P0 K9 ;\xb5-Fr\xe4ser\n; Werkzeuge f\xfcr Alu\nT1 P1 D6.000000 Z+0.100000 ;Bohrer \xf86mm\n"
    );
    // Only the table itself in the directory: the write-back went to a
    // new file renamed over the old one.
    let left: Vec<_> = std::fs::read_dir(&s.0)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("tools.tbl"))
        .collect();
    assert_eq!(left, ["tools.tbl"]);
    m.stop();
}

#[test]
fn a_tool_table_with_a_bad_line_starts_without_that_line_and_is_never_written() {
    let s = Scratch::new("badtable");
    let text = b"T5 P0 ;in the spindle\nT7 P12 ;drill\nT8 P3 Zbad\n";
    let ini = changer(&s, text);
    // As LinuxCNC does, the start goes on with the lines that read; the
    // one that does not is named, with its file and line.
    let m = Machine::start(&ini, "badtable");
    let err = m.stderr_with("could not be read");
    assert!(
        err.contains("tools.tbl:3: 'Zbad': Z needs a number: line skipped")
            && err.contains("1 line(s) of"),
        "{err}"
    );
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    change_tool(&m, "7", "12");
    // Tool 8 was left out: asking for it is refused.
    let (ok, _, refused) = m.task(&["-t", "2", "tool-change", "8"]);
    assert!(!ok && refused.contains("tool 8"), "{refused}");
    // The file keeps its bad line: it is never written back.
    assert_eq!(std::fs::read(s.0.join("tools.tbl")).unwrap(), text);
    let stderr = m.stderr_with("is not written back");
    assert!(stderr.contains("is not written back"), "{stderr}");
    m.stop();
}

#[test]
fn a_missing_tool_table_starts_empty() {
    let s = Scratch::new("notable");
    let ini = changer(&s, b"");
    std::fs::remove_file(s.0.join("tools.tbl")).unwrap();
    let m = Machine::start(&ini, "notable");
    let err = m.stderr_with("starting with an empty tool table");
    assert!(
        err.contains("[EMCIO]TOOL_TABLE: tool table")
            && err.contains("starting with an empty tool table"),
        "{err}"
    );
    // A random changer with nothing in pocket 0 reports tool -1, as
    // LinuxCNC 2.9 does (checked on the 2.9 peer with a missing table).
    assert_eq!(m.getp("iocontrol.0.tool-number"), "-1");
    m.stop();
}

#[test]
fn a_table_that_no_longer_reads_is_kept_and_not_written_back() {
    let s = Scratch::new("reloadbad");
    let ini = changer(&s, b"T5 P0 ;in the spindle\nT7 P12 ;drill\n");
    let m = Machine::start(&ini, "reloadbad");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    // The user edits the file and leaves a mistake in it.
    let edited = b"T5 P0 ;in the spindle\nT7 P12 ;drill\nT9 P4 D\n";
    std::fs::write(s.0.join("tools.tbl"), edited).unwrap();
    let (ok, _, err) = m.task(&["reload-tool-table"]);
    assert!(
        !ok && err.contains("tools.tbl:3: 'D': D needs a number"),
        "{err}"
    );
    // A change still works on the table in use, and leaves the file alone.
    change_tool(&m, "7", "12");
    assert_eq!(std::fs::read(s.0.join("tools.tbl")).unwrap(), edited);
    let stderr = m.stderr_with("is not written back");
    assert!(stderr.contains("is not written back"), "{stderr}");
    // Fixed and reloaded: write-backs resume.
    std::fs::write(
        s.0.join("tools.tbl"),
        b"T7 P0 ;drill\nT5 P12 ;in the spindle\n",
    )
    .unwrap();
    m.task_ok(&["reload-tool-table"]);
    change_tool(&m, "5", "12");
    let table = std::fs::read_to_string(s.0.join("tools.tbl")).unwrap();
    assert_eq!(table, "T5 P0 ;in the spindle\nT7 P12 ;drill\n");
    m.stop();
}

/// A machine with the coordinated planner configured from `[TRAJ]`: the
/// S-curve planner (PLANNER_TYPE = 1), a path speed limit below the axes'
/// own, a screw-error table on joint 0 and backlash on joint 1. The
/// joints' commands come back as their feedback; the planner's path
/// speed, acceleration and jerk are watched with minmax.
fn planner_ini(s: &Scratch, comp: &str) -> std::path::PathBuf {
    s.write("x.comp", comp);
    s.write(
        "sim.hal",
        "loadrt [KINS]KINEMATICS\n\
         loadrt [EMCMOT]EMCMOT servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=[KINS]JOINTS\n\
         loadrt ddt names=path_acc,path_jerk\n\
         loadrt minmax names=speed,acc,jerk\n\
         addf motion-command-handler servo-thread\naddf motion-controller servo-thread\n\
         addf path_acc servo-thread\naddf path_jerk servo-thread\n\
         addf speed servo-thread\naddf acc servo-thread\naddf jerk servo-thread\n\
         net j0 joint.0.motor-pos-cmd => joint.0.motor-pos-fb\n\
         net j1 joint.1.motor-pos-cmd => joint.1.motor-pos-fb\n\
         net j2 joint.2.motor-pos-cmd => joint.2.motor-pos-fb\n\
         net estop-loop iocontrol.0.user-enable-out iocontrol.0.emc-enable-in\n\
         net path-vel motion.current-vel => path_acc.in speed.in\n\
         net path-acc path_acc.out => path_jerk.in acc.in\n\
         net path-jerk path_jerk.out => jerk.in\n",
    );
    let axis = "MAX_VELOCITY = 10\nMAX_ACCELERATION = 200\nMIN_LIMIT = -50\nMAX_LIMIT = 50\n";
    let joint = "MAX_VELOCITY = 10\nMAX_ACCELERATION = 200\nMIN_LIMIT = -50\nMAX_LIMIT = 50\n";
    s.write(
        "p.ini",
        &format!(
            "[EMC]\nMACHINE = planner glue\n[EMCMOT]\nEMCMOT = motmod\nBASE_PERIOD = 0\n\
             SERVO_PERIOD = 1000000\n[KINS]\nKINEMATICS = trivkins coordinates=xyz\nJOINTS = 3\n\
             [DISPLAY]\nMAX_FEED_OVERRIDE = 1.5\n\
             [TRAJ]\nCOORDINATES = X Y Z\nMAX_LINEAR_VELOCITY = 4\nMAX_LINEAR_ACCELERATION = 100\n\
             MAX_LINEAR_JERK = 10000\nPLANNER_TYPE = 1\nARC_BLEND_ENABLE = 1\nARC_BLEND_GAP_CYCLES = 4\n\
             [HAL]\nHALFILE = sim.hal\n\
             [AXIS_X]\n{axis}[AXIS_Y]\n{axis}[AXIS_Z]\n{axis}\
             [JOINT_0]\n{joint}BACKLASH = 0.5\nCOMP_FILE = x.comp\nCOMP_FILE_TYPE = 1\n\
             [JOINT_1]\n{joint}BACKLASH = 0.02\n[JOINT_2]\n{joint}"
        ),
    )
}

/// `getp NAME` as a number.
fn real(m: &Machine, pin: &str) -> f64 {
    let v = m.getp(pin);
    v.parse()
        .unwrap_or_else(|_| panic!("{pin} = {v:?} is not a number"))
}

/// Waits (10 s at most) until `holds` is true of the machine.
fn wait_until(m: &Machine, what: &str, holds: impl Fn(&Machine) -> bool) {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    while !holds(m) {
        assert!(
            std::time::Instant::now() < end,
            "{what} did not happen:\n{}",
            m.stderr()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Resets the `minmax` instances `names` (at rest: their max drops to 0
/// once a servo cycle has seen the reset).
fn restart_watch(m: &Machine, names: &[&str]) {
    for n in names {
        m.halcmd(&["setp", &format!("{n}.reset"), "1"]);
        wait_until(m, "the minmax reset", |m| {
            real(m, &format!("{n}.max")) == 0.0
        });
        m.halcmd(&["setp", &format!("{n}.reset"), "0"]);
    }
}

/// Waits until joints 0 and 1 have taken up their whole correction.
fn comp_taken_up(m: &Machine) {
    wait_until(m, "the compensation is taken up", |m| {
        (0..2).all(|j| {
            real(m, &format!("joint.{j}.backlash-filt"))
                == real(m, &format!("joint.{j}.backlash-corr"))
        })
    });
}

#[test]
fn traj_settings_and_a_comp_file_reach_the_planner() {
    let s = Scratch::new("planner");
    // COMP_FILE_TYPE 1: trims moving positive, moving negative.
    let ini = planner_ini(
        &s,
        "# nominal forward reverse\n-10 0.010 -0.010\n0 0.020 -0.030\n10 0.040 -0.050\n",
    );
    let m = Machine::start(&ini, "planner");
    let err = m.stderr_with("p.ini:42: [JOINT_0]BACKLASH");
    assert!(
        err.contains("p.ini:42: [JOINT_0]BACKLASH: not used: the joint has a COMP_FILE"),
        "{err}"
    );
    // The arc blend settings go to motion (SETUP_ARC_BLENDS).
    assert!(!err.contains("ARC_BLEND_ENABLE"), "{err}");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.motion(&["coord"]);
    assert!(
        m.motion(&["status"]).contains(" s-curve"),
        "S-curve planner"
    );
    // Ask for far more than MAX_LINEAR_VELOCITY: X forward, Y back, as
    // an exact stop (a move that may be blended, G64, gets half the
    // acceleration, as in LinuxCNC).
    m.motion(&["term-cond", "stop"]);
    restart_watch(&m, &["speed", "acc", "jerk"]);
    m.motion(&["line", "7", "100", "X=4", "Y=-1"]);
    m.motion(&["-t", "30", "wait", "queue-done"]);
    // The path speed reached [TRAJ]MAX_LINEAR_VELOCITY and no more (the
    // axes alone allow 10), the acceleration MAX_LINEAR_ACCELERATION (the
    // axes allow 200) and the jerk stayed near MAX_LINEAR_JERK (a
    // trapezoidal planner jumps to 100 in a 1 ms period: 1e5).
    let speed = real(&m, "speed.max");
    assert!(
        (3.99..=4.0 + 1e-9).contains(&speed),
        "max path speed {speed}"
    );
    let acc = real(&m, "acc.max");
    assert!((90.0..=102.0).contains(&acc), "max path acceleration {acc}");
    let jerk = real(&m, "jerk.max");
    assert!(jerk <= 15000.0, "max path jerk {jerk}");
    // Joint 0 moved positive to 4: the table's forward trim there,
    // 0.020 + (0.040 - 0.020) * 0.4, not BACKLASH / 2. Joint 1 moved
    // negative: half its BACKLASH the other way.
    comp_taken_up(&m);
    let trim = real(&m, "joint.0.backlash-corr");
    assert!((trim - 0.028).abs() < 1e-6, "joint 0 trim {trim}");
    let motor = real(&m, "joint.0.motor-pos-cmd") - real(&m, "joint.0.pos-cmd");
    assert!(
        (motor - 0.028).abs() < 1e-6,
        "joint 0 motor - joint {motor}"
    );
    assert_eq!(real(&m, "joint.1.backlash-filt"), -0.01);
    assert_eq!(real(&m, "joint.1.pos-cmd"), -1.0);
    // The ini.traj_* pins are followed at run time (task reads them all
    // in one pass, so once the planner type has changed, so has the speed
    // limit).
    m.halcmd(&["setp", "ini.traj_max_velocity", "2"]);
    m.halcmd(&["setp", "ini.traj_planner_type", "0"]);
    wait_until(&m, "the trapezoidal planner", |m| {
        !m.motion(&["status"]).contains(" s-curve")
    });
    restart_watch(&m, &["speed"]);
    m.motion(&["line", "8", "100", "X=0", "Y=0"]);
    m.motion(&["-t", "30", "wait", "queue-done"]);
    let speed = real(&m, "speed.max");
    assert!(
        (1.99..=2.0 + 1e-9).contains(&speed),
        "max path speed {speed}"
    );
    // Back to 0 moving negative: the table's reverse trim at 0; joint 1
    // moved positive.
    comp_taken_up(&m);
    let trim = real(&m, "joint.0.backlash-corr");
    assert!((trim + 0.030).abs() < 1e-6, "joint 0 trim {trim}");
    assert_eq!(real(&m, "joint.1.backlash-filt"), 0.01);
    m.halcmd(&["setp", "ini.traj_max_jerk", "0.5"]);
    m.halcmd(&["setp", "ini.traj_planner_type", "1"]);
    wait_until(&m, "the refusal", |m| {
        m.stderr().contains(
            "task: ini.traj_planner_type: the S-curve planner needs MAX_LINEAR_JERK of at least 1",
        )
    });
    assert!(!m.motion(&["status"]).contains(" s-curve"));
    m.stop();
}

#[test]
fn a_malformed_comp_file_fails_the_launch_naming_file_and_line() {
    let s = Scratch::new("badcomp");
    let ini = planner_ini(&s, "-10 0.01 -0.01\n0 0.02\n10 0.04 -0.05\n");
    let m = Machine::spawn(&ini, "badcomp", &[]);
    let inst = m.instance.clone();
    let (status, err) = m.wait_exit();
    assert_eq!(status.code(), Some(1), "{err}");
    let comp = s.0.join("x.comp");
    let want = format!(
        "p.ini:43: [JOINT_0]COMP_FILE: {}:2: expected three numbers",
        comp.display()
    );
    assert!(err.contains(&want), "{want}\n{err}");
    assert!(
        hal_core::Instance::attach(&inst).is_err(),
        "nothing is left running"
    );
    // Nominals out of order, and a COMP_FILE without its type.
    s.write("x.comp", "0 0 0\n-1 0 0\n");
    let (status, err) = Machine::spawn(&ini, "badcomp2", &[]).wait_exit();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("x.comp:2: nominal -1 does not increase"),
        "{err}"
    );
    let text = std::fs::read_to_string(&ini).unwrap();
    s.write("p.ini", &text.replace("COMP_FILE_TYPE = 1\n", ""));
    let (status, err) = Machine::spawn(&ini, "badcomp3", &[]).wait_exit();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(err.contains("[JOINT_0]COMP_FILE_TYPE"), "{err}");
}

/// A machine whose only HAL file is a Tcl script that never ends, and the
/// tclsh its launcher started for it.
fn looping_machine(s: &Scratch, tag: &str) -> (Machine, i32) {
    s.write("loop.tcl", "while 1 {}\n");
    let ini = s.write(
        "l.ini",
        "[EMC]\nMACHINE = looping\n[HAL]\nHALFILE = loop.tcl\n",
    );
    let m = Machine::spawn(&ini, tag, &[]);
    let end = std::time::Instant::now() + std::time::Duration::from_secs(60);
    let tclsh = loop {
        if let Some(&p) = machine::children_named(m.pid(), "tclsh").first() {
            break p;
        }
        assert!(
            std::time::Instant::now() < end,
            "no tclsh started:\n{}",
            m.stderr()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    (m, tclsh)
}

/// Waits up to 20 s for `pid` to stop running.
fn gone_soon(pid: i32) -> bool {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while machine::running(pid) {
        if std::time::Instant::now() > end {
            return false;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    true
}

#[test]
fn sigterm_during_start_up_ends_the_start_and_what_it_started() {
    let s = Scratch::new("stopstart");
    let (m, tclsh) = looping_machine(&s, "stopstart");
    let inst = m.instance.clone();
    let began = std::time::Instant::now();
    let (status, err) = m.stop_with(nix::sys::signal::Signal::SIGTERM);
    assert!(
        began.elapsed() < std::time::Duration::from_secs(20),
        "took {:?}",
        began.elapsed()
    );
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(err.contains("stop requested during start-up"), "{err}");
    assert!(gone_soon(tclsh), "tclsh {tclsh} still runs");
    assert!(
        hal_core::Instance::attach(&inst).is_err(),
        "the host still runs"
    );
}

#[test]
fn a_launcher_killed_during_start_up_leaves_no_tclsh_behind() {
    let s = Scratch::new("killstart");
    let (m, tclsh) = looping_machine(&s, "killstart");
    let inst = m.instance.clone();
    let _ = m.stop_with(nix::sys::signal::Signal::SIGKILL);
    assert!(gone_soon(tclsh), "tclsh {tclsh} spins on as an orphan");
    // The host goes too (it ends with its parent), so the instance frees.
    let end = std::time::Instant::now() + std::time::Duration::from_secs(30);
    while hal_core::Instance::attach(&inst).is_ok() {
        assert!(std::time::Instant::now() < end, "the host still runs");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}
