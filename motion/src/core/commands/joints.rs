//! Free mode's joint commands: the keyboard jogs, activating and
//! deactivating joints, the hard-limit override and the SCALE.

use super::super::jog::dir_of;
use super::super::*;
use crate::command::{CommandResult, Direction, Quantity, Reject};

impl MotionCore {
    /// JOG_CONT: towards the jog limit in the direction of `vel`.
    pub(in crate::core) fn jog_cont(&mut self, joint: i32, vel: f64) -> CommandResult {
        let j = self.jog_checks(joint, vel)?;
        self.jog_direction_ok(j, dir_of(vel))?;
        let jt = &mut self.joints[j];
        jt.refresh_jog_limits();
        jt.free_tp.pos_cmd = if vel > 0.0 {
            jt.max_jog_limit
        } else {
            jt.min_jog_limit
        };
        self.start_kb_jog(j, vel);
        Ok(())
    }

    /// JOG_INCR: `offset` further from the planner's target.
    pub(in crate::core) fn jog_incr(&mut self, joint: i32, vel: f64, offset: f64) -> CommandResult {
        let j = self.jog_checks(joint, vel)?;
        let offset = Self::non_negative(Quantity::JogIncrement, offset)?;
        self.jog_direction_ok(j, dir_of(vel))?;
        let jt = &mut self.joints[j];
        jt.refresh_jog_limits();
        let target = if vel > 0.0 {
            jt.free_tp.pos_cmd + offset
        } else {
            jt.free_tp.pos_cmd - offset
        };
        if !target.is_finite() {
            return Err(Reject::BadValue {
                what: Quantity::JogTarget,
                value: target,
            });
        }
        if target > jt.max_jog_limit || target < jt.min_jog_limit {
            return Err(Reject::TargetOutsideLimits {
                joint: j,
                target,
                min: jt.min_jog_limit,
                max: jt.max_jog_limit,
            });
        }
        jt.free_tp.pos_cmd = target;
        self.start_kb_jog(j, vel);
        Ok(())
    }

    /// JOG_ABS: to `pos`, clamped into the jog limits.
    pub(in crate::core) fn jog_abs(&mut self, joint: i32, vel: f64, pos: f64) -> CommandResult {
        let j = self.jog_checks(joint, vel)?;
        let pos = Self::finite(Quantity::JogPosition, pos)?;
        let jt = &mut self.joints[j];
        jt.refresh_jog_limits();
        let target = pos.clamp(jt.min_jog_limit, jt.max_jog_limit);
        let here = jt.free_tp.curr_pos;
        if target != here {
            let dir = if target > here {
                Direction::Positive
            } else {
                Direction::Negative
            };
            self.jog_direction_ok(j, dir)?;
        }
        self.joints[j].free_tp.pos_cmd = target;
        self.start_kb_jog(j, vel);
        Ok(())
    }

    /// JOG_ABORT: stops the joint's jog (and its homing, if it is homing
    /// now).
    pub(in crate::core) fn jog_abort(&mut self, joint: i32) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.homing.cancel_joint(j, &mut self.joints);
        let jt = &mut self.joints[j];
        jt.end_jogs(false);
        jt.error = false;
        Ok(())
    }

    /// JOINT_ACTIVATE.
    pub(in crate::core) fn activate(&mut self, joint: i32) -> CommandResult {
        let j = self.joint_index(joint)?;
        // Activated while enabled, the joint would move without being
        // enabled, and so without its fault checks.
        if self.enabled && !self.joints[j].active {
            return Err(Reject::ActivateWhileEnabled { joint: j });
        }
        self.joints[j].active = true;
        Ok(())
    }

    /// JOINT_DEACTIVATE: also switches the amplifier off.
    pub(in crate::core) fn deactivate(&mut self, joint: i32) -> CommandResult {
        let j = self.joint_index(joint)?;
        if self.homing.in_sequence(j) {
            return Err(Reject::HomingActive);
        }
        if self.axes_moving() {
            return Err(Reject::JointMoving { joint: j });
        }
        let jt = &mut self.joints[j];
        if jt.free_tp.active {
            return Err(Reject::JointMoving { joint: j });
        }
        jt.active = false;
        jt.enabled = false;
        jt.free_tp.enable = false;
        Ok(())
    }

    /// OVERRIDE_LIMITS: `joint < 0` ends the override; otherwise the hard
    /// limits tripped now are overridden until the end of the next jog.
    pub(in crate::core) fn override_limits(&mut self, joint: i32) -> CommandResult {
        if joint < 0 {
            self.override_limit_mask = 0;
        } else {
            let mut mask = 0u32;
            for (n, jt) in self.joints.iter().enumerate() {
                if jt.nhl {
                    mask |= 1 << (2 * n);
                }
                if jt.phl {
                    mask |= 2 << (2 * n);
                }
            }
            self.override_limit_mask = mask;
        }
        self.overriding = false;
        for jt in &mut self.joints {
            jt.error = false;
        }
        Ok(())
    }

    /// The free-mode SCALE, clamped to 0..=1.
    pub(in crate::core) fn set_scale(&mut self, scale: f64) -> CommandResult {
        if scale.is_nan() {
            return Err(Reject::BadValue {
                what: Quantity::Scale,
                value: scale,
            });
        }
        self.scale = scale.clamp(0.0, 1.0);
        Ok(())
    }
}
