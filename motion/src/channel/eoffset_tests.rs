//! The external-offset block of the status snapshot: appended after the
//! fault block, read back as it was written, zero from an older
//! controller, and shown by the status text.

use super::*;
use crate::command::Command;
use crate::eoffset::EoffsetInputs;
use crate::kins::trivkins::Trivkins;
use crate::kins::KinematicsType;
use crate::test_support::{configure_test_axes, configure_test_joints, Sim};
use crate::{MotionConfig, MotionCore};

/// Trivkins XYZ in teleop, homed, Z offset by 0.75 (request 0.75).
fn offset_z() -> Sim {
    let kins = std::sync::Arc::new(Trivkins::new("xyz", KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(MotionConfig::default(), kins);
    configure_test_joints(&mut m);
    configure_test_axes(&mut m, 50.0);
    let mut s = Sim::new(m);
    s.cmd(Command::SetAxisEoffsetRatio {
        axis: 2,
        ratio: 0.5,
    })
    .unwrap();
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.enable();
    s.cmd(Command::Teleop).unwrap();
    let mut pins = EoffsetInputs {
        enable: true,
        clear: false,
        counts: 0,
        scale: 0.25,
    };
    s.m.axis_inputs[2].eoffset = pins;
    s.cycle();
    pins.counts = 3;
    s.m.axis_inputs[2].eoffset = pins;
    s.run(2000);
    s
}

#[test]
fn the_offsets_are_reported_after_the_fault_block() {
    assert_eq!(EOFFSET_START, FAULT_START + crate::FAULT_WORDS);
    assert_eq!(PATH_START, EOFFSET_START + EOFFSET_WORDS);
    assert_eq!(STATUS_WORDS, PATH_START + PATH_WORDS);
    let s = offset_z();
    let mut w = [0u64; STATUS_WORDS];
    fill_status(&s.m, LastCommand::default(), 0, &mut w);
    let st = decode_status(&w).unwrap();
    // The path block after it: the controller's own enables and kinematics.
    assert_eq!(st.traj.enables, Some(s.m.enables()));
    assert_eq!(st.traj.kinematics_type, Some(s.m.kins_type() as i32));
    let e = st.eoffset;
    assert!(e.active && !e.limited);
    assert!((e.applied[2] - 0.75).abs() < 1e-6, "{}", e.applied[2]);
    assert_eq!(e.requested[2], 0.75);
    assert_eq!((e.applied[0], e.requested[0]), (0.0, 0.0));
    // The world pose includes the offset; the status text says so.
    assert!((st.axes[2].pos_cmd - 0.75).abs() < 1e-6);
    let text = st.to_string();
    assert!(
        text.contains("external offsets: Z 0.75") && text.contains("(request 0.750000) active"),
        "{text}"
    );
    // A controller from before the block publishes fewer words: the
    // reader's zeros read as no offsets, and nothing else changes.
    let mut old = w;
    old[EOFFSET_START..].fill(0);
    let old = decode_status(&old).unwrap();
    assert_eq!(old.eoffset, EoffsetState::default());
    // (The path block after it is gone too: not reported.)
    assert_eq!(
        MotionStatus {
            eoffset: EoffsetState::default(),
            traj: crate::status::TrajState {
                enables: None,
                kinematics_type: None,
                ..st.traj
            },
            ..st
        },
        old
    );
    assert!(!old.to_string().contains("external offsets"));
}
