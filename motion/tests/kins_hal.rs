//! The kinematics modules through HAL: what `loadrt` exports (LinuxCNC's
//! pin names), that the geometry pins are read at every call, the
//! switchable-kinematics convention, refused module parameters, and a
//! linear delta driven by `motmod` in teleop mode.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::time::Duration;

mod common;

use common::*;
use hal_core::{HalError, Host, PinDir, Value};
use motion::kins::lineardeltakins::LinearDelta;
use motion::kins::{kinematics_for, Kinematics};
use motion::{
    Command, Event, KinematicsType, KinsError, KinsFlags, MotionClient, MotionHandle, Pose,
};

/// The pins the component `comp` owns, sorted, with their directions.
fn pins_of(h: &Host, comp: &str) -> Vec<(String, PinDir)> {
    let mut v: Vec<_> = h
        .instance()
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == comp)
        .map(|p| (p.name, p.dir))
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

fn kins(h: &Host) -> std::sync::Arc<dyn Kinematics> {
    kinematics_for(h.instance().name())
        .expect("kinematics registered")
        .1
}

fn set(h: &Host, pin: &str, v: f64) {
    h.instance().set_pin(pin, Value::Float(v)).unwrap();
}

fn inverse(k: &dyn Kinematics, pose: [f64; 6], start: [f64; 6]) -> Result<[f64; 6], KinsError> {
    let mut p = Pose::ZERO;
    p.0[..6].copy_from_slice(&pose);
    let mut j = start;
    k.inverse(&p, &mut j, &mut KinsFlags::default()).map(|()| j)
}

fn forward(k: &dyn Kinematics, joints: &[f64], guess: [f64; 6]) -> Result<Pose, KinsError> {
    let mut p = Pose::ZERO;
    p.0[..6].copy_from_slice(&guess);
    k.forward(joints, &mut p, &mut KinsFlags::default())
        .map(|()| p)
}

fn names(prefix: &str, items: &[&str]) -> Vec<String> {
    items.iter().map(|i| format!("{prefix}{i}")).collect()
}

/// Every module's pins, by LinuxCNC's names, owned by a component of the
/// module's name.
#[test]
fn modules_export_linuxcnc_pins() {
    let kinstype = names("kinstype.is-", &["0", "1", "2"]);
    let genser: Vec<String> = (0..6)
        .flat_map(|i| ["A", "ALPHA", "D", "unrotate"].map(|p| format!("genserkins.{p}-{i}")))
        .chain(names("genserkins.", &["last-iterations", "max-iterations"]))
        .collect();
    let genhex: Vec<String> = (0..6)
        .flat_map(|i| {
            let mut v: Vec<String> = ["base", "platform", "base-n", "platform-n"]
                .iter()
                .flat_map(|w| ["x", "y", "z"].map(|a| format!("genhexkins.{w}.{i}.{a}")))
                .collect();
            v.push(format!("genhexkins.correction.{i}"));
            v
        })
        .chain(names(
            "genhexkins.",
            &[
                "convergence-criterion",
                "limit-iterations",
                "max-error",
                "last-iterations",
                "max-iterations",
                "tool-offset",
                "spindle-offset",
                "screw-lead",
                "fwd-kins-fail",
                "x",
                "y",
                "z",
                "a",
                "b",
                "c",
            ],
        ))
        .chain(names("skgui.", &["x", "y", "z", "a", "b", "c"]))
        .collect();
    let trt = |m: &str| {
        names(
            &format!("{m}."),
            &[
                "x-rot-point",
                "y-rot-point",
                "z-rot-point",
                "x-offset",
                "y-offset",
                "z-offset",
                "tool-offset",
                "conventional-directions",
            ],
        )
    };
    let cases: Vec<(&str, Vec<String>, bool)> = vec![
        ("corexykins", vec![], false),
        ("bipodkins", names("bipodkins.", &["Bx"]), false),
        (
            "scarakins",
            names("scarakins.", &["D1", "D2", "D3", "D4", "D5", "D6"]),
            true,
        ),
        (
            "pumakins",
            names("pumakins.", &["A2", "A3", "D3", "D4", "D6"]),
            true,
        ),
        ("genserkins", genser, true),
        (
            "lineardeltakins",
            names("lineardeltakins.", &["R", "L"]),
            false,
        ),
        (
            "rotarydeltakins",
            names(
                "rotarydeltakins.",
                &["platformradius", "thighlength", "shinlength", "footradius"],
            ),
            false,
        ),
        ("genhexkins", genhex, true),
        ("xyzac-trt-kins", trt("xyzac-trt-kins"), true),
        ("xyzbc-trt-kins", trt("xyzbc-trt-kins"), true),
    ];
    for (module, mut want, switchable) in cases {
        let h = host(&format!("kpins-{module}"));
        loadrt(&h, module, &[]).unwrap();
        assert_eq!(h.loaded_components(), [module]);
        if switchable {
            want.extend(kinstype.iter().cloned());
        }
        want.sort();
        let got: Vec<String> = pins_of(&h, module).into_iter().map(|p| p.0).collect();
        assert_eq!(got, want, "{module}");
        let k = kins(&h);
        assert_eq!(k.name(), module);
        assert_eq!(k.kins_type(), KinematicsType::Both, "{module}");
        assert_eq!(k.is_switchable(), switchable, "{module}");
        // Unloading takes the kinematics away again.
        h.unloadrt(module).unwrap();
        assert!(kinematics_for(h.instance().name()).is_none());
    }
}

#[test]
fn pin_directions_and_defaults_follow_linuxcnc() {
    let h = host("kdefaults");
    loadrt(&h, "pumakins", &[]).unwrap();
    let pins = pins_of(&h, "pumakins");
    assert!(pins.contains(&("pumakins.A2".into(), PinDir::Io)));
    assert!(pins.contains(&("kinstype.is-0".into(), PinDir::Out)));
    assert_eq!(float(&h, "pumakins.D6"), 70.0);
    assert!(bit(&h, "kinstype.is-0") && !bit(&h, "kinstype.is-1"));
    h.unloadrt("pumakins").unwrap();
    loadrt(&h, "genhexkins", &[]).unwrap();
    assert_eq!(float(&h, "genhexkins.base.3.y"), -26.5);
    assert_eq!(float(&h, "genhexkins.platform-n.1.x"), 0.866025);
    assert_eq!(float(&h, "genhexkins.max-error"), 500.0);
    assert_eq!(
        h.instance()
            .pin_value("genhexkins.limit-iterations")
            .unwrap(),
        Value::U32(120)
    );
    h.unloadrt("genhexkins").unwrap();
    loadrt(&h, "lineardeltakins", &[]).unwrap();
    assert_eq!(float(&h, "lineardeltakins.R"), 130.25);
    assert_eq!(float(&h, "lineardeltakins.L"), 269.0);
}

/// Setting a geometry pin (as `setp` does) changes the next result.
#[test]
fn geometry_pins_are_read_at_every_call() {
    struct Case {
        module: &'static str,
        pin: &'static str,
        value: f64,
        pose: [f64; 6],
        start: [f64; 6],
    }
    let cases = [
        Case {
            module: "bipodkins",
            pin: "bipodkins.Bx",
            value: 3.0,
            pose: [0.5, 1.0, 0.0, 0.0, 0.0, 0.0],
            start: [0.0; 6],
        },
        Case {
            module: "scarakins",
            pin: "scarakins.D2",
            value: 300.0,
            pose: [300.0, 200.0, 100.0, 0.0, 0.0, 20.0],
            start: [0.0; 6],
        },
        Case {
            module: "pumakins",
            pin: "pumakins.A2",
            value: 320.0,
            pose: [300.0, 100.0, -300.0, 180.0, 10.0, 20.0],
            start: [0.0, 0.0, 0.0, 0.0, 30.0, 0.0],
        },
        Case {
            module: "genserkins",
            pin: "genserkins.D-3",
            value: 410.0,
            pose: [300.0, 100.0, -300.0, 180.0, 10.0, 20.0],
            start: [15.0, -30.0, 10.0, 0.0, 40.0, 20.0],
        },
        Case {
            module: "lineardeltakins",
            pin: "lineardeltakins.L",
            value: 280.0,
            pose: [10.0, 20.0, 0.0, 0.0, 0.0, 0.0],
            start: [0.0; 6],
        },
        Case {
            module: "rotarydeltakins",
            pin: "rotarydeltakins.shinlength",
            value: 15.0,
            pose: [1.0, 2.0, -15.0, 0.0, 0.0, 0.0],
            start: [0.0; 6],
        },
        Case {
            module: "genhexkins",
            pin: "genhexkins.platform.2.x",
            value: 11.0,
            pose: [1.0, 2.0, 20.0, 3.0, 4.0, 5.0],
            start: [0.0; 6],
        },
        Case {
            module: "xyzac-trt-kins",
            pin: "xyzac-trt-kins.y-rot-point",
            value: 25.0,
            pose: [10.0, 20.0, 30.0, 40.0, 0.0, 60.0],
            start: [0.0; 6],
        },
        Case {
            module: "xyzbc-trt-kins",
            pin: "xyzbc-trt-kins.x-offset",
            value: 5.0,
            pose: [10.0, 20.0, 30.0, 0.0, 50.0, 60.0],
            start: [0.0; 6],
        },
    ];
    for c in cases {
        let h = host(&format!("kgeom-{}", c.module));
        loadrt(&h, c.module, &[]).unwrap();
        let k = kins(&h);
        let before = inverse(&*k, c.pose, c.start).unwrap();
        set(&h, c.pin, c.value);
        let after = inverse(&*k, c.pose, c.start).unwrap();
        assert_ne!(before, after, "{}: {}", c.module, c.pin);
        // And forward agrees with the new geometry.
        let n = if c.module == "bipodkins" { 2 } else { 6 };
        let back = forward(&*k, &after[..n], c.pose).unwrap();
        for a in 0..n.min(3) {
            assert!(
                (back.0[a] - c.pose[a]).abs() < 1e-6,
                "{}: {back:?}",
                c.module
            );
        }
    }
}

#[test]
fn switchable_modules_follow_the_switchkins_convention() {
    let h = host("kswitch");
    loadrt(&h, "scarakins", &["coordinates=xyzabc"]).unwrap();
    let k = kins(&h);
    let j = [30.0, 40.0, 10.0, 20.0, 0.0, 0.0];
    let scara = forward(&*k, &j, [0.0; 6]).unwrap();
    assert!(scara.0[0] > 100.0, "type 0 is the SCARA: {scara:?}");
    // Type 1: identity over the coordinates.
    k.switch_to(1).unwrap();
    assert!(!bit(&h, "kinstype.is-0") && bit(&h, "kinstype.is-1") && !bit(&h, "kinstype.is-2"));
    let p = forward(&*k, &j, [0.0; 6]).unwrap();
    assert_eq!(p.0[..6], j);
    // Type 2: the user type, identity like LinuxCNC's unmodified template.
    k.switch_to(2).unwrap();
    assert!(bit(&h, "kinstype.is-2"));
    assert_eq!(inverse(&*k, j, [0.0; 6]).unwrap(), j);
    // Anything else is refused and changes nothing.
    assert_eq!(k.switch_to(3), Err(KinsError::Unsupported));
    assert_eq!(k.switch_to(-1), Err(KinsError::Unsupported));
    assert!(bit(&h, "kinstype.is-2"));
    k.switch_to(0).unwrap();
    assert_eq!(forward(&*k, &j, [0.0; 6]).unwrap(), scara);
    assert!(bit(&h, "kinstype.is-0"));
}

#[test]
fn identityfirst_swaps_types_for_the_table_modules() {
    let h = host("kidfirst");
    loadrt(&h, "xyzac-trt-kins", &["sparm=identityfirst"]).unwrap();
    let k = kins(&h);
    set(&h, "xyzac-trt-kins.y-rot-point", 10.0);
    let j = [1.0, 2.0, 3.0, 30.0, 40.0];
    let p = forward(&*k, &j, [0.0; 6]).unwrap();
    assert_eq!(p.0[..3], [1.0, 2.0, 3.0], "type 0 is identity");
    k.switch_to(1).unwrap();
    let p = forward(&*k, &j, [0.0; 6]).unwrap();
    assert_ne!(p.0[..3], [1.0, 2.0, 3.0], "type 1 is the table");
}

#[test]
fn genhexkins_reports_its_iterations() {
    let h = host("kgenhex");
    loadrt(&h, "genhexkins", &[]).unwrap();
    let k = kins(&h);
    let pose = [1.0, -1.0, 22.0, 4.0, -3.0, 2.0];
    let struts = inverse(&*k, pose, [0.0; 6]).unwrap();
    let p = forward(&*k, &struts, [0.0, 0.0, 20.0, 0.0, 0.0, 0.0]).unwrap();
    assert!((p.0[2] - 22.0).abs() < 1e-9);
    let last = |h: &Host| {
        h.instance()
            .pin_value("genhexkins.last-iterations")
            .unwrap()
    };
    let Value::U32(n) = last(&h) else { panic!() };
    assert!(n >= 2, "{n}");
    assert!(!bit(&h, "genhexkins.fwd-kins-fail"));
    assert!((float(&h, "genhexkins.z") - 22.0).abs() < 1e-9);
    assert!((float(&h, "skgui.z") - 22.0).abs() < 1e-9);
    // Not converging within the limit raises the failure pin.
    h.instance()
        .set_pin("genhexkins.limit-iterations", Value::U32(1))
        .unwrap();
    assert_eq!(
        forward(&*k, &struts, [0.0, 0.0, 20.0, 0.0, 0.0, 0.0]),
        Err(KinsError::NotConverged)
    );
    assert!(bit(&h, "genhexkins.fwd-kins-fail"));
    h.instance()
        .set_pin("genhexkins.limit-iterations", Value::U32(120))
        .unwrap();
    // In identity mode the display pins still follow the hexapod,
    // iterating from its last pose.
    let moved = inverse(&*k, [0.5, -1.0, 22.0, 4.0, -3.0, 2.0], [0.0; 6]).unwrap();
    k.switch_to(1).unwrap();
    let ident = forward(&*k, &moved, [0.0; 6]).unwrap();
    assert_eq!(ident.0[..6], moved);
    assert!((float(&h, "skgui.x") - 0.5).abs() < 1e-9);
    // Back to the hexapod: it restarts from its last pose (one look, no
    // step), not from the identity pose it is handed.
    k.switch_to(0).unwrap();
    let p = forward(&*k, &moved, ident.0[..6].try_into().unwrap()).unwrap();
    assert!((p.0[0] - 0.5).abs() < 1e-9, "{p:?}");
    assert_eq!(last(&h), Value::U32(1));
}

#[test]
fn genserkins_reports_its_iterations() {
    let h = host("kgenser");
    loadrt(&h, "genserkins", &[]).unwrap();
    let k = kins(&h);
    let j = [10.0, -20.0, 30.0, 40.0, -50.0, 60.0];
    let p = forward(&*k, &j, [0.0; 6]).unwrap();
    let start = [11.0, -21.0, 29.0, 41.0, -49.0, 59.0];
    let back = inverse(&*k, p.0[..6].try_into().unwrap(), start).unwrap();
    assert!(back.iter().zip(j).all(|(a, b)| (a - b).abs() < 1e-7));
    let Value::U32(n) = h
        .instance()
        .pin_value("genserkins.last-iterations")
        .unwrap()
    else {
        panic!()
    };
    assert!(n >= 2, "{n}");
    h.instance()
        .set_pin("genserkins.max-iterations", Value::U32(1))
        .unwrap();
    assert_eq!(
        inverse(&*k, p.0[..6].try_into().unwrap(), start),
        Err(KinsError::NotConverged)
    );
}

#[test]
fn bad_module_parameters_name_the_parameter_and_leave_nothing() {
    let h = host("kbadparams");
    for (module, args, param) in [
        ("scarakins", &["coordinates=xyzq"][..], "coordinates"),
        ("scarakins", &["coordinates=xyzabcu"][..], "coordinates"),
        ("pumakins", &["coordinates=xxzabc"][..], "coordinates"),
        ("xyzac-trt-kins", &["coordinates=xyzbc"][..], "coordinates"),
        ("genhexkins", &["bogus=1"][..], "bogus"),
        ("lineardeltakins", &["coordinates=xyz"][..], "coordinates"),
    ] {
        match loadrt(&h, module, args) {
            Err(HalError::ModuleParam {
                param: p, reason, ..
            }) => {
                assert_eq!(p, param, "{module} {args:?}: {reason}")
            }
            other => panic!("{module} {args:?}: {other:?}"),
        }
        assert!(h.loaded_components().is_empty());
        assert!(kinematics_for(h.instance().name()).is_none());
        assert!(h.instance().pins().unwrap().is_empty(), "{module}");
    }
    // Duplicates are fine for the table modules (a gantry).
    loadrt(&h, "xyzbc-trt-kins", &["coordinates=xyzbcy"]).unwrap();
    // One kinematics per instance.
    match loadrt(&h, "corexykins", &[]) {
        Err(HalError::ModuleLoad { reason, .. }) => assert!(reason.contains("xyzbc-trt-kins")),
        other => panic!("{other:?}"),
    }
}

/// A linear delta under `motmod`: homed at carriage height 300, jogged
/// in world coordinates, and refused (motion disabled, motors left
/// where they were) when a jog leaves the rods' reach.
#[test]
fn linear_delta_moves_in_teleop_and_stops_at_the_edge_of_reach() {
    let h = host("kdelta");
    loadrt(&h, "lineardeltakins", &[]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3"]).unwrap();
    loop_back_motors(&h, 3);
    let m = MotionHandle::attach(h.instance().name()).unwrap();
    start_motion(&h);
    let mut c = MotionClient::open(h.instance())
        .unwrap()
        .with_timeout(Duration::from_secs(2));
    for j in 0..3 {
        for cmd in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -1000.0,
                max: 1000.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 5000.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 50000.0,
            },
            Command::SetJointHomingParams {
                joint: j,
                config: motion::homing::HomingConfig {
                    offset: 300.0,
                    home: 300.0,
                    sequence: 0,
                    ..Default::default()
                },
            },
            Command::SetAxisPositionLimits {
                axis: j,
                min: -1000.0,
                max: 1000.0,
            },
            Command::SetAxisVelLimit {
                axis: j,
                vel: 400.0,
            },
            Command::SetAxisAccLimit {
                axis: j,
                acc: 4000.0,
            },
        ] {
            c.send(cmd).unwrap();
        }
    }
    c.send(Command::Enable).unwrap();
    wait_for("enabled", || bit(&h, "motion.motion-enabled"));
    c.send(Command::Home { joint: -1 }).unwrap();
    wait_for("homed", || bit(&h, "motion.is-all-homed"));
    // Teleop is refused until the final homing moves have settled.
    wait_for("teleop to be accepted", || c.send(Command::Teleop).is_ok());
    wait_for("teleop", || c.status().unwrap().mode == "TELEOP");

    // The world pose is the forward kinematics of the homed carriages.
    let delta = LinearDelta::default();
    let drop = (delta.l * delta.l - delta.r * delta.r).sqrt();
    assert!(float(&h, "axis.x.pos-cmd").abs() < 1e-9);
    assert!((float(&h, "axis.z.pos-cmd") - (300.0 - drop)).abs() < 1e-9);

    // Jog X by 40: the carriages follow the inverse kinematics.
    c.send(Command::AxisJogIncr {
        axis: 0,
        vel: 400.0,
        offset: 40.0,
    })
    .unwrap();
    wait_for("the jog to start", || !bit(&h, "motion.in-position"));
    wait_for("the jog to end", || bit(&h, "motion.in-position"));
    let mut pose = Pose::ZERO;
    pose.0[0] = 40.0;
    pose.0[2] = 300.0 - drop;
    let mut want = [0.0; 3];
    delta
        .inverse(&pose, &mut want, &mut KinsFlags::default())
        .unwrap();
    for (j, w) in want.iter().enumerate() {
        let got = float(&h, &format!("joint.{j}.pos-cmd"));
        assert!((got - w).abs() < 1e-6, "joint {j}: {got} vs {w}");
    }
    assert!(want[1] != want[2], "towers 1 and 2 move differently in X");
    let x = float(&h, "axis.x.pos-cmd");
    assert!((x - 40.0).abs() < 1e-6, "{x}");
    assert!(m.events().is_empty());

    // Jog towards X = 500, beyond the rods' reach: the inverse kinematics
    // refuse, motion stops and disables, no motor command is a NaN.
    c.send(Command::AxisJogAbs {
        axis: 0,
        vel: 400.0,
        pos: 500.0,
    })
    .unwrap();
    wait_for("motion to disable", || !bit(&h, "motion.motion-enabled"));
    assert!(m.events().contains(&Event::InverseKinsFailed));
    let x = float(&h, "axis.x.pos-cmd");
    assert!(x > 40.0 && x < 500.0, "stopped at the edge: {x}");
    for j in 0..3 {
        let motor = float(&h, &format!("joint.{j}.motor-pos-cmd"));
        let cmd = float(&h, &format!("joint.{j}.pos-cmd"));
        assert!(motor.is_finite() && cmd > 0.0, "joint {j}: {motor} {cmd}");
    }
    h.stop();
}

/// `motion.switchkins-type` switches a switchable module under `motmod`.
#[test]
fn motmod_switches_kinematics_through_its_pin() {
    let h = host("kswitchpin");
    loadrt(&h, "scarakins", &[]).unwrap();
    loadrt(&h, "motmod", &["num_joints=6"]).unwrap();
    start_motion(&h);
    assert!(bit(&h, "kinstype.is-0"));
    set(&h, "motion.switchkins-type", 1.0);
    wait_for("identity kinematics", || bit(&h, "kinstype.is-1"));
    assert!(!bit(&h, "kinstype.is-0"));
    set(&h, "motion.switchkins-type", 2.0);
    wait_for("user kinematics", || bit(&h, "kinstype.is-2"));
    h.stop();
}
