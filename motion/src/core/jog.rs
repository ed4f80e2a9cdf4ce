//! Joint jogs in free mode: the checks every keyboard jog shares, the
//! hard- and soft-limit rule for its direction, and the jog wheels
//! (`joint.N.jog-*`).

use super::*;
use crate::axis::wheel_acc;
use crate::command::{Direction, Reject};
use crate::homing::HomeFlags;

impl MotionCore {
    /// The requirements every free-mode jog shares; returns the joint.
    pub(super) fn jog_checks(&self, joint: i32, vel: f64) -> Result<usize, Reject> {
        let j = self.joint_index(joint)?;
        if !vel.is_finite() || vel == 0.0 {
            return Err(Reject::BadVelocity { vel });
        }
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        if self.state == MotionState::Teleop {
            return Err(Reject::JointJogInTeleop);
        }
        if self.state != MotionState::Free {
            return Err(Reject::NotFreeMode);
        }
        if !self.joints[j].active {
            return Err(Reject::JointInactive { joint: j });
        }
        if self.inputs.jog_inhibit {
            return Err(Reject::JogInhibited);
        }
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        if self.joints[j].wheel_jog_active {
            return Err(Reject::WheelJogActive { joint: j });
        }
        let flags = self.homing.joints[j].cfg.flags;
        if flags.contains(HomeFlags::UNLOCK_FIRST) {
            return Err(Reject::LockingIndexer { joint: j });
        }
        if self.homing.is_synchronized(j) {
            return Err(Reject::SynchronizedJoint { joint: j });
        }
        Ok(j)
    }

    /// LinuxCNC's `joint_jog_ok`: no jogging further into a tripped hard
    /// limit (unless both limits of the joint are overridden: a shared
    /// switch) and none from beyond the jog limit further out.
    pub(super) fn jog_direction_ok(&mut self, j: usize, dir: Direction) -> Result<(), Reject> {
        let neg_ovr = self.override_limit_mask & (1 << (2 * j)) != 0;
        let pos_ovr = self.override_limit_mask & (2 << (2 * j)) != 0;
        if neg_ovr && pos_ovr {
            return Ok(());
        }
        let jt = &mut self.joints[j];
        match dir {
            Direction::Positive if jt.phl => {
                return Err(Reject::OnHardLimit { joint: j, dir });
            }
            Direction::Negative if jt.nhl => {
                return Err(Reject::OnHardLimit { joint: j, dir });
            }
            _ => {}
        }
        jt.refresh_jog_limits();
        match dir {
            Direction::Positive if jt.pos_cmd > jt.max_jog_limit => {
                Err(Reject::PastSoftLimit { joint: j, dir })
            }
            Direction::Negative if jt.pos_cmd < jt.min_jog_limit => {
                Err(Reject::PastSoftLimit { joint: j, dir })
            }
            _ => Ok(()),
        }
    }

    /// What every accepted keyboard jog does once its target is set.
    pub(super) fn start_kb_jog(&mut self, j: usize, vel: f64) {
        let jt = &mut self.joints[j];
        jt.free_tp.max_vel = vel.abs().min(jt.cfg.vel_limit);
        jt.free_tp.max_acc = jt.cfg.acc_limit;
        jt.kb_jog_active = true;
        jt.free_tp.enable = true;
        jt.error = false;
        self.clear_homes(j);
    }

    /// Inverse-only kinematics cannot tell where a jogged machine is:
    /// jogging unhomes the joint (every joint once a move was queued).
    pub(super) fn clear_homes(&mut self, j: usize) {
        if self.kins_type == KinematicsType::InverseOnly {
            if self.rehome_all {
                for jt in &mut self.joints {
                    jt.homed = false;
                }
            } else {
                self.joints[j].homed = false;
            }
        }
    }

    /// MPG jogs: each joint's `jog-counts` moves its free planner target.
    pub(super) fn handle_jog_wheels(&mut self) {
        if self.inputs.jog_inhibit {
            return;
        }
        let first = self.wheel_first_pass;
        self.wheel_first_pass = false;
        for j in 0..self.joints.len() {
            let inp = self.joint_inputs[j];
            let jt = &mut self.joints[j];
            let delta = inp.jog_counts.wrapping_sub(jt.old_jog_counts);
            jt.old_jog_counts = inp.jog_counts;
            if first || delta == 0 || !jt.active {
                continue;
            }
            if self.state != MotionState::Free || !inp.jog_enable || self.homing.is_active() {
                continue;
            }
            if jt.kb_jog_active {
                continue;
            }
            let locking = self.homing.joints[j]
                .cfg
                .flags
                .contains(HomeFlags::UNLOCK_FIRST);
            if locking || self.homing.is_synchronized(j) {
                continue;
            }
            if self.net_feed_scale < 0.0001 {
                break;
            }
            let distance = f64::from(delta) * inp.jog_scale;
            if !distance.is_finite() {
                continue;
            }
            if distance > 0.0 && jt.phl {
                continue;
            }
            if distance < 0.0 && jt.nhl {
                continue;
            }
            let mut pos = jt.free_tp.pos_cmd + distance;
            jt.refresh_jog_limits();
            if pos > jt.max_jog_limit || pos < jt.min_jog_limit {
                continue;
            }
            let acc = wheel_acc(jt.cfg.acc_limit, inp.jog_accel_fraction);
            if inp.jog_vel_mode {
                let v = jt.cfg.vel_limit * self.net_feed_scale;
                let stop_dist = v * v / (2.0 * acc);
                if pos > jt.pos_cmd + stop_dist {
                    pos = jt.pos_cmd + stop_dist;
                } else if pos < jt.pos_cmd - stop_dist {
                    pos = jt.pos_cmd - stop_dist;
                }
            }
            jt.free_tp.pos_cmd = pos;
            jt.free_tp.max_vel = jt.cfg.vel_limit;
            jt.free_tp.max_acc = acc;
            jt.wheel_jog_active = true;
            jt.free_tp.enable = true;
            jt.error = false;
            self.clear_homes(j);
        }
    }
}

pub(super) fn dir_of(vel: f64) -> Direction {
    if vel > 0.0 {
        Direction::Positive
    } else {
        Direction::Negative
    }
}
