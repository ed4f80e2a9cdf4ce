//! The settings commands: a joint's limits, following-error limits,
//! backlash, motor offset and screw-compensation table, and the world
//! home.

use super::super::*;
use crate::command::{CommandResult, Quantity, Reject};

impl MotionCore {
    /// SET_JOINT_POSITION_LIMITS: the soft limits.
    pub(in crate::core) fn set_joint_limits(
        &mut self,
        joint: i32,
        min: f64,
        max: f64,
    ) -> CommandResult {
        let j = self.joint_index(joint)?;
        let min = Self::finite(Quantity::MinimumLimit, min)?;
        let max = Self::finite(Quantity::MaximumLimit, max)?;
        if min > max {
            return Err(Reject::LimitsReversed { min, max });
        }
        self.joints[j].cfg.min_pos_limit = min;
        self.joints[j].cfg.max_pos_limit = max;
        Ok(())
    }

    /// SET_JOINT_VEL_LIMIT.
    pub(in crate::core) fn set_joint_vel_limit(&mut self, joint: i32, vel: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.joints[j].cfg.vel_limit = Self::positive(Quantity::VelocityLimit, vel)?;
        Ok(())
    }

    /// SET_JOINT_ACC_LIMIT.
    pub(in crate::core) fn set_joint_acc_limit(&mut self, joint: i32, acc: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.joints[j].cfg.acc_limit = Self::positive(Quantity::AccelerationLimit, acc)?;
        Ok(())
    }

    /// SET_JOINT_JERK_LIMIT (0: none).
    pub(in crate::core) fn set_joint_jerk_limit(&mut self, joint: i32, jerk: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.joints[j].cfg.jerk_limit = Self::non_negative(Quantity::JerkLimit, jerk)?;
        Ok(())
    }

    /// SET_JOINT_MIN_FERROR.
    pub(in crate::core) fn set_min_ferror(&mut self, joint: i32, ferror: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.joints[j].cfg.min_ferror = Self::non_negative(Quantity::MinimumFerror, ferror)?;
        Ok(())
    }

    /// SET_JOINT_MAX_FERROR.
    pub(in crate::core) fn set_max_ferror(&mut self, joint: i32, ferror: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.joints[j].cfg.max_ferror = Self::non_negative(Quantity::MaximumFerror, ferror)?;
        Ok(())
    }

    /// SET_JOINT_BACKLASH.
    pub(in crate::core) fn set_backlash(&mut self, joint: i32, backlash: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        self.joints[j].cfg.backlash = Self::non_negative(Quantity::Backlash, backlash)?;
        Ok(())
    }

    /// SET_JOINT_MOTOR_OFFSET: restores a homing offset (not while homing).
    pub(in crate::core) fn set_motor_offset(&mut self, joint: i32, offset: f64) -> CommandResult {
        let j = self.joint_index(joint)?;
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        self.joints[j].motor_offset = Self::finite(Quantity::MotorOffset, offset)?;
        Ok(())
    }

    /// SET_JOINT_COMP: one more table entry (only while disabled).
    pub(in crate::core) fn add_comp(
        &mut self,
        joint: i32,
        nominal: f64,
        forward: f64,
        reverse: f64,
    ) -> CommandResult {
        use crate::comp::{CompEntry, CompPushError};
        let j = self.joint_index(joint)?;
        if self.enabled {
            return Err(Reject::MustBeDisabled);
        }
        let e = CompEntry {
            nominal,
            forward,
            reverse,
        };
        self.joints[j].comp.push(e).map_err(|err| match err {
            CompPushError::NotIncreasing { previous } => Reject::CompNotIncreasing {
                joint: j,
                nominal,
                previous,
            },
            CompPushError::Full => Reject::CompTableFull { joint: j },
            CompPushError::NotFinite => Reject::BadValue {
                what: Quantity::CompValue,
                value: [nominal, forward, reverse]
                    .into_iter()
                    .find(|v| !v.is_finite())
                    .unwrap_or(f64::NAN),
            },
        })
    }

    /// CLEAR_JOINT_COMP: empties the table (only while disabled).
    pub(in crate::core) fn clear_comp(&mut self, joint: i32) -> CommandResult {
        let j = self.joint_index(joint)?;
        if self.enabled {
            return Err(Reject::MustBeDisabled);
        }
        self.joints[j].comp.clear();
        Ok(())
    }

    /// SET_WORLD_HOME: the first guess of iterative forward kinematics.
    pub(in crate::core) fn set_world_home(&mut self, pose: Pose) -> CommandResult {
        for v in pose.0 {
            Self::finite(Quantity::WorldHomeCoordinate, v)?;
        }
        self.world_home = pose;
        Ok(())
    }
}
