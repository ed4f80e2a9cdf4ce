//! What the unit tests of several modules share.

use crate::command::Command;
use crate::core::MotionCore;

/// Activates every joint of `m` with the test machines' settings: soft
/// limits ±100, 10 u/s, 100 u/s², following error 0.01 at rest and 1 at
/// full speed.
pub(crate) fn configure_test_joints(m: &mut MotionCore) {
    for j in 0..m.num_joints() as i32 {
        for c in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -100.0,
                max: 100.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 10.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 100.0,
            },
            Command::SetJointMinFerror {
                joint: j,
                ferror: 0.01,
            },
            Command::SetJointMaxFerror {
                joint: j,
                ferror: 1.0,
            },
        ] {
            m.command(&c).unwrap();
        }
    }
}
