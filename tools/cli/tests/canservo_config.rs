//! configs/sim/canservo.hal: motmod drives three simulated CiA 402 axes
//! in CSP, homes them through the drives' internal homing, and jogs two
//! of them; every joint ends homed where it was sent, no drive faulted.

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
fn motion_homes_and_moves_three_can_servo_axes() {
    let dir = common::root().join("configs/sim");
    let out = common::halrun(&dir, &["-f", "canservo.hal"], "canservo");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (j, want) in [(0, 10.0), (1, -5.0), (2, -1.0)] {
        assert_eq!(
            value(&stdout, &format!("joint.{j}.homed")),
            "TRUE",
            "joint {j} homed"
        );
        let pos: f64 = value(&stdout, &format!("joint.{j}.pos-fb"))
            .parse()
            .unwrap();
        assert!((pos - want).abs() < 0.01, "joint {j} at {pos}, not {want}");
        let fb: f64 = value(&stdout, &format!("canservo.{j}.position-fb"))
            .parse()
            .unwrap();
        assert!((fb - want).abs() < 0.01, "drive {j} reports {fb}");
        assert_eq!(
            value(&stdout, &format!("canservo.{j}.state")),
            "5",
            "drive {j} enabled"
        );
        assert_eq!(value(&stdout, &format!("canservo.{j}.amp-fault")), "FALSE");
        assert_eq!(
            value(&stdout, &format!("canservo.{j}.home-complete")),
            "TRUE",
            "drive {j} homed itself"
        );
    }
}
