//! A joint's status pins, as halui has them for each joint
//! (`halui.joint.N.*`) and for the selected one (`halui.joint.selected.*`):
//! homed, faulted, on a hard or soft limit, limits overridden.

use hal_core::{Component, Out, Pin};
use motion::channel::JointState;

/// The status pins of one joint (or of the selected joint).
pub struct JointStatusPins {
    is_homed: Pin<bool, Out>,
    has_fault: Pin<bool, Out>,
    on_hard_min_limit: Pin<bool, Out>,
    on_hard_max_limit: Pin<bool, Out>,
    on_soft_min_limit: Pin<bool, Out>,
    on_soft_max_limit: Pin<bool, Out>,
    override_limits: Pin<bool, Out>,
}

/// A joint commanded beyond a soft limit, the way the motion controller
/// checks it: only a homed, active joint has soft limits.
fn beyond_soft_limits(joint: &JointState) -> (bool, bool) {
    const SLACK: f64 = 1e-12;
    if !(joint.active && joint.homed) {
        return (false, false);
    }
    (
        joint.pos_cmd < joint.min_limit - SLACK,
        joint.pos_cmd > joint.max_limit + SLACK,
    )
}

impl JointStatusPins {
    /// Creates `PREFIX.is-homed`, `.has-fault`, `.on-hard-min-limit`,
    /// `.on-hard-max-limit`, `.on-soft-min-limit`, `.on-soft-max-limit`
    /// and `.override-limits` (PREFIX like `halui.joint.0`).
    pub fn create(comp: &Component, prefix: &str) -> hal_core::Result<JointStatusPins> {
        let pin = |n: &str| comp.pin(&format!("{prefix}.{n}"));
        Ok(JointStatusPins {
            is_homed: pin("is-homed")?,
            has_fault: pin("has-fault")?,
            on_hard_min_limit: pin("on-hard-min-limit")?,
            on_hard_max_limit: pin("on-hard-max-limit")?,
            on_soft_min_limit: pin("on-soft-min-limit")?,
            on_soft_max_limit: pin("on-soft-max-limit")?,
            override_limits: pin("override-limits")?,
        })
    }

    /// Writes the pins for `joint`; `overridden`: its hard limits are
    /// overridden for now.
    pub fn write(&self, joint: &JointState, overridden: bool) {
        let (soft_min, soft_max) = beyond_soft_limits(joint);
        self.is_homed.set(joint.homed);
        self.has_fault.set(joint.faulted);
        self.on_hard_min_limit.set(joint.neg_hard_limit);
        self.on_hard_max_limit.set(joint.pos_hard_limit);
        self.on_soft_min_limit.set(soft_min);
        self.on_soft_max_limit.set(soft_max);
        self.override_limits.set(overridden);
    }
}

/// Whether the joints' `override-limits` show, from motion's mask (two
/// bits a joint): as in LinuxCNC, task reports one flag for all joints,
/// set while any tripped limit is overridden.
pub fn limits_overridden(mask: u64) -> bool {
    mask != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soft_limits_count_only_for_a_homed_joint_beyond_them() {
        let mut j = JointState {
            active: true,
            homed: true,
            min_limit: -10.0,
            max_limit: 10.0,
            pos_cmd: 10.0,
            ..JointState::default()
        };
        assert_eq!(beyond_soft_limits(&j), (false, false), "at the limit");
        j.pos_cmd = 10.5;
        assert_eq!(beyond_soft_limits(&j), (false, true));
        j.pos_cmd = -11.0;
        assert_eq!(beyond_soft_limits(&j), (true, false));
        j.homed = false;
        assert_eq!(beyond_soft_limits(&j), (false, false), "not homed");
        // Joint 1's upper limit overridden: every joint shows it.
        assert!(limits_overridden(0b1000));
        assert!(!limits_overridden(0));
    }
}
