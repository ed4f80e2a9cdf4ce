//! `loadrt trivkins` + `loadrt motmod` in a private HAL host: the exact
//! pin and param names and types of LinuxCNC's motion(9) man page, the
//! threads motmod creates, module-parameter errors, and a run with the
//! functions in the servo thread driven through `MotionHandle`.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::collections::BTreeMap;
use std::time::Duration;

mod common;

use common::*;
use hal_core::{HalError, HalType, Host, ParamDir, PinDir, Value};
use motion::{Command, Event, MotionHandle, Reject};

/// (name, type, dir) where dir is "IN", "OUT", "I/O" for pins and "RO",
/// "RW" for params.
type Item = (String, HalType, &'static str);

fn pins_of(h: &Host, owner: &str) -> BTreeMap<String, (HalType, &'static str)> {
    h.instance()
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == owner)
        .map(|p| {
            let d = match p.dir {
                PinDir::In => "IN",
                PinDir::Out => "OUT",
                PinDir::Io => "I/O",
            };
            (p.name, (p.hal_type, d))
        })
        .collect()
}

fn params_of(h: &Host, owner: &str) -> BTreeMap<String, (HalType, &'static str)> {
    h.instance()
        .params()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == owner)
        .map(|p| {
            let d = match p.dir {
                ParamDir::Ro => "RO",
                ParamDir::Rw => "RW",
            };
            (p.name, (p.hal_type, d))
        })
        .collect()
}

/// The pins of motion(9) for `num_joints=3` and default parameters.
fn expected_pins(num_joints: usize) -> Vec<Item> {
    // Long: the list of motion(9)'s pins, one per line.
    use HalType::*;
    let mut v: Vec<Item> = Vec::new();
    let mut add = |n: String, t: HalType, d: &'static str| v.push((n, t, d));
    // Function timing pins (the HAL makes one per function).
    add("motion-command-handler.time".into(), S32, "OUT");
    add("motion-controller.time".into(), S32, "OUT");
    for (n, t, d) in [
        ("adaptive-feed", Float, "IN"),
        ("coord-error", Bit, "OUT"),
        ("coord-mode", Bit, "OUT"),
        ("current-vel", Float, "OUT"),
        ("distance-to-go", Float, "OUT"),
        ("enable", Bit, "IN"),
        ("eoffset-active", Bit, "OUT"),
        ("eoffset-limited", Bit, "OUT"),
        ("feed-hold", Bit, "IN"),
        ("feed-inches-per-minute", Float, "OUT"),
        ("feed-inches-per-second", Float, "OUT"),
        ("feed-inhibit", Bit, "IN"),
        ("feed-mm-per-minute", Float, "OUT"),
        ("feed-mm-per-second", Float, "OUT"),
        ("feed-upm", Float, "OUT"),
        ("homing-inhibit", Bit, "IN"),
        ("in-position", Bit, "OUT"),
        ("interp.arc-center-x", Float, "OUT"),
        ("interp.arc-center-y", Float, "OUT"),
        ("interp.arc-center-z", Float, "OUT"),
        ("interp.arc-radius", Float, "OUT"),
        ("interp.feedrate", Float, "OUT"),
        ("interp.heading", Float, "OUT"),
        ("interp.iscircle", Bit, "OUT"),
        ("interp.line-number", S32, "OUT"),
        ("interp.motion-type", S32, "OUT"),
        ("interp.normal-heading", Float, "OUT"),
        ("is-all-homed", Bit, "OUT"),
        ("jog-inhibit", Bit, "IN"),
        ("jog-is-active", Bit, "OUT"),
        ("jog-stop", Bit, "IN"),
        ("jog-stop-immediate", Bit, "IN"),
        ("motion-enabled", Bit, "OUT"),
        ("motion-type", S32, "OUT"),
        ("on-soft-limit", Bit, "OUT"),
        ("probe-input", Bit, "IN"),
        ("program-line", S32, "OUT"),
        ("requested-vel", Float, "OUT"),
        ("servo.last-period", U32, "OUT"),
        ("teleop-mode", Bit, "OUT"),
        ("tp-reverse", Bit, "OUT"),
    ] {
        add(format!("motion.{n}"), t, d);
    }
    for n in 0..4 {
        add(format!("motion.digital-in-{n:02}"), Bit, "IN");
        add(format!("motion.digital-out-{n:02}"), Bit, "OUT");
        add(format!("motion.analog-in-{n:02}"), Float, "IN");
        add(format!("motion.analog-out-{n:02}"), Float, "OUT");
    }
    for l in "xyzabcuvw".chars() {
        add(format!("motion.tooloffset.{l}"), Float, "OUT");
    }
    for (n, t, d) in [
        ("amp-fault-in", Bit, "IN"),
        ("at-speed", Bit, "IN"),
        ("brake", Bit, "OUT"),
        ("forward", Bit, "OUT"),
        ("index-enable", Bit, "I/O"),
        ("inhibit", Bit, "IN"),
        ("is-oriented", Bit, "IN"),
        ("locked", Bit, "OUT"),
        ("on", Bit, "OUT"),
        ("orient", Bit, "OUT"),
        ("orient-angle", Float, "OUT"),
        ("orient-fault", S32, "IN"),
        ("orient-mode", S32, "OUT"),
        ("reverse", Bit, "OUT"),
        ("revs", Float, "IN"),
        ("speed-cmd-rps", Float, "OUT"),
        ("speed-in", Float, "IN"),
        ("speed-out", Float, "OUT"),
        ("speed-out-abs", Float, "OUT"),
        ("speed-out-rps", Float, "OUT"),
        ("speed-out-rps-abs", Float, "OUT"),
    ] {
        add(format!("spindle.0.{n}"), t, d);
    }
    for j in 0..num_joints {
        for (n, t, d) in [
            ("acc-cmd", Float, "OUT"),
            ("active", Bit, "OUT"),
            ("amp-enable-out", Bit, "OUT"),
            ("amp-fault-in", Bit, "IN"),
            ("backlash-corr", Float, "OUT"),
            ("backlash-filt", Float, "OUT"),
            ("backlash-vel", Float, "OUT"),
            ("coarse-pos-cmd", Float, "OUT"),
            ("error", Bit, "OUT"),
            ("f-error", Float, "OUT"),
            ("f-error-lim", Float, "OUT"),
            ("f-errored", Bit, "OUT"),
            ("faulted", Bit, "OUT"),
            ("free-pos-cmd", Float, "OUT"),
            ("free-tp-enable", Bit, "OUT"),
            ("free-vel-lim", Float, "OUT"),
            ("home-state", S32, "OUT"),
            ("home-sw-in", Bit, "IN"),
            ("homed", Bit, "OUT"),
            ("homing", Bit, "OUT"),
            ("in-position", Bit, "OUT"),
            ("index-enable", Bit, "I/O"),
            ("jerk-cmd", Float, "OUT"),
            ("jog-accel-fraction", Float, "IN"),
            ("jog-counts", S32, "IN"),
            ("jog-enable", Bit, "IN"),
            ("jog-scale", Float, "IN"),
            ("jog-vel-mode", Bit, "IN"),
            ("kb-jog-active", Bit, "OUT"),
            ("motor-offset", Float, "OUT"),
            ("motor-pos-cmd", Float, "OUT"),
            ("motor-pos-fb", Float, "IN"),
            ("neg-hard-limit", Bit, "OUT"),
            ("neg-lim-sw-in", Bit, "IN"),
            ("pos-cmd", Float, "OUT"),
            ("pos-fb", Float, "OUT"),
            ("pos-hard-limit", Bit, "OUT"),
            ("pos-lim-sw-in", Bit, "IN"),
            ("vel-cmd", Float, "OUT"),
            ("wheel-jog-active", Bit, "OUT"),
        ] {
            add(format!("joint.{j}.{n}"), t, d);
        }
    }
    for l in "xyzabcuvw".chars() {
        for (n, t, d) in [
            ("eoffset", Float, "OUT"),
            ("eoffset-clear", Bit, "IN"),
            ("eoffset-counts", S32, "IN"),
            ("eoffset-enable", Bit, "IN"),
            ("eoffset-request", Float, "OUT"),
            ("eoffset-scale", Float, "IN"),
            ("jog-accel-fraction", Float, "IN"),
            ("jog-counts", S32, "IN"),
            ("jog-enable", Bit, "IN"),
            ("jog-scale", Float, "IN"),
            ("jog-vel-mode", Bit, "IN"),
            ("kb-jog-active", Bit, "OUT"),
            ("pos-cmd", Float, "OUT"),
            ("teleop-pos-cmd", Float, "OUT"),
            ("teleop-tp-enable", Bit, "OUT"),
            ("teleop-vel-cmd", Float, "OUT"),
            ("teleop-vel-lim", Float, "OUT"),
            ("wheel-jog-active", Bit, "OUT"),
        ] {
            add(format!("axis.{l}.{n}"), t, d);
        }
    }
    v
}

fn expected_params() -> Vec<Item> {
    use HalType::*;
    let mut v: Vec<Item> = vec![
        ("motion-command-handler.tmax".into(), S32, "RW"),
        ("motion-command-handler.tmax-increased".into(), Bit, "RO"),
        ("motion-controller.tmax".into(), S32, "RW"),
        ("motion-controller.tmax-increased".into(), Bit, "RO"),
        ("motion.debug-bit-0".into(), Bit, "RO"),
        ("motion.debug-bit-1".into(), Bit, "RO"),
        ("motion.debug-float-0".into(), Float, "RO"),
        ("motion.debug-float-1".into(), Float, "RO"),
        ("motion.debug-float-2".into(), Float, "RO"),
        ("motion.debug-float-3".into(), Float, "RO"),
        ("motion.debug-s32-0".into(), S32, "RO"),
        ("motion.debug-s32-1".into(), S32, "RO"),
        ("traj.active_tc".into(), U32, "RO"),
        ("traj.pos_out".into(), Float, "RO"),
        ("traj.vel_out".into(), Float, "RO"),
    ];
    for n in 0..4 {
        for q in ["pos", "vel", "acc"] {
            v.push((format!("tc.{n}.{q}"), Float, "RO"));
        }
    }
    v
}

fn as_map(items: Vec<Item>) -> BTreeMap<String, (HalType, &'static str)> {
    items.into_iter().map(|(n, t, d)| (n, (t, d))).collect()
}

/// Differences between two name maps, for a readable failure.
fn diff(
    got: &BTreeMap<String, (HalType, &'static str)>,
    want: &BTreeMap<String, (HalType, &'static str)>,
) -> String {
    let mut s = String::new();
    for (k, v) in want {
        match got.get(k) {
            None => s.push_str(&format!("missing {k}\n")),
            Some(g) if g != v => s.push_str(&format!("{k}: got {g:?}, want {v:?}\n")),
            _ => {}
        }
    }
    for k in got.keys() {
        if !want.contains_key(k) {
            s.push_str(&format!("unexpected {k}\n"));
        }
    }
    s
}

#[test]
fn loadrt_trivkins_then_motmod_num_joints_3_exports_the_man_page_names() {
    let h = host("names");
    loadrt(&h, "trivkins", &[]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3"]).unwrap();
    assert_eq!(h.loaded_components(), ["trivkins", "motmod"]);
    let pins = pins_of(&h, "motmod");
    let want = as_map(expected_pins(3));
    assert_eq!(diff(&pins, &want), "");
    assert_eq!(pins.len(), want.len());
    let params = params_of(&h, "motmod");
    assert_eq!(diff(&params, &as_map(expected_params())), "");
    let mut functs: Vec<String> = h
        .instance()
        .functs()
        .unwrap()
        .into_iter()
        .filter(|f| f.owner == "motmod")
        .map(|f| f.name)
        .collect();
    functs.sort();
    assert_eq!(functs, ["motion-command-handler", "motion-controller"]);
    // Defaults LinuxCNC gives its inputs.
    let inst = h.instance();
    assert_eq!(inst.pin_value("motion.enable").unwrap(), Value::Bit(true));
    assert_eq!(
        inst.pin_value("motion.adaptive-feed").unwrap(),
        Value::Float(1.0)
    );
    assert_eq!(
        inst.pin_value("spindle.0.at-speed").unwrap(),
        Value::Bit(true)
    );
    assert_eq!(
        inst.pin_value("joint.2.jog-accel-fraction").unwrap(),
        Value::Float(1.0)
    );
    assert_eq!(
        inst.pin_value("axis.w.jog-accel-fraction").unwrap(),
        Value::Float(1.0)
    );
    assert_eq!(
        inst.pin_value("motion.is-all-homed").unwrap(),
        Value::Bit(false)
    );
}

#[test]
fn optional_pins_follow_the_module_parameters() {
    let h = host("optional");
    loadrt(&h, "trivkins", &["coordinates=xyzy", "kinstype=both"]).unwrap();
    loadrt(
        &h,
        "motmod",
        &[
            "num_joints=4",
            "num_extrajoints=1",
            "num_spindles=2",
            "names_din=homed-x,homed-y",
            "names_dout=busy",
            "num_aio=1",
            "names_misc_errors=overtemp,coolant",
            "unlock_joints_mask=0x5",
        ],
    )
    .unwrap();
    let pins = pins_of(&h, "motmod");
    let has = |n: &str| pins.contains_key(n);
    for n in [
        "motion.din-homed-x",
        "motion.din-homed-y",
        "motion.dout-busy",
        "motion.digital-out-00",
        "motion.analog-in-00",
        "motion.analog-out-00",
        "motion.err-overtemp",
        "motion.err-coolant",
        "spindle.1.speed-out",
        "joint.0.unlock",
        "joint.0.is-unlocked",
        "joint.2.unlock",
        "joint.3.posthome-cmd",
        "joint.3.motor-pos-cmd",
    ] {
        assert!(has(n), "{n}");
    }
    for n in [
        "motion.digital-in-00",
        "motion.digital-out-01",
        "motion.analog-in-01",
        "motion.misc-error-00",
        "joint.1.unlock",
        "joint.2.posthome-cmd",
        "joint.4.pos-cmd",
        "spindle.2.on",
        "motion.switchkins-type",
    ] {
        assert!(!has(n), "{n}");
    }
    assert_eq!(pins["joint.2.unlock"], (HalType::Bit, "OUT"));
    assert_eq!(pins["joint.2.is-unlocked"], (HalType::Bit, "IN"));
    assert_eq!(pins["joint.3.posthome-cmd"], (HalType::Float, "IN"));

    let h = host("numbered");
    loadrt(&h, "trivkins", &[]).unwrap();
    loadrt(
        &h,
        "motmod",
        &[
            "num_joints=1",
            "num_dio=2",
            "num_misc_error=2",
            "num_spindles=0",
        ],
    )
    .unwrap();
    let pins = pins_of(&h, "motmod");
    assert!(pins.contains_key("motion.misc-error-01"));
    assert!(pins.contains_key("motion.digital-out-01"));
    assert!(!pins.contains_key("motion.digital-out-02"));
    assert!(!pins.keys().any(|k| k.starts_with("spindle.")));
}

fn threads(h: &Host) -> Vec<(String, i64)> {
    h.instance()
        .threads()
        .unwrap()
        .into_iter()
        .map(|t| (t.name, t.period))
        .collect()
}

#[test]
fn motmod_creates_its_threads_like_linuxcnc() {
    let h = host("thr1");
    loadrt(&h, "trivkins", &[]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3"]).unwrap();
    assert_eq!(threads(&h), [("servo-thread".to_string(), 1_000_000)]);

    let h = host("thr2");
    loadrt(&h, "trivkins", &[]).unwrap();
    loadrt(
        &h,
        "motmod",
        &["base_period_nsec=25000", "servo_period_nsec=1010000"],
    )
    .unwrap();
    // The servo period is rounded to a whole number of base periods.
    let mut t = threads(&h);
    t.sort();
    assert_eq!(
        t,
        [
            ("base-thread".to_string(), 25_000),
            ("servo-thread".to_string(), 1_000_000)
        ]
    );

    let h = host("thr3");
    loadrt(&h, "trivkins", &[]).unwrap();
    loadrt(
        &h,
        "motmod",
        &["base_period_nsec=500000", "servo_period_nsec=500000"],
    )
    .unwrap();
    assert_eq!(threads(&h), [("servo-thread".to_string(), 500_000)]);
}

#[test]
fn bad_module_parameters_are_refused_and_leave_nothing() {
    let h = host("bad");
    // No kinematics loaded.
    match loadrt(&h, "motmod", &[]) {
        Err(HalError::ModuleLoad { module, reason }) => {
            assert_eq!(module, "motmod");
            assert!(reason.contains("kinematics"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    loadrt(&h, "trivkins", &[]).unwrap();
    for (args, param) in [
        (&["num_joints=0"][..], "num_joints"),
        (&["num_joints=17"][..], "num_joints"),
        (
            &["num_joints=3", "num_extrajoints=4"][..],
            "num_extrajoints",
        ),
        (
            &["num_joints=3", "num_extrajoints=1"][..],
            "num_extrajoints",
        ),
        (&["num_dio=0"][..], "num_dio"),
        (&["num_dio=65"][..], "num_dio"),
        (&["num_dio=2", "names_din=a"][..], "num_dio"),
        (&["num_aio=70"][..], "num_aio"),
        (&["num_aio=1", "names_aout=a"][..], "num_aio"),
        (&["num_misc_error=65"][..], "num_misc_error"),
        (
            &["num_misc_error=1", "names_misc_errors=x"][..],
            "num_misc_error",
        ),
        (&["num_spindles=9"][..], "num_spindles"),
        (&["num_spindles=-1"][..], "num_spindles"),
        (&["servo_period_nsec=0"][..], "servo_period_nsec"),
        (&["base_period_nsec=-5"][..], "base_period_nsec"),
        (&["traj_period_nsec=-5"][..], "traj_period_nsec"),
        (
            &["base_period_nsec=2000000", "servo_period_nsec=1000000"][..],
            "servo_period_nsec",
        ),
        (&["num_joints=x"][..], "num_joints"),
        (
            &[
                "base_period_nsec=2",
                "servo_period_nsec=9223372036854775807",
            ][..],
            "servo_period_nsec",
        ),
        (&["nonsense=1"][..], "nonsense"),
    ] {
        match loadrt(&h, "motmod", args) {
            Err(HalError::ModuleParam {
                param: p, module, ..
            }) => {
                assert_eq!((module.as_str(), p.as_str()), ("motmod", param), "{args:?}")
            }
            other => panic!("{args:?}: {other:?}"),
        }
        assert_eq!(h.loaded_components(), ["trivkins"], "{args:?}");
        assert!(threads(&h).is_empty(), "{args:?}");
        assert!(MotionHandle::attach(h.instance().name()).is_none());
    }
    loadrt(&h, "motmod", &["num_joints=2"]).unwrap();
    assert!(MotionHandle::attach(h.instance().name()).is_some());
}

#[test]
fn running_in_the_servo_thread_enables_jogs_and_trips() {
    let h = host("run");
    loadrt(&h, "trivkins", &["coordinates=xyz"]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3", "servo_period_nsec=1000000"]).unwrap();
    let inst = h.instance();
    // Loop each motor command back as its feedback.
    loop_back_motors(&h, 3);
    let m = MotionHandle::attach(inst.name()).expect("motmod registered");
    assert_eq!(m.num_joints(), 3);
    // Not running yet: nobody takes the command.
    assert_eq!(m.command(Command::Enable), Err(Reject::Timeout));

    start_motion(&h);
    for j in 0..3 {
        for c in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -10.0,
                max: 10.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 20.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 500.0,
            },
        ] {
            m.command(c).unwrap();
        }
    }
    assert_eq!(
        m.command(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::NotEnabled)
    );
    inst.set_pin("motion.enable", Value::Bit(false)).unwrap();
    assert_eq!(m.command(Command::Enable), Err(Reject::EnableInputFalse));
    inst.set_pin("motion.enable", Value::Bit(true)).unwrap();
    m.command(Command::Enable).unwrap();
    wait_for("motion enabled", || bit(&h, "motion.motion-enabled"));
    assert!(bit(&h, "joint.0.amp-enable-out") && bit(&h, "joint.2.active"));

    m.command(Command::JogIncr {
        joint: 1,
        vel: 10.0,
        offset: 0.5,
    })
    .unwrap();
    wait_for("the jog to start", || !bit(&h, "motion.in-position"));
    assert!(bit(&h, "joint.1.kb-jog-active"));
    wait_for("the jog to end", || bit(&h, "motion.in-position"));
    assert!((float(&h, "joint.1.pos-cmd") - 0.5).abs() < 1e-6);
    assert_eq!(float(&h, "joint.1.free-pos-cmd"), 0.5);
    assert_eq!(
        float(&h, "axis.y.pos-cmd"),
        float(&h, "joint.1.coarse-pos-cmd")
    );
    assert_eq!(
        float(&h, "joint.1.motor-pos-cmd"),
        float(&h, "joint.1.pos-cmd")
    );
    assert!(!bit(&h, "motion.jog-is-active"));

    assert_eq!(
        float(&h, "joint.1.f-error-lim"),
        0.01,
        "at rest: MIN_FERROR default"
    );

    // A hard limit trips; override, re-enable and jog off it.
    inst.set_pin("joint.0.neg-lim-sw-in", Value::Bit(true))
        .unwrap();
    wait_for("the limit to disable", || !bit(&h, "motion.motion-enabled"));
    assert!(bit(&h, "joint.0.neg-hard-limit") && bit(&h, "joint.0.error"));
    assert_eq!(m.events(), [Event::JointOnLimit { joint: 0 }]);
    m.command(Command::OverrideLimits { joint: 0 }).unwrap();
    m.command(Command::Enable).unwrap();
    wait_for("motion enabled again", || bit(&h, "motion.motion-enabled"));
    assert_eq!(
        m.command(Command::JogCont {
            joint: 0,
            vel: -1.0
        }),
        Err(Reject::OnHardLimit {
            joint: 0,
            dir: motion::Direction::Negative
        })
    );
    m.command(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    wait_for("the joint to move", || float(&h, "joint.0.vel-cmd") > 0.0);
    inst.set_pin("joint.0.neg-lim-sw-in", Value::Bit(false))
        .unwrap();
    m.command(Command::JogAbort { joint: 0 }).unwrap();
    wait_for("the jog to stop", || bit(&h, "motion.in-position"));
    assert!(bit(&h, "motion.motion-enabled"));
    assert_eq!(
        h.instance().param_value("motion.debug-s32-0").unwrap(),
        Value::S32(0),
        "the override ended with the jog"
    );

    // An amplifier fault disables at once and is reported once.
    inst.set_pin("joint.2.amp-fault-in", Value::Bit(true))
        .unwrap();
    wait_for("the fault to disable", || !bit(&h, "motion.motion-enabled"));
    assert!(bit(&h, "joint.2.faulted") && bit(&h, "joint.2.error"));
    assert!(!bit(&h, "joint.0.amp-enable-out"));
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(m.events(), [Event::JointAmpFault { joint: 2 }]);
    h.stop();
    // Unloading motmod ends the registration.
    h.unloadrt("motmod").unwrap();
    assert!(MotionHandle::attach(inst.name()).is_none());
}

#[test]
fn the_shared_memory_channel_enables_jogs_reports_status_and_rejects() {
    use motion::{MotionClient, Reject};
    let h = host("chan");
    loadrt(&h, "trivkins", &["coordinates=xyz"]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3", "servo_period_nsec=1000000"]).unwrap();
    let inst = h.instance();
    loop_back_motors(&h, 3);
    let mut c = MotionClient::open(inst)
        .unwrap()
        .with_timeout(Duration::from_millis(200));
    let s0 = c.status().unwrap();
    assert_eq!(
        (s0.mode, s0.enabled, s0.joints.len()),
        ("DISABLED", false, 3)
    );
    assert_eq!(s0.last.serial, 0);
    // Not running: no answer.
    let e = c.send(Command::Enable).unwrap_err();
    assert_eq!(e.reason, Reject::Timeout);
    // The stale command is still in the ring; it runs when the thread
    // starts, and its late answer is discarded by the next send.
    start_motion(&h);
    let mut c = c.with_timeout(Duration::from_secs(2));
    // Undo the stale ENABLE before configuring.
    c.send(Command::Disable).unwrap();
    for j in 0..3 {
        for cmd in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -10.0,
                max: 10.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 20.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 500.0,
            },
        ] {
            c.send(cmd).unwrap();
        }
    }
    // A rejection with its reason, code and text.
    let r = c.send(Command::JogCont { joint: 7, vel: 1.0 }).unwrap_err();
    assert_eq!(
        r.reason,
        Reject::NoSuchJoint {
            joint: 7,
            num_joints: 3
        }
    );
    assert_eq!(r.code(), 1);
    assert!(r.to_string().contains("joint 7 does not exist"), "{r}");
    wait_for("the status to show the rejection", || {
        let s = c.status().unwrap();
        s.last.serial == r.serial && s.last.code == 1
    });
    let r = c
        .send(Command::AxisJogCont { axis: 0, vel: 1.0 })
        .unwrap_err();
    assert_eq!(r.reason, Reject::NotEnabled, "{r}");

    let a = c.send(Command::Enable).unwrap();
    assert!(a.serial > r.serial);
    wait_for("enabled in the status", || {
        let s = c.status().unwrap();
        s.enabled && s.mode == "FREE" && s.joints.iter().all(|j| j.amp_enabled && j.active)
    });
    c.send(Command::JogIncr {
        joint: 2,
        vel: 10.0,
        offset: 0.5,
    })
    .unwrap();
    wait_for("the jog to show in the status", || {
        let s = c.status().unwrap();
        s.joints[2].pos_cmd > 0.0 && s.joints[2].pos_cmd < 0.5
    });
    wait_for("the jog to end", || {
        let s = c.status().unwrap();
        s.in_position && (s.joints[2].pos_cmd - 0.5).abs() < 1e-6
    });
    assert_eq!(
        float(&h, "joint.2.pos-cmd"),
        c.status().unwrap().joints[2].pos_cmd
    );

    // The same controller answers MotionHandle and the channel.
    let m = MotionHandle::attach(inst.name()).unwrap();
    m.command(Command::Disable).unwrap();
    wait_for("disabled", || !c.status().unwrap().enabled);
    assert_eq!(
        c.send(Command::JogCont { joint: 0, vel: 1.0 })
            .unwrap_err()
            .reason,
        Reject::NotEnabled
    );

    // A corrupt record written straight into the ring is answered, not run.
    let mut w = hal_core::RingWriter::open(inst, motion::channel::CMD_RING).unwrap();
    let mut rec = motion::channel::encode_command(999_999, &Command::Enable);
    rec[4] ^= 1;
    assert!(w.push(&rec));
    wait_for("the corrupt record to be answered", || {
        c.status().unwrap().last.serial == 999_999
    });
    let s = c.status().unwrap();
    assert_eq!(
        motion::channel::result_name(s.last.code),
        "rejected: malformed"
    );
    assert!(!s.enabled, "the corrupt ENABLE did not run");
    h.stop();
}

#[test]
fn homing_on_the_index_through_hal_pins() {
    let h = host("home");
    loadrt(&h, "trivkins", &["coordinates=x"]).unwrap();
    loadrt(&h, "motmod", &["num_joints=1", "servo_period_nsec=1000000"]).unwrap();
    let inst = h.instance();
    loop_back_motors(&h, 1);
    // The encoder's side of the index handshake is this test.
    inst.newsig("j0-index", HalType::Bit).unwrap();
    inst.link("joint.0.index-enable", "j0-index").unwrap();
    let m = MotionHandle::attach(inst.name()).unwrap();
    start_motion(&h);
    for c in [
        Command::JointActivate { joint: 0 },
        Command::SetJointPositionLimits {
            joint: 0,
            min: -10.0,
            max: 10.0,
        },
        Command::SetJointVelLimit {
            joint: 0,
            vel: 20.0,
        },
        Command::SetJointAccLimit {
            joint: 0,
            acc: 500.0,
        },
        Command::SetJointHomingParams {
            joint: 0,
            config: motion::homing::HomingConfig {
                offset: 2.0,
                home: 3.0,
                latch_vel: 1.0,
                flags: motion::homing::HomeFlags::USE_INDEX,
                sequence: 0,
                ..Default::default()
            },
        },
        Command::Enable,
    ] {
        m.command(c).unwrap();
    }
    wait_for("motion enabled", || bit(&h, "motion.motion-enabled"));
    m.command(Command::Home { joint: 0 }).unwrap();
    wait_for("the index to be armed", || bit(&h, "joint.0.index-enable"));
    let state = |h: &Host| match h.instance().pin_value("joint.0.home-state").unwrap() {
        Value::S32(v) => v,
        v => panic!("{v:?}"),
    };
    assert_eq!(state(&h), 18, "INDEX_SEARCH_WAIT");
    assert!(bit(&h, "joint.0.homing") && !bit(&h, "joint.0.homed"));
    wait_for("the latch move", || float(&h, "joint.0.vel-cmd") > 0.5);
    // The encoder sees the index: it restarts its count and clears the
    // signal (here the count is the command, so zero it too).
    inst.set_signal("j0-index", Value::Bit(false)).unwrap();
    wait_for("homing to finish", || {
        bit(&h, "joint.0.homed") && !bit(&h, "joint.0.homing")
    });
    assert_eq!(state(&h), 0);
    wait_for("the final move", || bit(&h, "motion.in-position"));
    assert_eq!(float(&h, "joint.0.pos-cmd"), 3.0);
    assert!(!bit(&h, "joint.0.index-enable"), "nothing re-armed it");
    assert!(bit(&h, "motion.is-all-homed"));
    assert!(m.events().is_empty());
    h.stop();
}
