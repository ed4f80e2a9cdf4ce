//! The kinematics modules of LinuxCNC's five-axis, pentapod, rose-engine
//! and mill-turn sim machines through HAL: what `loadrt` exports (names,
//! types, directions and values as LinuxCNC 2.9's modules export them),
//! that the geometry is read at every call, the switches, and the
//! modules' own outputs.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::*;
use hal_core::{Host, Value};
use motion::kins::{kinematics_for, Kinematics};
use motion::{KinematicsType, KinsFlags, Pose};

/// The pins and params the component `comp` owns, one line each as
/// `TYPE DIR VALUE NAME`, sorted by name.
fn exports(h: &Host, comp: &str) -> Vec<String> {
    let inst = h.instance();
    let mut v: Vec<(String, String)> = inst
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == comp)
        .map(|p| {
            let line = format!("{:?} {} {:?}", p.hal_type, p.dir.label(), p.value);
            (p.name, line)
        })
        .chain(
            inst.params()
                .unwrap()
                .into_iter()
                .filter(|p| p.owner == comp)
                .map(|p| {
                    let line = format!("{:?} {} {:?}", p.hal_type, p.dir.label(), p.value);
                    (p.name, line)
                }),
        )
        .collect();
    v.sort();
    v.into_iter().map(|(n, l)| format!("{l} {n}")).collect()
}

fn kins(h: &Host) -> std::sync::Arc<dyn Kinematics> {
    kinematics_for(h.instance().name())
        .expect("kinematics registered")
        .1
}

fn inverse(k: &dyn Kinematics, axes: &[f64], n: usize) -> Vec<f64> {
    let mut p = Pose::ZERO;
    p.0[..axes.len()].copy_from_slice(axes);
    let mut j = vec![0.0; n];
    k.inverse(&p, &mut j, &mut KinsFlags::default()).unwrap();
    j
}

fn forward(k: &dyn Kinematics, joints: &[f64]) -> Pose {
    let mut p = Pose::ZERO;
    k.forward(joints, &mut p, &mut KinsFlags::default())
        .unwrap();
    p
}

fn lines(items: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = items.iter().map(|s| s.to_string()).collect();
    v.sort_by(|a, b| a.rsplit(' ').next().cmp(&b.rsplit(' ').next()));
    v
}

#[test]
fn modules_export_what_linuxcnc_exports() {
    let penta: Vec<String> = (0..5)
        .flat_map(|i| {
            let base = [
                [-418.03, 324.56, 895.56],
                [417.96, 324.56, 895.56],
                [-418.03, -325.44, 895.56],
                [417.96, -325.44, 895.56],
                [-0.06, -492.96, 895.56],
            ][i];
            let z = [-185.5, -159.5, -67.5, -41.5, -14.0][i];
            vec![
                format!("Float RW Float({:?}) pentakins.base.{i}.x", base[0]),
                format!("Float RW Float({:?}) pentakins.base.{i}.y", base[1]),
                format!("Float RW Float({:?}) pentakins.base.{i}.z", base[2]),
                format!("Float RW Float(80.32) pentakins.effector.{i}.r"),
                format!("Float RW Float({z:?}) pentakins.effector.{i}.z"),
            ]
        })
        .chain(
            [
                "Float I/O Float(1e-9) pentakins.convergence-criterion",
                "U32 OUT U32(0) pentakins.last-iterations",
                "U32 I/O U32(120) pentakins.limit-iterations",
                "Float I/O Float(100.0) pentakins.max-error",
                "U32 OUT U32(0) pentakins.max-iterations",
                "Float IN Float(0.0) pentakins.tool-offset",
            ]
            .map(String::from),
        )
        .collect();
    let cases: Vec<(&str, Vec<String>, bool)> = vec![
        (
            "5axiskins",
            lines(&[
                "Float IN Float(250.0) 5axiskins.pivot-length",
                "Bit OUT Bit(true) kinstype.is-0",
                "Bit OUT Bit(false) kinstype.is-1",
                "Bit OUT Bit(false) kinstype.is-2",
            ]),
            true,
        ),
        (
            "maxkins",
            lines(&["Float I/O Float(0.666) maxkins.pivot-length"]),
            false,
        ),
        (
            "rosekins",
            lines(&[
                "Float OUT Float(0.0) rosekins.bigtheta_degrees",
                "Float OUT Float(0.0) rosekins.revolutions",
                "Float OUT Float(0.0) rosekins.theta_degrees",
            ]),
            false,
        ),
        (
            "pentakins",
            lines(&penta.iter().map(|s| s.as_str()).collect::<Vec<_>>()),
            false,
        ),
        (
            "xyzab_tdr_kins",
            lines(&[
                "S32 OUT S32(0) xyzab-tdr-kins.0.dummy",
                "Float IN Float(0.0) xyzab_tdr_kins.tool-offset-z",
                "Float IN Float(0.0) xyzab_tdr_kins.x-offset",
                "Float IN Float(0.0) xyzab_tdr_kins.x-rot-point",
                "Float IN Float(0.0) xyzab_tdr_kins.y-rot-point",
                "Float IN Float(0.0) xyzab_tdr_kins.z-offset",
                "Float IN Float(0.0) xyzab_tdr_kins.z-rot-point",
                "Bit OUT Bit(true) kinstype.is-0",
                "Bit OUT Bit(false) kinstype.is-1",
            ]),
            true,
        ),
        (
            "millturn",
            lines(&[
                "S32 OUT S32(0) millturn.0.fdemo.time",
                "S32 RW S32(0) millturn.0.fdemo.tmax",
                "Bit RO Bit(false) millturn.0.fdemo.tmax-increased",
                "S32 OUT S32(0) millturn.0.fpin",
                "U32 IN U32(0) millturn.in",
                "U32 OUT U32(0) millturn.out",
                "Float RO Float(0.0) millturn.param-ro",
                "Float RW Float(0.0) millturn.param-rw",
                "Bit OUT Bit(true) kinstype.is-0",
                "Bit OUT Bit(false) kinstype.is-1",
            ]),
            true,
        ),
    ];
    for (module, want, switchable) in cases {
        let h = host(&format!("ksim-{module}"));
        loadrt(&h, module, &[]).unwrap();
        assert_eq!(h.loaded_components(), [module]);
        assert_eq!(exports(&h, module), want, "{module}");
        let k = kins(&h);
        assert_eq!(k.name(), module);
        assert_eq!(k.kins_type(), KinematicsType::Both, "{module}");
        assert_eq!(k.is_switchable(), switchable, "{module}");
        h.unloadrt(module).unwrap();
        assert!(kinematics_for(h.instance().name()).is_none());
    }
}

#[test]
fn geometry_is_read_at_every_call() {
    // (module, joints, pose, pin or param, new value)
    let cases: [(&str, usize, &[f64], &str, f64); 3] = [
        (
            "5axiskins",
            6,
            &[10.0, 20.0, 30.0, 0.0, 30.0, 45.0],
            "5axiskins.pivot-length",
            100.0,
        ),
        (
            "maxkins",
            6,
            &[10.0, 20.0, 30.0, 0.0, 30.0, 45.0],
            "maxkins.pivot-length",
            50.8,
        ),
        (
            "pentakins",
            5,
            &[10.0, 20.0, 30.0, 3.0, 4.0],
            "pentakins.base.2.y",
            450.0,
        ),
    ];
    for (module, n, pose, item, value) in cases {
        let h = host(&format!("ksimgeom-{module}"));
        loadrt(&h, module, &[]).unwrap();
        let k = kins(&h);
        let before = inverse(&*k, pose, n);
        let inst = h.instance();
        if inst.param(item).unwrap().is_some() {
            inst.set_param(item, Value::Float(value)).unwrap();
        } else {
            inst.set_pin(item, Value::Float(value)).unwrap();
        }
        let after = inverse(&*k, pose, n);
        assert_ne!(before, after, "{module}: {item}");
        let mut back = Pose::ZERO;
        back.0[..pose.len()].copy_from_slice(pose);
        k.forward(&after, &mut back, &mut KinsFlags::default())
            .unwrap();
        for (a, b) in back.0.iter().zip(pose) {
            assert!((a - b).abs() < 1e-6, "{module}: {back:?}");
        }
    }
}

#[test]
fn table_dual_rotary_switches_to_tool_centre_point() {
    let h = host("ksimtdr");
    loadrt(&h, "xyzab_tdr_kins", &["names=tdr-a,tdr-b"]).unwrap();
    assert_eq!(
        h.instance().pin_value("tdr-b.dummy").unwrap(),
        Value::S32(0)
    );
    let k = kins(&h);
    h.instance()
        .set_pin("xyzab_tdr_kins.z-offset", Value::Float(20.0))
        .unwrap();
    let pose = [10.0, 20.0, 30.0, 15.0, 25.0];
    assert_eq!(inverse(&*k, &pose, 5), pose, "type 0 is identity");
    k.switch_to(1).unwrap();
    assert!(!bit(&h, "kinstype.is-0") && bit(&h, "kinstype.is-1"));
    let j = inverse(&*k, &pose, 5);
    assert_ne!(j, pose);
    let back = forward(&*k, &j);
    assert!(back.0.iter().zip(pose).all(|(a, b)| (a - b).abs() < 1e-9));
    // A type the module does not have is refused and changes nothing.
    assert!(k.switch_to(2).is_err());
    assert!(bit(&h, "kinstype.is-1"));
}

#[test]
fn millturn_turns_and_runs_its_demo_function() {
    let h = host("ksimmillturn");
    loadrt(&h, "millturn", &["count=2"]).unwrap();
    let k = kins(&h);
    k.switch_to(1).unwrap();
    assert_eq!(
        forward(&*k, &[1.0, 2.0, 3.0, 4.0]).0[..4],
        [3.0, -2.0, 1.0, 4.0]
    );
    // The inverse copies `in` to `out`.
    h.instance().set_pin("millturn.in", Value::U32(7)).unwrap();
    inverse(&*k, &[3.0, -2.0, 1.0, 4.0], 4);
    assert_eq!(
        h.instance().pin_value("millturn.out").unwrap(),
        Value::U32(7)
    );
    // fdemo counts its runs on fpin.
    h.create_thread("demo-thread", 1_000_000, true, None)
        .unwrap();
    h.addf("millturn.1.fdemo", "demo-thread", -1).unwrap();
    h.start().unwrap();
    wait_for(
        "fdemo runs",
        || matches!(h.instance().pin_value("millturn.1.fpin").unwrap(), Value::S32(n) if n >= 3),
    );
    assert_eq!(
        h.instance().pin_value("millturn.0.fpin").unwrap(),
        Value::S32(0)
    );
}

#[test]
fn rosekins_reports_turns_on_its_pins() {
    let h = host("ksimrose");
    loadrt(&h, "rosekins", &[]).unwrap();
    let k = kins(&h);
    // Round the spindle one and a half turns counterclockwise.
    let mut j = vec![0.0; 3];
    for step in 0..=54 {
        let a = f64::from(step) * 10.0;
        let (s, c) = a.to_radians().sin_cos();
        j = inverse(&*k, &[5.0 * c, 5.0 * s, 1.0], 3);
    }
    assert!((j[2] - 540.0).abs() < 1e-9, "{j:?}");
    assert_eq!(float(&h, "rosekins.revolutions"), 1.0);
    assert!((float(&h, "rosekins.bigtheta_degrees") - 540.0).abs() < 1e-9);
    assert!((float(&h, "rosekins.theta_degrees").abs() - 180.0).abs() < 1e-9);
}
