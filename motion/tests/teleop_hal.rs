//! Teleop and coordinated mode through HAL: `motmod` in a running servo
//! thread, commands through the shared-memory channel, and the mode and
//! `axis.L.*` pins (teleop planner, keyboard and wheel jogs) read back.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::time::Duration;

mod common;

use common::*;
use hal_core::Value;
use motion::{Command, MotionClient, Reject};

#[test]
fn teleop_jogs_through_the_channel_drive_the_axis_and_mode_pins() {
    // Long: one scenario through the channel, each step checked as it goes.
    let h = host("tel-run");
    loadrt(&h, "trivkins", &["coordinates=xyz"]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3"]).unwrap();
    let inst = h.instance();
    loop_back_motors(&h, 3);
    start_motion(&h);
    let mut c = MotionClient::open(inst)
        .unwrap()
        .with_timeout(Duration::from_secs(2));
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
            Command::SetAxisPositionLimits {
                axis: j,
                min: -5.0,
                max: 5.0,
            },
            Command::SetAxisVelLimit { axis: j, vel: 10.0 },
            Command::SetAxisAccLimit {
                axis: j,
                acc: 200.0,
            },
        ] {
            c.send(cmd).unwrap();
        }
    }
    // Asked for while disabled: remembered, shown on the pin already.
    c.send(Command::Teleop).unwrap();
    wait_for("the teleop flag", || bit(&h, "motion.teleop-mode"));
    let s = c.status().unwrap();
    assert_eq!((s.mode, s.teleop_mode), ("DISABLED", true));
    let r = c
        .send(Command::AxisJogCont { axis: 0, vel: 1.0 })
        .unwrap_err();
    assert_eq!(r.reason, Reject::NotEnabled);
    c.send(Command::Enable).unwrap();
    wait_for("teleop mode", || c.status().unwrap().mode == "TELEOP");
    assert!(bit(&h, "motion.motion-enabled") && !bit(&h, "motion.coord-mode"));
    let r = c.send(Command::JogCont { joint: 0, vel: 1.0 }).unwrap_err();
    assert_eq!(r.reason, Reject::JointJogInTeleop);
    assert_eq!(r.code(), 33);
    let r = c
        .send(Command::AxisJogCont { axis: 4, vel: 1.0 })
        .unwrap_err();
    assert_eq!(r.reason, Reject::AxisNotInKinematics { axis: 4 });
    assert!(r.to_string().contains("axis B is not one"), "{r}");

    // A keyboard jog of Y.
    c.send(Command::AxisJogIncr {
        axis: 1,
        vel: 4.0,
        offset: 1.5,
    })
    .unwrap();
    // Refused while the jog runs (the jog lasts about 0.4 s).
    let r = c.send(Command::Free).unwrap_err();
    assert_eq!(r.reason, Reject::NotInPosition);
    wait_for("the jog to start", || !bit(&h, "motion.in-position"));
    assert!(bit(&h, "axis.y.kb-jog-active") && bit(&h, "axis.y.teleop-tp-enable"));
    assert!(bit(&h, "motion.jog-is-active"));
    assert_eq!(float(&h, "axis.y.teleop-pos-cmd"), 1.5);
    assert_eq!(float(&h, "axis.y.teleop-vel-lim"), 4.0);
    wait_for("cruise", || {
        float(&h, "axis.y.teleop-vel-cmd") == 4.0
            && (float(&h, "motion.current-vel") - 4.0).abs() < 1e-9
    });
    wait_for("the jog to end", || bit(&h, "motion.in-position"));
    assert!(!bit(&h, "axis.y.kb-jog-active") && !bit(&h, "motion.jog-is-active"));
    assert!((float(&h, "joint.1.pos-cmd") - 1.5).abs() < 1e-6);
    assert_eq!(
        float(&h, "axis.y.pos-cmd"),
        float(&h, "joint.1.pos-cmd"),
        "axis.L.pos-cmd is the pose"
    );
    assert_eq!(
        float(&h, "joint.1.coarse-pos-cmd"),
        float(&h, "joint.1.pos-cmd")
    );
    let s = c.status().unwrap();
    assert!(s.axes[1].in_kinematics && !s.axes[3].in_kinematics);
    assert_eq!(s.axes[1].pos_cmd, s.joints[1].pos_cmd);

    // A wheel on X.
    inst.set_pin("axis.x.jog-scale", Value::Float(0.01))
        .unwrap();
    inst.set_pin("axis.x.jog-enable", Value::Bit(true)).unwrap();
    inst.set_pin("axis.x.jog-counts", Value::S32(-40)).unwrap();
    wait_for("the wheel jog", || bit(&h, "axis.x.wheel-jog-active"));
    wait_for("the wheel jog to end", || {
        !bit(&h, "axis.x.wheel-jog-active") && bit(&h, "motion.in-position")
    });
    assert!((float(&h, "joint.0.pos-cmd") + 0.4).abs() < 1e-6);
    assert_eq!(float(&h, "axis.x.teleop-pos-cmd"), -0.4);

    // Coordinated mode holds.
    c.send(Command::Coord).unwrap();
    wait_for("coordinated mode", || bit(&h, "motion.coord-mode"));
    assert!(!bit(&h, "motion.teleop-mode"));
    assert_eq!(c.status().unwrap().mode, "COORD");
    let y = float(&h, "joint.1.pos-cmd");
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(float(&h, "joint.1.pos-cmd"), y);
    assert!(bit(&h, "motion.in-position"));
    let r = c
        .send(Command::AxisJogCont { axis: 1, vel: 1.0 })
        .unwrap_err();
    assert_eq!(r.reason, Reject::NotTeleopMode);

    // Kept over a disable, left for free mode.
    c.send(Command::Disable).unwrap();
    wait_for("disabled", || !bit(&h, "motion.motion-enabled"));
    assert!(bit(&h, "motion.coord-mode"));
    c.send(Command::Free).unwrap();
    wait_for("the coord flag to drop", || !bit(&h, "motion.coord-mode"));
    c.send(Command::Enable).unwrap();
    wait_for("free mode", || c.status().unwrap().mode == "FREE");
    h.stop();
}
