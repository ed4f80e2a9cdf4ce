//! Configurations shaped like LinuxCNC's own sim configurations
//! (tests/linuxcnc-configs) run headless through `linuxcnc`: each loads,
//! runs its threads, takes an e-stop reset and machine-on (and, where it
//! has home switches, homes), and stops cleanly.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{root, Machine, Scratch};

fn config(dir: &str, ini: &str) -> std::path::PathBuf {
    root().join("tests/linuxcnc-configs").join(dir).join(ini)
}

/// Starts the machine, checks its threads run, turns it on, runs
/// `more` on it, stops it; returns its stderr.
fn runs(dir: &str, ini: &str, more: impl FnOnce(&Machine)) -> String {
    runs_at(&config(dir, ini), dir, more)
}

/// [`runs`] for the INI file at `ini`, on the instance named after `tag`.
fn runs_at(ini: &std::path::Path, tag: &str, more: impl FnOnce(&Machine)) -> String {
    let dir = tag;
    let m = Machine::start(ini, tag);
    assert!(m.threads_run(), "{dir}: threads run\n{}", m.stderr());
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE", "{dir}");
    more(&m);
    m.stop()
}

fn home_all(m: &Machine) {
    m.motion(&["home", "-1"]);
    m.motion(&["-t", "60", "wait", "all-homed"]);
    // Feedback settles a few cycles after the homed flags rise.
    m.motion(&["-t", "30", "wait", "in-position"]);
}

#[test]
fn axis_mm_shape() {
    let err = runs("axis-mm", "axis_mm.ini", |m| {
        home_all(m);
        assert_eq!(m.getp("joint.2.pos-fb"), "0");
        assert_eq!(m.halcmd(&["gets", "constraints-ok"]).trim(), "TRUE");
        // sim_spindle_encoder.hal: a stopped spindle is at its speed.
        assert_eq!(m.halcmd(&["gets", "spindle-at-speed"]).trim(), "TRUE");
    });
    assert!(err.contains("loadusr -W hal_manualtoolchange"), "{err}");
    assert!(err.contains(
        "iocontrol.0.tool-change (signal tool-change; hal_manualtoolchange.change not created)"
    ));
}

#[test]
fn basic_sim_tcl_shape() {
    let err = runs("basic-sim", "xyz.ini", |m| {
        // basic_sim.tcl's pass-through pid and sample-hold mux per joint.
        assert!(m
            .halcmd(&["show", "sig", "J0:pos-fb"])
            .contains("==> joint.0.motor-pos-fb"));
        // LIB:wheeljogpins.tcl 0.1: wheel jogging on, scale 0.1.
        assert_eq!(m.getp("axis.w.jog-scale"), "0.1");
        assert_eq!(m.getp("joint.2.jog-enable"), "TRUE");
        // [EMCMOT]EMCMOT's unlock_joints_mask reached motmod.
        assert!(m
            .halcmd(&["show", "pin", "joint.2.unlock"])
            .contains("joint.2.unlock"));
        m.motion(&["jog-incr", "0", "1", "0.5"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
        assert_eq!(m.getp("joint.0.pos-fb"), "0.5");
        assert_eq!(m.halcmd(&["gets", "J0:vel"]).trim(), "0");
    });
    assert!(
        err.contains("application 'halshow --fformat %.5f ./xyz.halshow' ([APPLICATIONS]APP)"),
        "{err}"
    );
}

#[test]
fn nine_axis_shape() {
    runs("nine-axis", "axis_9axis.ini", |m| {
        assert_eq!(m.getp("ini.8.max_velocity"), "1.2");
        assert_eq!(m.getp("ini.w.max_limit"), "10");
        m.motion(&["jog-incr", "5", "45", "90"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
        assert_eq!(m.getp("joint.5.pos-fb"), "90");
    });
}

#[test]
fn lathe_xz_shape() {
    runs("lathe-xz", "lathe.ini", |m| {
        home_all(m);
        m.motion(&["teleop"]);
        m.motion(&["axis-jog-incr", "z", "-1", "1.5"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
        assert_eq!(m.getp("joint.1.pos-fb"), "-1.5");
        assert_eq!(m.task_ok(&["tool-change", "2"]).trim(), "tool 2 in spindle");
    });
}

#[test]
fn gantry_xyyz_shape() {
    runs("gantry-xyyz", "gantry.ini", |m| {
        home_all(m);
        assert!(m.motion(&["status"]).contains("all-homed yes"));
    });
}

#[test]
fn includes_shape() {
    runs("includes", "includes_demo.ini", |m| {
        assert_eq!(m.getp("ini.1.home_sequence"), "1");
        home_all(m);
    });
}

#[test]
fn twopass_shape() {
    let err = runs("twopass", "twopass.ini", |m| {
        // One pid component with the three files' instances.
        assert_eq!(
            m.halcmd(&["list", "pin", "pid_*.command"]).trim(),
            "pid_x.command pid_y.command pid_z.command"
        );
        m.motion(&["jog-incr", "2", "1", "0.25"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
        assert_eq!(m.getp("joint.2.pos-fb"), "0.25");
    });
    let passes: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("joint_z.tcl: pass"))
        .collect();
    assert_eq!(
        passes,
        ["joint_z.tcl: pass 0", "joint_z.tcl: pass 1"],
        "{err}"
    );
}

#[test]
fn moveoff_shape() {
    runs("moveoff", "moveoff.ini", |m| {
        // LIB:hookup_moveoff.tcl put mv between motion and the loops.
        let plus = m.halcmd(&["show", "sig", "hu:plus-0"]);
        assert!(
            plus.contains("<== mv.pos-plusoffset-0") && plus.contains("==> J0_pid.command"),
            "{plus}"
        );
        let minus = m.halcmd(&["show", "sig", "hu:minus-0"]);
        assert!(minus.contains("==> joint.0.motor-pos-fb"), "{minus}");
        let thread = m.halcmd(&["show", "thread"]);
        let at = |f: &str| thread.find(f).unwrap_or_else(|| panic!("{f}: {thread}"));
        assert!(at("mv.read-inputs") < at("motion-command-handler"));
        assert!(at("motion-controller") < at("mv.write-outputs"));
        // [MOVEOFF_0], else [JOINT_2]; [MOVEOFF].
        assert_eq!(m.getp("mv.offset-max-0"), "10");
        assert_eq!(m.getp("mv.offset-vel-2"), "5");
        assert_eq!(m.getp("mv.epsilon"), "0.001");
        // An offset on moveoff_external.hal's signals moves the loop;
        // motion's feedback stays where it commands.
        m.halcmd(&["setp", "mv.power-on", "TRUE"]);
        m.halcmd(&["setp", "mv.apply-offsets", "TRUE"]);
        m.halcmd(&["sets", "external_enable", "TRUE"]);
        m.halcmd(&["sets", "external_offset_0", "1.5"]);
        assert_eq!(m.wait_getp("mv.offset-current-0", "1.5"), "1.5");
        assert_eq!(m.wait_getp("J0_mux.out", "1.5"), "1.5");
        assert_eq!(m.wait_getp("joint.0.motor-pos-fb", "0"), "0");
        assert_eq!(m.getp("mv.offset-applied"), "TRUE");
    });
}

#[test]
fn servo_pid_shape() {
    let err = runs("servo-pid", "servo.ini", |m| {
        m.motion(&["jog-incr", "0", "0.5", "0.1"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
        let fb: f64 = m.getp("joint.0.pos-fb").parse().unwrap();
        assert!((fb - 0.1).abs() < 0.01, "the servo loop follows: {fb}");
    });
    assert!(
        err.contains("servo_postgui.hal:2: net Xpos-fb => pyvcp.x-position"),
        "{err}"
    );
}

#[test]
fn vismach_trt_shape() {
    let err = runs("vismach-trt", "trt.ini", |m| {
        // The kinematics of [KINS] and the HALCMD lines that do not name
        // the vismach view.
        assert_eq!(m.getp("xyzac-trt-kins.z-offset"), "10");
        home_all(m);
        m.motion(&["axis-jog-incr", "c", "30", "15"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
        assert_eq!(m.getp("joint.4.pos-fb"), "15");
    });
    assert!(
        err.contains("trt.ini:22: loadusr -W xyzac-trt-gui"),
        "{err}"
    );
    assert!(
        err.contains(
            "xyzac-trt-kins.z-offset (signal :z-offset; xyzac-trt-gui.z-offset not created)"
        ),
        "{err}"
    );
}

#[test]
fn ldelta_shape() {
    let err = runs("ldelta", "ldelta.ini", |m| {
        // sim_ldelta.hal from the library, found on the search path.
        assert_eq!(m.getp("lineardeltakins.L"), "269");
        home_all(m);
        assert_eq!(m.getp("joint.0.pos-fb"), "270");
    });
    assert!(
        err.contains("sim_ldelta.hal:8: loadusr -W lineardelta MIN_JOINT=-420"),
        "{err}"
    );
}

#[test]
fn stepper_limits_shape() {
    runs("stepper-limits", "stepper.ini", |m| {
        // Step generators on the base thread; homing finds the window
        // comparators' switches of simulated_limits.hal.
        assert_eq!(m.getp("stepgen.0.position-scale"), "1000");
        home_all(m);
        // The step generator's feedback trails the command a little.
        let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
        loop {
            let x: f64 = m.getp("joint.0.pos-fb").parse().unwrap();
            if x.abs() < 1e-3 {
                break;
            }
            assert!(std::time::Instant::now() < end, "X at HOME: {x}");
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        assert_eq!(m.halcmd(&["gets", "Xhome"]).trim(), "FALSE");
        assert_eq!(m.halcmd(&["gets", "Zmaxlim"]).trim(), "FALSE");
    });
}

#[test]
fn gantry_panels_shape() {
    let err = runs("gantry-panels", "gantry_panels.ini", |m| {
        // gantrysim.hal came from the library: its loop-back signals.
        assert!(m
            .halcmd(&["show", "sig", "J3pos"])
            .contains("==> joint.3.motor-pos-fb"));
        home_all(m);
        // iocontrol's tool-prep-index and tool-from-pocket are pins, on
        // the POSTGUI file's signals.
        assert_eq!(m.task_ok(&["tool-change", "2"]).trim(), "tool 2 in spindle");
        assert_eq!(m.getp("iocontrol.0.tool-from-pocket"), "7");
        assert_eq!(m.halcmd(&["gets", "gantry:tool-from-pocket"]).trim(), "7");
        m.task_ok(&["tool-prepare", "1"]);
        assert_eq!(m.halcmd(&["gets", "gantry:tool-prep-index"]).trim(), "1");
        let pin = m.halcmd(&["show", "pin", "iocontrol.0.tool-prep-index"]);
        assert!(pin.contains("s32") && pin.contains("OUT"), "{pin}");
    });
    assert!(
        err.contains("[HAL]HALFILE is empty: no file to run"),
        "{err}"
    );
    assert!(err.contains("loadusr -W gantrygui"), "{err}");
    for gui_pin in [
        "gantrypanel.enable-offset",
        "vismach.plotclear",
        "pyvcp.tool-from-pocket",
    ] {
        assert!(err.contains(gui_pin), "{gui_pin}: {err}");
    }
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

/// Starts LinuxCNC's own sample configuration `rel` (a path under the
/// peer's sample-configs) unchanged, from a copy of its directory (what
/// it writes, parameter and position files, stays in the copy), and
/// turns it on; returns the machine and the copy, which must outlive it.
fn peer_machine(rel: &str, tag: &str) -> (Machine, Scratch) {
    let src = std::path::Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join(rel);
    let s = Scratch::new(tag);
    copy_dir(src.parent().unwrap(), &s.0);
    let m = Machine::start(&s.0.join(src.file_name().unwrap()), tag);
    assert!(m.threads_run(), "{rel}: threads run\n{}", m.stderr());
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE", "{rel}");
    (m, s)
}

/// LinuxCNC's 5axiskins bridge mill: seven joints from
/// `coordinates=xyzbcwy` (Y on joints 1 and 6), the kinematics switch on
/// an analog output, and the pivot length from a sum2 of the tool length.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_5axis_bridgemill_runs() {
    let (m, _copy) = peer_machine("sim/axis/vismach/5axis/bridgemill/5axis.ini", "p5axis");
    assert_eq!(m.getp("kinstype.is-0"), "TRUE");
    assert!(m
        .halcmd(&["show", "sig", ":pivot-len"])
        .contains("==> 5axiskins.pivot-length"));
    home_all(&m);
    // Homed, in teleop: a Y jog moves both of Y's joints.
    m.motion(&["axis-jog-incr", "y", "10", "2"]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert_eq!(m.getp("joint.1.pos-fb"), "2");
    assert_eq!(m.getp("joint.6.pos-fb"), "2");
    m.stop();
}

/// LinuxCNC's max5 with maxkins: the pivot length from its INI file's
/// `[MAX]B_PIVOT_LENGTH`, limit3 loops on five joints.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_max5_runs() {
    let (m, _copy) = peer_machine("sim/axis/vismach/5axis/max5/max5kins.ini", "pmax5");
    assert_eq!(m.getp("maxkins.pivot-length"), "0");
    m.motion(&["jog-incr", "4", "10", "5"]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    assert_eq!(m.getp("joint.4.pos-fb"), "5");
    m.stop();
}

/// LinuxCNC's rose engine: rosekins on three joints, homed at once; a
/// spindle turn shows on the module's pins.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_rose_engine_runs() {
    let (m, _copy) = peer_machine("sim/axis/rose_engine/rose_engine.ini", "prose");
    home_all(&m);
    assert_eq!(m.getp("rosekins.revolutions"), "0");
    m.stop();
}

/// LinuxCNC's pentapod: pentakins with the geometry of its
/// kinematics.hal, and the iteration counts on its panel's signals.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_pentapod_runs() {
    let (m, _copy) = peer_machine("sim/axis/pentapod/pentapod.ini", "ppenta");
    assert_eq!(m.getp("pentakins.base.3.z"), "510");
    assert_eq!(m.getp("pentakins.max-error"), "1000");
    // The joints home at once, at the INI file's lengths.
    home_all(&m);
    assert_eq!(m.getp("joint.4.pos-fb"), "806.0397");
    m.stop();
}

/// LinuxCNC's dual rotary table: xyzab_tdr_kins with its offsets set by
/// HALCMD lines, the switch on an analog output.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_xyzab_tdr_runs() {
    let (m, _copy) = peer_machine(
        "sim/axis/vismach/5axis/table-dual-rotary/xyzab-tdr.ini",
        "ptdr",
    );
    assert_eq!(m.getp("xyzab_tdr_kins.x-offset"), "-20");
    assert_eq!(m.getp("kinstype.is-0"), "TRUE");
    m.stop();
}

/// LinuxCNC's mill-turn: millturn's two kinematics, shown on
/// `kinstype.is-0`/`is-1`.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_millturn_runs() {
    let (m, _copy) = peer_machine("sim/axis/vismach/millturn/millturn.ini", "pmillturn");
    assert_eq!(m.getp("kinstype.is-0"), "TRUE");
    assert_eq!(m.getp("kinstype.is-1"), "FALSE");
    m.stop();
}

/// LinuxCNC's axis sim with its trivkins swapped for matrixkins and for
/// userkins (the `[KINS]KINEMATICS` line changed in a copy): matrixkins'
/// calibration matrix, set at run time, moves joint 1 when X moves;
/// userkins, the template unmodified, keeps X on joint 0 alone.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_axis_runs_on_matrixkins_and_userkins() {
    for (kins, tag, joint1) in [("matrixkins", "pmatrixk", "1"), ("userkins", "puserk", "0")] {
        let src = std::path::Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join("sim/axis/axis.ini");
        let s = Scratch::new(tag);
        // Its own files only: the directory's subdirectories are other
        // configurations (one holds dangling links).
        std::fs::create_dir_all(&s.0).unwrap();
        for entry in std::fs::read_dir(src.parent().unwrap()).unwrap().flatten() {
            if entry.file_type().unwrap().is_file() {
                std::fs::copy(entry.path(), s.0.join(entry.file_name())).unwrap();
            }
        }
        let ini = s.0.join("axis.ini");
        let text = std::fs::read_to_string(&ini).unwrap();
        let line = "KINEMATICS = trivkins\n";
        assert!(text.contains(line), "axis.ini's [KINS] changed");
        std::fs::write(&ini, text.replace(line, &format!("KINEMATICS = {kins}\n"))).unwrap();
        runs_at(&ini, tag, |m| {
            if kins == "matrixkins" {
                m.halcmd(&["setp", "matrixkins.C_yx", "0.5"]);
            }
            home_all(m);
            m.motion(&["teleop"]);
            m.motion(&["axis-jog-incr", "x", "10", "2"]);
            m.motion(&["-t", "30", "wait", "in-position"]);
            assert_eq!(m.getp("joint.0.pos-fb"), "2", "{kins}");
            assert_eq!(m.getp("joint.1.pos-fb"), joint1, "{kins}");
        });
    }
}

/// LinuxCNC's Scorbot ER-3 arm on scorbot-kins, without its hardware:
/// the copy's HAL files leave out `loadusr -W scorbot-er-3` (the arm's
/// driver program) and the nets to its pins, so the joints' commands
/// loop back as feedback. The unchanged configuration stops at that
/// `loadusr`, as it would on a machine without the arm.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_scorbot_runs_on_scorbot_kins_without_its_arm() {
    let rel = "by_machine/scorbot-er-3/scorbot-er-3.ini";
    let src = std::path::Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join(rel);
    let s = Scratch::new("pscorbot");
    copy_dir(src.parent().unwrap(), &s.0);
    for name in ["scorbot-er-3.hal", "pyvcp.hal"] {
        let hal = s.0.join(name);
        let text = std::fs::read_to_string(&hal).unwrap();
        let kept: String = text
            .lines()
            .filter(|l| !l.contains("loadusr") && !l.contains("scorbot-er-3."))
            .map(|l| format!("{l}\n"))
            .collect();
        assert!(kept.len() < text.len(), "{name} changed");
        std::fs::write(&hal, kept).unwrap();
    }
    runs_at(&s.0.join("scorbot-er-3.ini"), "pscorbot", |m| {
        assert!(m.halcmd(&["show", "comp"]).contains("scorbot-kins"));
        // The wrist's differential turns the pitch and roll commands into
        // the two motors' and back.
        assert_eq!(m.getp("joint.3.motor-pos-fb"), "0");
    });
}

/// LinuxCNC's rolfmill, written before joints and axes were apart
/// (`[EMC]VERSION = $Revision$`, `[AXIS_n]` sections, `[TRAJ]AXES`,
/// `axis.N.*` pins): run converted in memory, as LinuxCNC's update_ini
/// converts it, with halui reading the same conversion; its 3-D view
/// (a vismach script) is a GUI, not started. Its files stay as they were.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_rolfmill_in_the_old_format_runs_converted() {
    let rel = "sim/axis/vismach/rolfmill/rolfmill.ini";
    let (m, copy) = peer_machine(rel, "prolf");
    assert!(m
        .halcmd(&["show", "sig", "Xpos"])
        .contains("==> joint.0.motor-pos-fb"));
    // [KINS]JOINTS = 3 from COORDINATES = X Y Z.
    assert_eq!(m.getp("joint.2.motor-pos-fb"), "0");
    assert!(m
        .halcmd(&["show", "pin", "halui.machine.is-on"])
        .contains("halui.machine.is-on"));
    let err = m.stop();
    assert!(
        err.contains("[KINS]KINEMATICS = trivkins coordinates=XYZ, [KINS]JOINTS = 3"),
        "{err}"
    );
    assert!(err.contains("converted in memory"), "{err}");
    assert!(err.contains("loadusr -W ./rolfmill"), "{err}");
    let src = std::path::Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join(rel);
    for name in ["rolfmill.ini", "rolfmill.hal"] {
        assert_eq!(
            std::fs::read(src.with_file_name(name)).unwrap(),
            std::fs::read(copy.0.join(name)).unwrap(),
            "{name} was rewritten"
        );
    }
}

/// Fails with what to build when the pendant driver (package hal-usb,
/// not a binary of this package) is not beside `linuxcnc`.
fn need_xhc_hb04() {
    let exe = std::path::Path::new(env!("CARGO_BIN_EXE_linuxcnc")).with_file_name("xhc-hb04");
    assert!(
        exe.exists(),
        "{} is missing: run `cargo build -p hal-usb` first",
        exe.display()
    );
}

/// LinuxCNC's XHC HB04 pendant demo (require_pendant = no): with no
/// pendant the driver's pins exist, `connected` is false, and the wheel,
/// buttons and start/pause are wired through pendant_util to the axes,
/// joints and halui.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_xhc_hb04_starts_without_the_pendant() {
    need_xhc_hb04();
    let (m, _copy) = peer_machine("sim/axis/xhc-hb04/xhc-hb04-layout2.ini", "pxhc");
    assert_eq!(m.getp("xhc-hb04.connected"), "FALSE");
    assert_eq!(m.getp("xhc-hb04.require_pendant"), "FALSE");
    assert_eq!(m.getp("xhc-hb04.button-zero-x"), "FALSE");
    let wheel = m.halcmd(&["show", "sig", "pendant:wheel-counts"]);
    assert!(wheel.contains("<== xhc-hb04.jog.counts"), "{wheel}");
    assert!(wheel.contains("==> pendant_util.in0"), "{wheel}");
    assert!(wheel.contains("==> halui.feed-override.counts"), "{wheel}");
    let x = m.halcmd(&["show", "sig", "pendant:wheel-counts-x-filtered"]);
    assert!(x.contains("==> joint.0.jog-counts"), "{x}");
    let run = m.halcmd(&["show", "sig", "pendant:program-run"]);
    assert!(run.contains("<== pendant_util.run"), "{run}");
    assert_eq!(m.getp("pendant_util.k"), "100");
    m.stop();
}

/// LinuxCNC's xyzx demo with the pendant: X on joints 0 and 3, so the
/// Tcl wires axis x only and the POSTGUI file puts joint 3 on
/// pendant_util's fourth filter.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_xyzx_xhc_hb04_postgui_drives_joint_3() {
    need_xhc_hb04();
    let (m, _copy) = peer_machine("sim/axis/ja_tests/xyzx_mpg/xyzx-xhc-hb04.ini", "pxyzx");
    let j3 = m.halcmd(&["show", "sig", "optionalj3:filtered"]);
    assert!(j3.contains("<== pendant_util.out3"), "{j3}");
    assert!(j3.contains("==> joint.3.jog-counts"), "{j3}");
    assert_eq!(m.getp("pendant_util.scale3"), "100");
    assert_eq!(m.getp("xhc-hb04.inch-icon"), "TRUE");
    let err = m.stop();
    assert!(err.contains("coordinate x has no single joint"), "{err}");
}

/// Waits (up to 10 s) until the float pin `name` reads `want` to within
/// 1e-6; returns the last value read.
fn wait_float(m: &Machine, name: &str, want: f64) -> f64 {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    loop {
        let v: f64 = m.getp(name).parse().unwrap_or(f64::NAN);
        if (v - want).abs() < 1e-6 || std::time::Instant::now() > end {
            return v;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// LinuxCNC's external offsets demo (Z: OFFSET_AV_RATIO 0.2, limits
/// -1..1, eoffset-scale 0.1 from its HAL file): counts on its `e:zcounts`
/// signal offset Z's joint; past MAX_LIMIT the offset stops at the limit
/// and motion.eoffset-limited says so; counted back, Z returns.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_eoffsets_offset_z_within_its_limits() {
    let (m, _copy) = peer_machine("sim/axis/external_offsets/eoffsets.ini", "peoff");
    home_all(&m);
    let z0: f64 = m.getp("joint.2.pos-cmd").parse().unwrap();
    // The enable is the PyVCP panel's button, which does not run here:
    // its signal stays, without a writer.
    m.halcmd(&["sets", "E:z-enable", "TRUE"]);
    m.halcmd(&["sets", "e:zcounts", "3"]);
    let z = wait_float(&m, "joint.2.pos-cmd", z0 + 0.3);
    assert!((z - (z0 + 0.3)).abs() < 1e-6, "{z} from {z0}");
    assert_eq!(m.getp("motion.eoffset-active"), "TRUE");
    assert_eq!(m.getp("motion.eoffset-limited"), "FALSE");
    let status = m.task_ok(&["status"]);
    assert!(
        status.contains("external offsets: Z 0.300000 (request 0.300000) active"),
        "{status}"
    );
    // Far past MAX_LIMIT = 1: held on it.
    m.halcmd(&["sets", "e:zcounts", "100"]);
    assert_eq!(m.wait_getp("motion.eoffset-limited", "TRUE"), "TRUE");
    let z = wait_float(&m, "joint.2.pos-cmd", 1.0);
    assert!((z - 1.0).abs() < 1e-9, "{z}");
    m.halcmd(&["sets", "e:zcounts", "0"]);
    let z = wait_float(&m, "joint.2.pos-cmd", z0);
    assert!((z - z0).abs() < 1e-6, "{z} back to {z0}");
    assert_eq!(m.wait_getp("motion.eoffset-limited", "FALSE"), "FALSE");
    m.stop();
}

/// qtdragon_hd's z_level_compensation: the probe map of the
/// configuration directory gives the Z offset at the commanded X/Y as
/// counts of 0.001 for motion's external offset, which motion applies to Z
/// (OFFSET_AV_RATIO 0.2); off again, counts are 0 and so is the offset.
#[test]
fn zlevel_shape() {
    // A private copy: the run writes the interpreter's parameter file (the
    // G10 below) beside the INI file.
    let s = Scratch::new("zlevel");
    for entry in std::fs::read_dir(root().join("tests/linuxcnc-configs/zlevel")).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), s.0.join(entry.file_name())).unwrap();
    }
    let err = runs_at(&s.0.join("zlevel.ini"), "zlevel", |m| {
        home_all(m);
        assert_eq!(m.getp("z_level_compensation.counts"), "0");
        // What qtdragon_hd's GUI file sets: the offset's enable and scale.
        m.halcmd(&["setp", "axis.z.eoffset-enable", "TRUE"]);
        m.halcmd(&["setp", "axis.z.eoffset-scale", "0.001"]);
        m.halcmd(&["sets", "z_compensation_on", "TRUE"]);
        // At X0 Y0 the plane is 0.0504: 50 counts.
        assert_eq!(m.wait_getp("z_level_compensation.counts", "50"), "50");
        assert_eq!(m.getp("z_level_compensation.scale"), "0.001");
        assert_eq!(m.getp("axis.z.eoffset-counts"), "50");
        // Motion applies it: Z's joint moves, axis.z.pos-cmd does not.
        assert!((wait_float(m, "axis.z.eoffset", 0.05) - 0.05).abs() < 1e-6);
        let z = wait_float(m, "joint.2.pos-cmd", 0.05);
        assert!((z - 0.05).abs() < 1e-6, "{z}");
        assert_eq!(m.getp("axis.z.pos-cmd"), "0");
        assert_eq!(m.getp("motion.eoffset-active"), "TRUE");
        m.task_ok(&["mode", "mdi"]);
        // A G54 offset of X5: X10 is machine X15, and the map is looked
        // up at X10 (less the G5x offset, as LinuxCNC's component does).
        m.task_ok(&["mdi", "G10 L2 P1 X5 Y0"]);
        m.task_ok(&["mdi", "G0 X10 Y20"]);
        assert_eq!(m.wait_getp("axis.x.pos-cmd", "15"), "15");
        // 0.0504 + 0.01 + 0.04 = 0.1004: 100 counts (105 at X15).
        assert_eq!(m.wait_getp("z_level_compensation.counts", "100"), "100");
        let z = wait_float(m, "joint.2.pos-cmd", 0.1);
        assert!((z - 0.1).abs() < 1e-6, "{z}");
        m.halcmd(&["sets", "z_compensation_on", "FALSE"]);
        assert_eq!(m.wait_getp("z_level_compensation.counts", "0"), "0");
        let z = wait_float(m, "joint.2.pos-cmd", 0.0);
        assert!(z.abs() < 1e-6, "{z}");
        assert_eq!(m.wait_getp("motion.eoffset-active", "FALSE"), "FALSE");
    });
    // External offsets are applied: no note about them.
    assert!(!err.contains("OFFSET_AV_RATIO"), "{err}");
}

/// An OFFSET_AV_RATIO outside 0..0.9 is replaced by 0.1, as LinuxCNC
/// does, with a note naming the line: Z's jogs then get 0.9 of its
/// MAX_VELOCITY of 5.
#[test]
fn an_offset_ratio_out_of_range_falls_back_to_0_1_with_a_note() {
    let s = Scratch::new("zlratio");
    for entry in std::fs::read_dir(root().join("tests/linuxcnc-configs/zlevel")).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), s.0.join(entry.file_name())).unwrap();
    }
    let ini = s.0.join("zlevel.ini");
    let text = std::fs::read_to_string(&ini).unwrap();
    assert!(text.contains("OFFSET_AV_RATIO = 0.2"));
    std::fs::write(
        &ini,
        text.replace("OFFSET_AV_RATIO = 0.2", "OFFSET_AV_RATIO = 1.5"),
    )
    .unwrap();
    let err = runs_at(&ini, "zlratio", |m| {
        home_all(m);
        m.motion(&["axis-jog-cont", "z", "100"]);
        assert_eq!(m.getp("axis.z.teleop-vel-lim"), "4.5");
        m.motion(&["axis-jog-abort", "z"]);
    });
    assert!(
        err.contains(
            "[AXIS_Z]OFFSET_AV_RATIO: 1.5 is outside 0 to 0.9: 0.1 is used instead, as LinuxCNC does"
        ),
        "{err}"
    );
}

/// `[TRAJ]POSITION_FILE` (the axis-mm shape with it added): at exit the
/// joints' positions are written, 16 lines of 17 decimals as LinuxCNC
/// writes them; at the next start each joint reads its saved position
/// before anything moves. A file that does not hold 16 numbers is not
/// used, with a note naming the joint that failed.
#[test]
fn position_file_keeps_the_joints_between_runs() {
    let s = Scratch::new("posfile");
    let src = root().join("tests/linuxcnc-configs/axis-mm");
    for entry in std::fs::read_dir(&src).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), s.0.join(entry.file_name())).unwrap();
    }
    let ini = s.0.join("axis_mm.ini");
    let text = std::fs::read_to_string(&ini)
        .unwrap()
        .replace("[TRAJ]\n", "[TRAJ]\nPOSITION_FILE = position.txt\n");
    std::fs::write(&ini, text).unwrap();
    let saved = s.0.join("position.txt");

    runs_at(&ini, "posfile-1", |m| {
        assert_eq!(
            m.getp("joint.0.pos-fb"),
            "0",
            "no file yet: nothing restored"
        );
        m.motion(&["jog-incr", "0", "10", "2.5"]);
        m.motion(&["-t", "30", "wait", "in-position"]);
    });
    let text = std::fs::read_to_string(&saved).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 16, "{text}");
    // 17 decimals, as LinuxCNC's %.17f: "2.49999999996020517".
    assert_eq!(lines[0].split_once('.').map(|(_, f)| f.len()), Some(17));
    let saved0: f64 = lines[0].parse().unwrap();
    assert!((saved0 - 2.5).abs() < 1e-6, "{text}");
    assert!(
        lines[1..].iter().all(|l| *l == "0.00000000000000000"),
        "{text}"
    );

    let m = Machine::start(&ini, "posfile-2");
    assert!(m.threads_run(), "{}", m.stderr());
    let fb: f64 = m.getp("joint.0.pos-fb").parse().unwrap();
    // halcmd shows floats to a few digits; the restored value is the saved one.
    assert!(
        (fb - saved0).abs() < 1e-6,
        "restored before machine-on: {fb}"
    );
    let offset: f64 = m.getp("joint.0.motor-offset").parse().unwrap();
    assert!((offset + saved0).abs() < 1e-6, "motor offset {offset}");
    assert_eq!(m.getp("joint.1.pos-fb"), "0");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    let cmd: f64 = m.getp("joint.0.pos-cmd").parse().unwrap();
    assert!(
        (cmd - saved0).abs() < 1e-6,
        "nothing moved at machine-on: {cmd}"
    );
    m.stop();

    std::fs::write(&saved, "1 2 3\n").unwrap();
    let err = runs_at(&ini, "posfile-3", |m| {
        assert_eq!(m.getp("joint.0.pos-fb"), "0");
    });
    assert!(
        err.contains("position.txt: joint 3: the file ends before joint 3's position (positions not restored)"),
        "{err}"
    );
}

/// LinuxCNC's locking indexer sample (B on joint 3; a timedelay stands
/// in for the clamp: 0.75 s to unlock, 0.5 s to lock): G0 B90 raises
/// joint.3.unlock with motion-type 6, B's joint waits for is-unlocked,
/// moves, and the unlock drops at the end; a feed move of B is refused
/// with motion's message.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_locking_indexer_unlocks_around_a_rapid() {
    let (m, _copy) = peer_machine("sim/axis/ja_tests/xyzb_locking_indexer/xyzb.ini", "pindex");
    home_all(&m);
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "G0 B90"]);
    assert_eq!(m.wait_getp("joint.3.unlock", "TRUE"), "TRUE");
    assert_eq!(m.getp("motion.motion-type"), "6");
    // Still clamped (the on-delay is 0.75 s): B has not moved.
    assert_eq!(m.getp("joint.3.is-unlocked"), "FALSE");
    assert_eq!(m.getp("joint.3.pos-cmd"), "0");
    let b = wait_float(&m, "joint.3.pos-cmd", 90.0);
    assert!((b - 90.0).abs() < 1e-9, "{b}");
    m.task_ok(&["wait-done"]);
    assert_eq!(m.getp("joint.3.unlock"), "FALSE");
    assert_eq!(m.getp("joint.3.is-unlocked"), "FALSE");
    assert_eq!(m.getp("motion.motion-type"), "0");
    let (_, out, err) = m.task(&["mdi", "G1 B100 F100"]);
    let _ = m.task(&["wait-done"]);
    let all = format!("{out}{err}{}", m.stderr());
    assert!(
        all.contains("axis B is a locking indexer: only a rapid move (G0) may move it"),
        "{all}"
    );
    assert!((wait_float(&m, "joint.3.pos-cmd", 90.0) - 90.0).abs() < 1e-9);
    m.stop();
}
