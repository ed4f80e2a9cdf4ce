//! The kinematics modules of LinuxCNC's Scorbot ER-3, rotary-table and
//! template configurations, and LinuxCNC 2.7's gantrykins, through HAL:
//! what `loadrt` exports (names, types, directions and values as
//! LinuxCNC's modules export them), parameters read at every call, and
//! refused module parameters.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::*;
use hal_core::{HalError, Host, Value};
use motion::kins::{kinematics_for, Kinematics};
use motion::{KinematicsType, KinsError, KinsFlags, Pose};

/// The pins and params the component `comp` owns, one line each as
/// `TYPE DIR VALUE NAME`, sorted by name.
fn exports(h: &Host, comp: &str) -> Vec<String> {
    let inst = h.instance();
    let pins = inst
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == comp)
        .map(|p| {
            (
                p.name,
                format!("{:?} {} {:?}", p.hal_type, p.dir.label(), p.value),
            )
        });
    let params = inst
        .params()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == comp)
        .map(|p| {
            (
                p.name,
                format!("{:?} {} {:?}", p.hal_type, p.dir.label(), p.value),
            )
        });
    let mut v: Vec<(String, String)> = pins.chain(params).collect();
    v.sort();
    v.into_iter().map(|(n, l)| format!("{l} {n}")).collect()
}

fn kins(h: &Host) -> std::sync::Arc<dyn Kinematics> {
    kinematics_for(h.instance().name())
        .expect("kinematics registered")
        .1
}

fn inverse(k: &dyn Kinematics, axes: &[f64], n: usize) -> Result<Vec<f64>, KinsError> {
    let mut p = Pose::ZERO;
    p.0[..axes.len()].copy_from_slice(axes);
    let mut j = vec![0.0; n];
    k.inverse(&p, &mut j, &mut KinsFlags::default())?;
    Ok(j)
}

fn forward(k: &dyn Kinematics, joints: &[f64]) -> Pose {
    let mut p = Pose::ZERO;
    k.forward(joints, &mut p, &mut KinsFlags::default())
        .unwrap();
    p
}

fn sorted(items: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = items.iter().map(|s| s.to_string()).collect();
    v.sort_by(|a, b| a.rsplit(' ').next().cmp(&b.rsplit(' ').next()));
    v
}

#[test]
fn modules_export_what_linuxcnc_exports() {
    let gantry: Vec<String> = [0, 1, 2, 3, 4, 5, -1, -1, -1]
        .iter()
        .enumerate()
        .map(|(i, a)| format!("S32 RW S32({a}) gantrykins.joint-{i}"))
        .collect();
    let mut cases: Vec<(&str, Vec<String>, KinematicsType)> = vec![
        ("scorbot-kins", vec![], KinematicsType::Both),
        ("rotatekins", vec![], KinematicsType::Both),
        (
            "userkins",
            sorted(&[
                "S32 OUT S32(0) userkins.0.fdemo.time",
                "S32 RW S32(0) userkins.0.fdemo.tmax",
                "Bit RO Bit(false) userkins.0.fdemo.tmax-increased",
                "S32 OUT S32(0) userkins.0.fpin",
                "U32 IN U32(0) userkins.in",
                "U32 OUT U32(0) userkins.out",
                "Float RO Float(0.0) userkins.param-ro",
                "Float RW Float(0.0) userkins.param-rw",
            ]),
            KinematicsType::Identity,
        ),
        ("gantrykins", gantry, KinematicsType::Both),
        ("gentrivkins", vec![], KinematicsType::Identity),
        (
            "matrixkins",
            sorted(&[
                "Bit OUT Bit(true) matrixkins.0.dummy",
                "Float RW Float(1.0) matrixkins.C_xx",
                "Float RW Float(0.0) matrixkins.C_xy",
                "Float RW Float(0.0) matrixkins.C_xz",
                "Float RW Float(0.0) matrixkins.C_yx",
                "Float RW Float(1.0) matrixkins.C_yy",
                "Float RW Float(0.0) matrixkins.C_yz",
                "Float RW Float(0.0) matrixkins.C_zx",
                "Float RW Float(0.0) matrixkins.C_zy",
                "Float RW Float(1.0) matrixkins.C_zz",
            ]),
            KinematicsType::Both,
        ),
    ];
    let three21 = sorted(&[
        "Float IN Float(64.2) three21kins.A1",
        "Float IN Float(305.0) three21kins.A2",
        "Float IN Float(0.0) three21kins.A3",
        "Float IN Float(169.77) three21kins.D1",
        "Float IN Float(0.0) three21kins.D2",
        "Float IN Float(-6.25) three21kins.D3",
        "Float IN Float(223.63) three21kins.D4",
        "Float IN Float(36.5) three21kins.D6",
        "Bit OUT Bit(true) kinstype.is-0",
        "Bit OUT Bit(false) kinstype.is-1",
        "Bit OUT Bit(false) kinstype.is-2",
    ]);
    cases.push(("three21kins", three21, KinematicsType::Both));
    for (module, want, kins_type) in cases {
        let h = host(&format!("kmore-{module}"));
        loadrt(&h, module, &[]).unwrap();
        assert_eq!(h.loaded_components(), [module]);
        assert_eq!(exports(&h, module), want, "{module}");
        let k = kins(&h);
        assert_eq!(k.name(), module);
        assert_eq!(k.kins_type(), kins_type, "{module}");
        assert_eq!(k.is_switchable(), module == "three21kins", "{module}");
        h.unloadrt(module).unwrap();
        assert!(kinematics_for(h.instance().name()).is_none());
    }
}

#[test]
fn scorbot_reaches_round_its_base_and_refuses_what_it_cannot_reach() {
    let h = host("kmore-scorbot");
    loadrt(&h, "scorbot-kins", &[]).unwrap();
    let k = kins(&h);
    let pose = [150.0, -220.0, 260.0, 10.0, -30.0];
    let j = inverse(&*k, &pose, 5).unwrap();
    let back = forward(&*k, &j);
    assert!(
        back.0.iter().zip(pose).all(|(a, b)| (a - b).abs() < 1e-9),
        "{back:?}"
    );
    assert_eq!(back.0[5..], [0.0; 4]);
    assert_eq!(
        inverse(&*k, &[500.0, 0.0, 140.0, 0.0, 0.0], 5),
        Err(KinsError::NoSolution)
    );
}

#[test]
fn gantry_parameters_are_read_at_every_call() {
    let h = host("kmore-gantry");
    // stepper-gantry's kinematics.hal, after a plain load.
    loadrt(&h, "gantrykins", &[]).unwrap();
    let k = kins(&h);
    let pose = [1.0, 2.0, 3.0, 4.0];
    assert_eq!(inverse(&*k, &pose, 4).unwrap(), [1.0, 2.0, 3.0, 4.0]);
    h.instance()
        .set_param("gantrykins.joint-3", Value::S32(1))
        .unwrap();
    assert_eq!(inverse(&*k, &pose, 4).unwrap(), [1.0, 2.0, 3.0, 2.0]);
    assert_eq!(k.has_axis(3), Some(false));
    let back = forward(&*k, &[1.0, 2.0, 3.0, 2.0]);
    assert_eq!(back.0[..4], [1.0, 2.0, 3.0, 0.0]);
    // coordinates= sets the same map at load.
    h.unloadrt("gantrykins").unwrap();
    loadrt(&h, "gantrykins", &["coordinates=xyzy"]).unwrap();
    assert_eq!(
        h.instance().param_value("gantrykins.joint-3").unwrap(),
        Value::S32(1)
    );
}

#[test]
fn matrix_coefficients_are_read_at_every_call() {
    let h = host("kmore-matrix");
    loadrt(&h, "matrixkins", &[]).unwrap();
    let k = kins(&h);
    let pose = [10.0, 20.0, 30.0];
    assert_eq!(inverse(&*k, &pose, 3).unwrap(), pose);
    // LinuxCNC's matrixkins test: Z skewed by X and Y.
    let inst = h.instance();
    inst.set_param("matrixkins.C_zx", Value::Float(0.01))
        .unwrap();
    inst.set_param("matrixkins.C_zy", Value::Float(0.03))
        .unwrap();
    let j = inverse(&*k, &pose, 3).unwrap();
    assert!((j[2] - (30.0 + 0.1 + 0.6)).abs() < 1e-12, "{j:?}");
    let back = forward(&*k, &j);
    assert!(back.0[..3]
        .iter()
        .zip(pose)
        .all(|(a, b)| (a - b).abs() < 1e-9));
    // A singular matrix: the forward kinematics refuse.
    inst.set_param("matrixkins.C_zz", Value::Float(0.0))
        .unwrap();
    inst.set_param("matrixkins.C_zx", Value::Float(0.0))
        .unwrap();
    inst.set_param("matrixkins.C_zy", Value::Float(0.0))
        .unwrap();
    let mut p = Pose::ZERO;
    assert_eq!(
        k.forward(&j, &mut p, &mut KinsFlags::default()),
        Err(KinsError::NoSolution)
    );
}

#[test]
fn three21kins_reads_its_dimensions_and_switches() {
    let h = host("kmore-three21");
    loadrt(&h, "three21kins", &["sparm=identityfirst"]).unwrap();
    let k = kins(&h);
    // identityfirst: type 0 is identity, type 1 the arm.
    let home = [369.2, -6.25, -90.36, 0.0, 0.0, 0.0];
    assert_eq!(inverse(&*k, &home, 6).unwrap(), home);
    k.switch_to(1).unwrap();
    let at_zero = forward(&*k, &[0.0; 6]);
    assert!((at_zero.0[0] - 369.2).abs() < 1e-9, "{at_zero:?}");
    h.instance()
        .set_pin("three21kins.A1", Value::Float(0.0))
        .unwrap();
    let moved = forward(&*k, &[0.0; 6]);
    assert!((moved.0[0] - 305.0).abs() < 1e-9, "{moved:?}");
    let j = inverse(&*k, &moved.0[..6], 6).unwrap();
    assert!(j.iter().all(|v| v.abs() < 1e-6), "{j:?}");
}

#[test]
fn trsrn_modules_export_what_linuxcnc_exports_and_switch_three_ways() {
    for (module, comp_prefix, l) in [
        ("xyzacb_trsrn", "xyzacb-trsrn", 'y'),
        ("xyzbca_trsrn", "xyzbca-trsrn", 'x'),
    ] {
        let h = host(&format!("kmore-{module}"));
        loadrt(&h, module, &[]).unwrap();
        let p = format!("{module}_kins");
        let mut want: Vec<String> = [
            format!("S32 OUT S32(0) {comp_prefix}.0.fdemo.time"),
            format!("S32 RW S32(0) {comp_prefix}.0.fdemo.tmax"),
            format!("Bit RO Bit(false) {comp_prefix}.0.fdemo.tmax-increased"),
            format!("S32 OUT S32(0) {comp_prefix}.0.fpin"),
            format!("U32 IN U32(0) {p}.in"),
            format!("U32 OUT U32(0) {p}.out"),
            "Bit OUT Bit(true) kinstype.is-0".into(),
            "Bit OUT Bit(false) kinstype.is-1".into(),
            "Bit OUT Bit(false) kinstype.is-2".into(),
        ]
        .into_iter()
        .chain(
            [
                "tool-offset-z".to_string(),
                format!("{l}-pivot"),
                "z-pivot".into(),
                "x-offset".into(),
                "y-offset".into(),
                format!("{l}-rot-axis"),
                "z-rot-axis".into(),
                "pre-rot".into(),
                "nut-angle".into(),
                "primary-angle".into(),
                "secondary-angle".into(),
            ]
            .map(|n| format!("Float IN Float(0.0) {p}.{n}")),
        )
        .collect();
        want.sort_by(|a, b| a.rsplit(' ').next().cmp(&b.rsplit(' ').next()));
        assert_eq!(exports(&h, module), want, "{module}");
        let k = kins(&h);
        assert!(k.is_switchable());
        assert_eq!(k.kins_type(), KinematicsType::Both);
        let inst = h.instance();
        inst.set_pin(&format!("{p}.z-pivot"), Value::Float(100.0))
            .unwrap();
        inst.set_pin(&format!("{p}.nut-angle"), Value::Float(45.0))
            .unwrap();
        inst.set_pin(&format!("{p}.primary-angle"), Value::Float(30.0))
            .unwrap();
        inst.set_pin(&format!("{p}.in"), Value::U32(4)).unwrap();
        let pose = [10.0, 20.0, 30.0, 15.0, 25.0, 35.0];
        assert_eq!(inverse(&*k, &pose, 6).unwrap(), pose, "type 0 is identity");
        assert_eq!(inst.pin_value(&format!("{p}.out")).unwrap(), Value::U32(4));
        for t in [1, 2] {
            k.switch_to(t).unwrap();
            let j = inverse(&*k, &pose, 6).unwrap();
            assert_ne!(j[..3], pose[..3], "{module} type {t}");
            let back = forward(&*k, &j);
            assert!(
                back.0.iter().zip(pose).all(|(a, b)| (a - b).abs() < 1e-9),
                "{module} type {t}: {back:?}"
            );
        }
        let is = |i: usize| inst.pin_value(&format!("kinstype.is-{i}")).unwrap();
        assert_eq!([is(0), is(1), is(2)], [false, false, true].map(Value::Bit));
        assert!(k.switch_to(3).is_err());
    }
}

#[test]
fn gentrivkins_takes_trivkins_parameters() {
    let h = host("kmore-gentriv");
    loadrt(&h, "gentrivkins", &["coordinates=xyzy", "kinstype=b"]).unwrap();
    let k = kins(&h);
    assert_eq!(k.kins_type(), KinematicsType::Both);
    assert_eq!(
        inverse(&*k, &[1.0, 2.0, 3.0], 4).unwrap(),
        [1.0, 2.0, 3.0, 2.0]
    );
    assert_eq!(k.has_axis(3), Some(false));
}

#[test]
fn userkins_echoes_its_pin_and_runs_its_demo_function() {
    let h = host("kmore-userkins");
    loadrt(&h, "userkins", &["names=ua,ub"]).unwrap();
    let k = kins(&h);
    h.instance().set_pin("userkins.in", Value::U32(9)).unwrap();
    assert_eq!(inverse(&*k, &[1.0, 2.0, 3.0], 3).unwrap(), [1.0, 2.0, 3.0]);
    assert_eq!(
        h.instance().pin_value("userkins.out").unwrap(),
        Value::U32(9)
    );
    h.create_thread("demo-thread", 1_000_000, true, None)
        .unwrap();
    h.addf("ub.fdemo", "demo-thread", -1).unwrap();
    h.start().unwrap();
    wait_for(
        "fdemo runs",
        || matches!(h.instance().pin_value("ub.fpin").unwrap(), Value::S32(n) if n >= 3),
    );
    assert_eq!(h.instance().pin_value("ua.fpin").unwrap(), Value::S32(0));
}

#[test]
fn bad_module_parameters_name_the_parameter_and_leave_nothing() {
    let h = host("kmore-bad");
    for (module, args, param) in [
        ("gantrykins", &["coordinates=xyq"][..], "coordinates"),
        ("gantrykins", &["coordinates=xyzabcuvwx"][..], "coordinates"),
        ("scorbot-kins", &["coordinates=xyz"][..], "coordinates"),
        ("rotatekins", &["kinstype=b"][..], "kinstype"),
        ("gentrivkins", &["kinstype=q"][..], "kinstype"),
        ("gentrivkins", &["coordinates=x-y"][..], "coordinates"),
        ("matrixkins", &["coordinates=xyz"][..], "coordinates"),
    ] {
        match loadrt(&h, module, args) {
            Err(HalError::ModuleParam { param: p, .. }) => assert_eq!(p, param, "{module}"),
            other => panic!("{module} {args:?}: {other:?}"),
        }
        assert!(h.loaded_components().is_empty());
        assert!(kinematics_for(h.instance().name()).is_none());
    }
}
