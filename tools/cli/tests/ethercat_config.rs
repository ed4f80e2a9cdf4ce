//! configs/sim/ethercat.hal: linuxcnc-ethercat's configuration loaded
//! by `loadrt lcec` on a simulated segment; motmod homes three CiA 402
//! drives through their own homing and jogs two of them; the segment is
//! in OP, no drive faulted, and the EL2008 shows motion enabled.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

/// The value column of `show pin` for pin `name`.
fn value<'a>(stdout: &'a str, name: &str) -> &'a str {
    stdout
        .lines()
        .find(|l| l.split_whitespace().nth(4) == Some(name))
        .and_then(|l| l.split_whitespace().nth(3))
        .unwrap_or_else(|| panic!("no pin {name} in\n{stdout}"))
}

#[test]
fn motion_homes_and_moves_three_ethercat_drives() {
    let dir = common::root().join("configs/sim");
    let out = common::halrun(&dir, &["-f", "ethercat.hal"], "ethercat");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(value(&stdout, "lcec.all-op"), "TRUE");
    assert_eq!(value(&stdout, "lcec.0.slaves-responding"), "0x00000006");
    assert_eq!(value(&stdout, "lcec.0.dout.dout-0"), "TRUE");
    for (j, axis, want) in [(0, "x", 10.0), (1, "y", -5.0), (2, "z", -1.0)] {
        assert_eq!(
            value(&stdout, &format!("joint.{j}.homed")),
            "TRUE",
            "joint {j} homed"
        );
        let pos: f64 = value(&stdout, &format!("joint.{j}.pos-fb"))
            .parse()
            .unwrap();
        assert!((pos - want).abs() < 0.01, "joint {j} at {pos}, not {want}");
        let fb: f64 = value(&stdout, &format!("lcec.0.{axis}.srv-actual-position"))
            .parse()
            .unwrap();
        assert!((fb - want).abs() < 0.01, "drive {axis} reports {fb}");
        for (pin, want) in [
            ("srv-enabled", "TRUE"),
            ("srv-fault", "FALSE"),
            ("srv-home-complete", "TRUE"),
        ] {
            assert_eq!(
                value(&stdout, &format!("lcec.0.{axis}.{pin}")),
                want,
                "drive {axis} {pin}"
            );
        }
    }
}

/// configs/sim/ethercat-io.hal: the terminals and a generic slave laid
/// out by its XML, on a simulated segment with distributed clocks.
#[test]
fn terminals_and_a_generic_slave_exchange_data() {
    let dir = common::root().join("configs/sim");
    let out = common::halrun(&dir, &["-f", "ethercat-io.hal"], "ethercat-io");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(value(&stdout, "lcec.all-op"), "TRUE");
    assert_eq!(value(&stdout, "lcec.0.slaves-responding"), "0x00000006");
    assert_eq!(value(&stdout, "lcec.0.aout.aout-0-raw"), "8192");
    assert_eq!(value(&stdout, "lcec.0.stepper.srv-raw-cmd"), "16383");
    assert_eq!(value(&stdout, "lcec.0.stepper.srv-move-pos"), "TRUE");
    let count: i64 = value(&stdout, "lcec.0.stepper.enc-count").parse().unwrap();
    assert!(count > 0, "the stepper's encoder counts: {count}");
    let level: f64 = value(&stdout, "lcec.0.io.level").parse().unwrap();
    assert!((level - 12.34).abs() < 1e-9, "level {level}");
    assert_eq!(value(&stdout, "lcec.0.io.lamp-on"), "TRUE");
}
