//! SET_OFFSET through HAL: `motmod` in a running servo thread shows the
//! tool offset task gives it on `motion.tooloffset.L` (LinuxCNC's pins,
//! for kinematics and HAL logic that follow the tool tip), and refuses
//! one that is not finite, keeping the last.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::time::Duration;

mod common;

use common::*;
use motion::{Command, MotionClient, Pose};

#[test]
fn the_tool_offset_shows_on_the_tooloffset_pins() {
    let h = host("tooloffset");
    loadrt(&h, "trivkins", &["coordinates=xyz"]).unwrap();
    loadrt(&h, "motmod", &["num_joints=3"]).unwrap();
    start_motion(&h);
    let mut c = MotionClient::open(h.instance())
        .unwrap()
        .with_timeout(Duration::from_secs(2));
    assert_eq!(float(&h, "motion.tooloffset.z"), 0.0);
    let offset = Pose([0.0, 0.0, 1.25, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5]);
    c.send(Command::SetToolOffset { offset }).unwrap();
    wait_for("the tool offset on the pins", || {
        float(&h, "motion.tooloffset.z") == 1.25 && float(&h, "motion.tooloffset.w") == -0.5
    });
    let mut bad = offset;
    bad.0[2] = f64::NAN;
    assert!(c.send(Command::SetToolOffset { offset: bad }).is_err());
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(float(&h, "motion.tooloffset.z"), 1.25);
    assert_eq!(float(&h, "motion.tooloffset.x"), 0.0);
}
