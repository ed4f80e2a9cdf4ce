//! Homing commands: JOINT_HOME and JOINT_UNHOME with their
//! requirements, and the joints' homing configuration.

use super::super::*;
use crate::command::{CommandResult, Reject};
use crate::homing::{ConfigProblem, HomeFlags};

impl MotionCore {
    /// SET_JOINT_HOMING_PARAMS: the whole configuration (not while
    /// homing; a locking indexer only on a joint with unlock pins).
    pub(in crate::core) fn set_homing_params(
        &mut self,
        joint: i32,
        config: HomingConfig,
    ) -> CommandResult {
        let j = self.joint_index(joint)?;
        config
            .check()
            .map_err(|problem| Reject::BadHomingConfig { joint: j, problem })?;
        let lockable = j < 32 && self.cfg.unlock_joints_mask & (1 << j) != 0;
        if config.flags.contains(HomeFlags::UNLOCK_FIRST) && !lockable {
            return Err(Reject::BadHomingConfig {
                joint: j,
                problem: ConfigProblem::NoUnlockPins,
            });
        }
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        self.homing.joints[j].cfg = config;
        Ok(())
    }

    /// UPDATE_JOINT_HOMING_PARAMS: HOME_OFFSET, HOME and HOME_SEQUENCE.
    pub(in crate::core) fn update_homing_params(
        &mut self,
        joint: i32,
        offset: f64,
        home: f64,
        sequence: i32,
    ) -> CommandResult {
        let j = self.joint_index(joint)?;
        let config = HomingConfig {
            offset,
            home,
            sequence,
            ..self.homing.joints[j].cfg
        };
        config
            .check()
            .map_err(|problem| Reject::BadHomingConfig { joint: j, problem })?;
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        self.homing.joints[j].cfg = config;
        Ok(())
    }

    /// JOINT_HOME with its requirements, in LinuxCNC's order.
    pub(in crate::core) fn home(&mut self, joint: i32) -> CommandResult {
        if joint != -1 {
            self.joint_index(joint)?;
        }
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        if self.state != MotionState::Free {
            return Err(Reject::NotFreeMode);
        }
        if self.inputs.homing_inhibit {
            return Err(Reject::HomingInhibited);
        }
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        // Homed extra joints follow posthome-cmd, not their planner.
        let mut following_posthome = [false; MAX_JOINTS];
        for (j, f) in following_posthome
            .iter_mut()
            .enumerate()
            .take(self.joints.len())
        {
            *f = j >= self.kins_joints && self.joints[j].homed;
        }
        self.homing.request(joint, &mut self.joints)?;
        // Homing one of them takes it back from posthome-cmd: its
        // command restarts where it is.
        for (j, jt) in self.joints.iter_mut().enumerate() {
            if following_posthome[j] && self.homing.in_sequence(j) && !jt.homed {
                jt.pos_cmd = jt.pos_fb;
                jt.coarse_pos = jt.pos_fb;
                jt.rest_planner_at(jt.pos_fb);
            }
        }
        Ok(())
    }

    /// JOINT_UNHOME: one joint, every active joint (−1) or the volatile
    /// ones (−2); for −1 and −2 all or nothing.
    pub(in crate::core) fn unhome(&mut self, joint: i32) -> CommandResult {
        if !matches!(self.state, MotionState::Free | MotionState::Disabled) {
            return Err(Reject::NotFreeOrDisabled);
        }
        let volatile_only = match joint {
            -1 => false,
            -2 => true,
            _ => {
                let j = self.joint_index(joint)?;
                let jt = &self.joints[j];
                if !jt.active {
                    return Err(Reject::JointInactive { joint: j });
                }
                if jt.homing || self.homing.in_sequence(j) {
                    return Err(Reject::HomingActive);
                }
                if jt.free_tp.active {
                    return Err(Reject::JointMoving { joint: j });
                }
                if j >= self.kins_joints && self.enabled {
                    return Err(Reject::ExtraJointEnabled { joint: j });
                }
                self.joints[j].homed = false;
                return Ok(());
            }
        };
        let chosen = |j: usize, jt: &Joint, homing: &Homing| {
            jt.active && (!volatile_only || homing.joints[j].cfg.volatile_home)
        };
        for (j, jt) in self.joints.iter().enumerate() {
            if !chosen(j, jt, &self.homing) {
                continue;
            }
            if jt.homing || self.homing.in_sequence(j) {
                return Err(Reject::HomingActive);
            }
            if jt.free_tp.active {
                return Err(Reject::JointMoving { joint: j });
            }
            if j >= self.kins_joints && self.enabled && jt.homed {
                return Err(Reject::ExtraJointEnabled { joint: j });
            }
        }
        for j in 0..self.joints.len() {
            if chosen(j, &self.joints[j], &self.homing) {
                self.joints[j].homed = false;
            }
        }
        Ok(())
    }
}
