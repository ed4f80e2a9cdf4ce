//! External axis offsets through HAL: `motmod` in a running servo thread,
//! a coordinated move queued through the channel, and another thread
//! turning `axis.z.eoffset-counts` as a jog wheel or a height controller
//! would while the move runs. The joint commands carry the offset, the
//! axis and motion pins and the status report it, `eoffset-clear` takes
//! it away again.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::time::Duration;

mod common;

use common::*;
use hal_core::Value;
use motion::command::LineKind;
use motion::{Command, MotionClient, Pose};

/// X Y Z trivkins, homed, in coordinated mode; Z has OFFSET_AV_RATIO 0.2
/// of 10 u/s and 100 u/s².
fn machine(h: &hal_core::Host) -> MotionClient {
    loadrt(h, "trivkins", &["coordinates=xyz"]).unwrap();
    loadrt(h, "motmod", &["num_joints=3"]).unwrap();
    loop_back_motors(h, 3);
    start_motion(h);
    let mut c = MotionClient::open(h.instance())
        .unwrap()
        .with_timeout(Duration::from_secs(2));
    for j in 0..3 {
        for cmd in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -100.0,
                max: 100.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 20.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 500.0,
            },
            Command::SetJointHomingParams {
                joint: j,
                config: motion::homing::HomingConfig {
                    sequence: 0,
                    ..Default::default()
                },
            },
            Command::SetAxisPositionLimits {
                axis: j,
                min: -50.0,
                max: 50.0,
            },
            Command::SetAxisVelLimit { axis: j, vel: 10.0 },
            Command::SetAxisAccLimit {
                axis: j,
                acc: 100.0,
            },
        ] {
            c.send(cmd).unwrap();
        }
    }
    c.send(Command::SetAxisEoffsetRatio {
        axis: 2,
        ratio: 0.2,
    })
    .unwrap();
    c.send(Command::Enable).unwrap();
    wait_for("enabled", || bit(h, "motion.motion-enabled"));
    c.send(Command::Home { joint: -1 }).unwrap();
    wait_for("homed", || bit(h, "motion.is-all-homed"));
    wait_for("coord to be accepted", || c.send(Command::Coord).is_ok());
    wait_for("coord", || c.status().unwrap().mode == "COORD");
    c
}

#[test]
fn an_offset_turned_in_during_a_move_is_added_to_the_joint_commands() {
    let h = host("eoff-move");
    let mut c = machine(&h);
    let inst = h.instance();
    inst.set_pin("axis.z.eoffset-scale", Value::Float(0.01))
        .unwrap();
    inst.set_pin("axis.z.eoffset-enable", Value::Bit(true))
        .unwrap();
    std::thread::sleep(Duration::from_millis(20));
    let mut end = Pose::ZERO;
    end.0[0] = 8.0;
    c.send(Command::Line {
        end,
        vel: 8.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id: 1,
    })
    .unwrap();
    wait_for("the move to start", || float(&h, "joint.0.pos-cmd") > 0.0);
    // 100 counts of 0.01, a count every 2 ms, while X moves.
    let seen_during_move = std::thread::scope(|s| {
        s.spawn(|| {
            for n in 1..=100 {
                inst.set_pin("axis.z.eoffset-counts", Value::S32(n))
                    .unwrap();
                std::thread::sleep(Duration::from_millis(2));
            }
        });
        let mut seen = false;
        while !bit(&h, "motion.in-position") {
            let x = float(&h, "joint.0.pos-cmd");
            let z = float(&h, "joint.2.pos-cmd");
            seen |= x > 0.5 && x < 7.5 && z > 0.1;
            std::thread::sleep(Duration::from_millis(1));
        }
        seen
    });
    assert!(seen_during_move, "Z moved by the offset while X ran");
    assert!((float(&h, "axis.z.eoffset-request") - 1.0).abs() < 1e-9);
    wait_for("the offset to settle", || {
        (float(&h, "axis.z.eoffset") - 1.0).abs() < 1e-6
    });
    assert!((float(&h, "joint.0.pos-cmd") - 8.0).abs() < 1e-9);
    assert!((float(&h, "joint.2.pos-cmd") - 1.0).abs() < 1e-6);
    assert!(
        float(&h, "axis.z.pos-cmd").abs() < 1e-12,
        "axis.L.pos-cmd leaves the offset out"
    );
    assert!(bit(&h, "motion.eoffset-active") && !bit(&h, "motion.eoffset-limited"));
    let st = c.status().unwrap();
    assert!((st.eoffset.applied[2] - 1.0).abs() < 1e-6 && st.eoffset.active);
    assert!((st.eoffset.requested[2] - 1.0).abs() < 1e-9);

    // Clear: the offset goes back to zero at its own limits.
    inst.set_pin("axis.z.eoffset-clear", Value::Bit(true))
        .unwrap();
    wait_for("the offset to clear", || !bit(&h, "motion.eoffset-active"));
    assert!(float(&h, "joint.2.pos-cmd").abs() < 1e-6);
    assert_eq!(float(&h, "axis.z.eoffset-request"), 0.0);
}
