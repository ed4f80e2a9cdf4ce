//! Applying one command ([`MotionCore::command`]): the value checks every
//! configuration command shares, the dispatch, and JOINT_HOME/JOINT_UNHOME.

use super::jog::dir_of;
use super::queue::Override;
use super::*;
use crate::command::{Command, CommandResult, Direction, Feature, Quantity, Reject};
use crate::homing::{ConfigProblem, HomeFlags};
use crate::sizes::{AF_ENABLED, FH_ENABLED, FS_ENABLED, SS_ENABLED};

impl MotionCore {
    // ----------------------------------------------------------------
    // Commands

    pub(super) fn joint_index(&self, joint: i32) -> Result<usize, Reject> {
        if joint >= 0 && (joint as usize) < self.joints.len() {
            Ok(joint as usize)
        } else {
            Err(Reject::NoSuchJoint {
                joint,
                num_joints: self.joints.len(),
            })
        }
    }

    pub(super) fn finite(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    pub(super) fn non_negative(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    pub(super) fn positive(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    /// Applies one command. On `Err` nothing changed. Reads the
    /// machine-wide inputs (`motion.enable`, `motion.jog-inhibit`) from
    /// [`Self::inputs`].
    pub fn command(&mut self, cmd: &Command) -> CommandResult {
        match *cmd {
            Command::Abort => {
                self.tp.abort();
                self.end_probing();
                self.homing.abort(&mut self.joints);
                for j in &mut self.joints {
                    j.free_tp.enable = false;
                    j.error = false;
                    j.fault = false;
                }
                self.abort_axis_jogs(false);
                self.error = false;
                Ok(())
            }
            Command::Enable => {
                if !self.inputs.enable {
                    return Err(Reject::EnableInputFalse);
                }
                self.enabling = true;
                Ok(())
            }
            Command::Disable => {
                self.enabling = false;
                Ok(())
            }
            Command::JogCont { joint, vel } => {
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
            Command::JogIncr { joint, vel, offset } => {
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
            Command::JogAbs { joint, vel, pos } => {
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
            Command::JogAbort { joint } => {
                let j = self.joint_index(joint)?;
                self.homing.cancel_joint(j, &mut self.joints);
                let jt = &mut self.joints[j];
                jt.end_jogs(false);
                jt.error = false;
                Ok(())
            }
            Command::JointActivate { joint } => {
                let j = self.joint_index(joint)?;
                // Activated while enabled, the joint would move without
                // being enabled, and so without its fault checks.
                if self.enabled && !self.joints[j].active {
                    return Err(Reject::ActivateWhileEnabled { joint: j });
                }
                self.joints[j].active = true;
                Ok(())
            }
            Command::JointDeactivate { joint } => {
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
            Command::OverrideLimits { joint } => {
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
            Command::Free => self.request_mode(Mode::Free),
            Command::Teleop => self.request_mode(Mode::Teleop),
            Command::Coord => self.request_mode(Mode::Coord),
            Command::EnableAmplifier { joint } | Command::DisableAmplifier { joint } => {
                self.joint_index(joint)?;
                Err(Reject::Unsupported {
                    what: Feature::AmplifierCommand,
                })
            }
            Command::Scale { scale } => {
                if scale.is_nan() {
                    return Err(Reject::BadValue {
                        what: Quantity::Scale,
                        value: scale,
                    });
                }
                self.scale = scale.clamp(0.0, 1.0);
                Ok(())
            }
            Command::SetJointPositionLimits { joint, min, max } => {
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
            Command::SetJointVelLimit { joint, vel } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.vel_limit = Self::positive(Quantity::VelocityLimit, vel)?;
                Ok(())
            }
            Command::SetJointAccLimit { joint, acc } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.acc_limit = Self::positive(Quantity::AccelerationLimit, acc)?;
                Ok(())
            }
            Command::SetJointMinFerror { joint, ferror } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.min_ferror =
                    Self::non_negative(Quantity::MinimumFerror, ferror)?;
                Ok(())
            }
            Command::SetJointMaxFerror { joint, ferror } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.max_ferror =
                    Self::non_negative(Quantity::MaximumFerror, ferror)?;
                Ok(())
            }
            Command::SetJointBacklash { joint, backlash } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.backlash = Self::non_negative(Quantity::Backlash, backlash)?;
                Ok(())
            }
            Command::SetJointMotorOffset { joint, offset } => {
                let j = self.joint_index(joint)?;
                if self.homing.is_active() {
                    return Err(Reject::HomingActive);
                }
                self.joints[j].motor_offset = Self::finite(Quantity::MotorOffset, offset)?;
                Ok(())
            }
            Command::SetWorldHome { pose } => {
                for v in pose.0 {
                    Self::finite(Quantity::WorldHomeCoordinate, v)?;
                }
                self.world_home = pose;
                Ok(())
            }
            Command::Home { joint } => self.home(joint),
            Command::Unhome { joint } => self.unhome(joint),
            Command::SetJointHomingParams { joint, config } => {
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
            Command::UpdateJointHomingParams {
                joint,
                offset,
                home,
                sequence,
            } => {
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
            Command::AxisJogCont { axis, vel } => self.axis_jog_cont(axis, vel),
            Command::AxisJogIncr { axis, vel, offset } => self.axis_jog_incr(axis, vel, offset),
            Command::AxisJogAbs { axis, vel, pos } => self.axis_jog_abs(axis, vel, pos),
            Command::AxisJogAbort { axis } => self.axis_jog_abort(axis),
            Command::SetAxisPositionLimits { axis, min, max } => {
                self.set_axis_position_limits(axis, min, max)
            }
            Command::SetAxisVelLimit { axis, vel } => self.set_axis_vel_limit(axis, vel),
            Command::SetAxisAccLimit { axis, acc } => self.set_axis_acc_limit(axis, acc),
            Command::Line { end, vel, kind, id } => self.queue_line(end, vel, kind, id),
            Command::Circle {
                end,
                center,
                normal,
                turns,
                vel,
                id,
            } => self.queue_circle(end, center, normal, turns, vel, id),
            Command::Dwell { seconds, id } => self.queue_dwell(seconds, id),
            Command::Probe {
                end,
                vel,
                probe,
                id,
            } => self.queue_probe(end, vel, probe, id),
            Command::ClearProbeFlags => {
                self.probe.tripped = false;
                Ok(())
            }
            Command::SetTermCond { cond, tolerance } => self.set_term_cond(cond, tolerance),
            Command::Pause => {
                self.tp.pause();
                Ok(())
            }
            Command::Resume => {
                self.tp.resume();
                Ok(())
            }
            Command::Step => self.step(),
            Command::FeedScale { scale } => self.set_override(Override::Feed, scale),
            Command::RapidScale { scale } => self.set_override(Override::Rapid, scale),
            Command::SetMaxFeedOverride { scale } => self.set_override(Override::Max, scale),
            Command::FeedScaleEnable { on } => self.set_enable(FS_ENABLED, on),
            Command::FeedHoldEnable { on } => self.set_enable(FH_ENABLED, on),
            Command::AdaptiveFeedEnable { on } => self.set_enable(AF_ENABLED, on),
            Command::SpindleScaleEnable { on } => self.set_enable(SS_ENABLED, on),
            Command::SetVelLimit { vel } => self.set_traj_limit(Quantity::VelocityLimit, vel),
            Command::SetAccLimit { acc } => self.set_traj_limit(Quantity::AccelerationLimit, acc),
            Command::SetJerkLimit { jerk } => self.set_traj_limit(Quantity::JerkLimit, jerk),
            Command::SetPlannerType { planner } => self.set_planner_type(planner),
            Command::SetJointJerkLimit { joint, jerk } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.jerk_limit = Self::non_negative(Quantity::JerkLimit, jerk)?;
                Ok(())
            }
            Command::SetAxisJerkLimit { axis, jerk } => self.set_axis_jerk_limit(axis, jerk),
            Command::SetJointComp {
                joint,
                nominal,
                forward,
                reverse,
            } => self.add_comp(joint, nominal, forward, reverse),
            Command::ClearJointComp { joint } => {
                let j = self.joint_index(joint)?;
                if self.enabled {
                    return Err(Reject::MustBeDisabled);
                }
                self.joints[j].comp.clear();
                Ok(())
            }
        }
    }

    /// SET_JOINT_COMP: one more table entry (only while disabled).
    fn add_comp(&mut self, joint: i32, nominal: f64, forward: f64, reverse: f64) -> CommandResult {
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

    /// JOINT_HOME with its requirements, in LinuxCNC's order.
    pub(super) fn home(&mut self, joint: i32) -> CommandResult {
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
    pub(super) fn unhome(&mut self, joint: i32) -> CommandResult {
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
