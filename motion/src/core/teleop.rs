//! Teleop mode: the axis jog and axis configuration commands, the axis
//! jog wheels and the teleop cycle.
//!
//! Teleop mode: nine axis planners ([`crate::axis`]) produce the pose; the
//! inverse kinematics give the joint commands. LinuxCNC feeds those
//! through a cubic interpolator that smooths and delays them by two servo
//! periods; there is none here, the joint command is the inverse
//! kinematics result itself (`pos_cmd = coarse_pos`, velocity from the
//! difference to the previous command). The axis planners are already
//! acceleration limited, so nothing is lost but the extra smoothing. In
//! position means: no axis planner moving (LinuxCNC never updates the flag
//! in teleop). An inverse-kinematics failure or a non-finite joint
//! position reports an [`Event`], raises the motion error and disables
//! motion in the same cycle.
//!
//! Axis jogs are separate commands ([`Command::AxisJogCont`] ...) rather
//! than LinuxCNC's joint jogs carrying an axis number, and every refusal
//! says why (LinuxCNC drops a teleop jog silently when the motion error
//! flag is set). An absolute axis jog is implemented (LinuxCNC drops it,
//! and would treat it as an increment), with its target clamped into the
//! axis limits; a continuous jog from beyond a limit further out is
//! refused (LinuxCNC would head back for the limit). Axis wheels consume
//! their counts every cycle, also while they may not move the axis (not
//! teleop, jog-inhibit, on a soft limit, motion error, feed hold), so
//! counts turned meanwhile never move it later (LinuxCNC keeps them while
//! jog-inhibit is true), and a wheel target beyond a limit only skips that
//! axis (LinuxCNC skips all the axes after it too). The per-cycle axis
//! limit stop clamps onto the limit and ends the jog (see
//! [`crate::axis::Axis`]). With an external offset applied (see
//! `core::eoffset`), jog targets, the limit checks and the limit stop use
//! the axis's limits less the offset, so that planned plus offset stays
//! within them, and jogs get the share of the axis's velocity and
//! acceleration that `OFFSET_AV_RATIO` leaves.
//!
//! Other safety details: while a homed joint's command is beyond its soft
//! limits in teleop, axis jogs are stopped and the motion error is set
//! every cycle, as in LinuxCNC (jog off in free mode); a kinematics fault
//! disables motion in the cycle it happens (LinuxCNC: the next one); a
//! joint cannot be deactivated while the axis planners move; after a
//! kinematics switch the axis planners restart, at rest, from the pose the
//! new kinematics compute.

use super::*;
use crate::axis::{wheel_acc, Axis};
use crate::command::{CommandResult, Direction, Quantity, Reject};

/// The axis index of an axis number from a command.
pub(super) fn axis_index(axis: i32) -> Result<usize, Reject> {
    usize::try_from(axis)
        .ok()
        .filter(|&a| a < NUM_AXES)
        .ok_or(Reject::NoSuchAxis { axis })
}

impl MotionCore {
    // ----------------------------------------------------------------
    // Axis commands

    /// The requirements every axis jog shares; returns the axis.
    pub(super) fn axis_jog_checks(&self, axis: i32, vel: f64) -> Result<usize, Reject> {
        let a = axis_index(axis)?;
        if !vel.is_finite() || vel == 0.0 {
            return Err(Reject::BadVelocity { vel });
        }
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        if self.state != MotionState::Teleop {
            return Err(Reject::NotTeleopMode);
        }
        if !self.axis_in_kinematics(a) {
            return Err(Reject::AxisNotInKinematics { axis: a });
        }
        if self.inputs.jog_inhibit {
            return Err(Reject::JogInhibited);
        }
        if self.error {
            return Err(Reject::MotionError);
        }
        if self.world.axes[a].wheel_jog_active {
            return Err(Reject::AxisWheelJogActive { axis: a });
        }
        if let Some(joint) = self.indexer_joint[a] {
            // As LinuxCNC: a locking indexer axis does not jog in teleop.
            return Err(Reject::IndexerJog {
                axis: a,
                joint: usize::from(joint),
            });
        }
        Ok(a)
    }

    /// Where an incremental jog starts from: the target of a running
    /// planner, the position of a stopped one.
    pub(super) fn axis_jog_base(&self, a: usize) -> f64 {
        let tp = &self.world.axes[a].teleop_tp;
        if tp.enable {
            tp.pos_cmd
        } else {
            tp.curr_pos
        }
    }

    /// What every accepted axis jog does once its target is set.
    pub(super) fn start_axis_jog(&mut self, a: usize, vel: f64) {
        let ax = &mut self.world.axes[a];
        ax.teleop_tp.max_vel = vel.abs().min(ax.cfg.plan_vel());
        ax.teleop_tp.max_acc = ax.cfg.plan_acc();
        ax.kb_jog_active = true;
        ax.teleop_tp.enable = true;
    }

    /// AXIS_JOG_CONT: towards the axis limit in the direction of `vel`.
    pub(super) fn axis_jog_cont(&mut self, axis: i32, vel: f64) -> CommandResult {
        let a = self.axis_jog_checks(axis, vel)?;
        let ax = &self.world.axes[a];
        let here = ax.teleop_tp.curr_pos;
        let (min, max) = ax.planned_limits();
        // From beyond a limit the jog would head for the limit, backwards.
        if vel > 0.0 && here > max {
            return Err(Reject::AxisPastLimit {
                axis: a,
                dir: Direction::Positive,
            });
        }
        if vel < 0.0 && here < min {
            return Err(Reject::AxisPastLimit {
                axis: a,
                dir: Direction::Negative,
            });
        }
        let target = if vel > 0.0 { max } else { min };
        self.world.axes[a].teleop_tp.pos_cmd = target;
        self.start_axis_jog(a, vel);
        Ok(())
    }

    /// AXIS_JOG_INCR: `offset` in the direction of `vel`; refused if the
    /// target leaves the axis limits.
    pub(super) fn axis_jog_incr(&mut self, axis: i32, vel: f64, offset: f64) -> CommandResult {
        let a = self.axis_jog_checks(axis, vel)?;
        let offset = Self::non_negative(Quantity::JogIncrement, offset)?;
        let base = self.axis_jog_base(a);
        let target = if vel > 0.0 {
            base + offset
        } else {
            base - offset
        };
        if !target.is_finite() {
            return Err(Reject::BadValue {
                what: Quantity::JogTarget,
                value: target,
            });
        }
        let (min, max) = self.world.axes[a].planned_limits();
        if target > max || target < min {
            return Err(Reject::AxisTargetOutsideLimits {
                axis: a,
                target,
                min,
                max,
            });
        }
        self.world.axes[a].teleop_tp.pos_cmd = target;
        self.start_axis_jog(a, vel);
        Ok(())
    }

    /// AXIS_JOG_ABS: to `pos` clamped into the axis limits.
    pub(super) fn axis_jog_abs(&mut self, axis: i32, vel: f64, pos: f64) -> CommandResult {
        let a = self.axis_jog_checks(axis, vel)?;
        let pos = Self::finite(Quantity::JogPosition, pos)?;
        let (min, max) = self.world.axes[a].planned_limits();
        // Written out: `f64::clamp` would panic on reversed bounds, which
        // the limit commands never allow anyway.
        let target = if pos > max {
            max
        } else if pos < min {
            min
        } else {
            pos
        };
        self.world.axes[a].teleop_tp.pos_cmd = target;
        self.start_axis_jog(a, vel);
        Ok(())
    }

    /// AXIS_JOG_ABORT: a stop at the axis's acceleration limit, in any mode.
    pub(super) fn axis_jog_abort(&mut self, axis: i32) -> CommandResult {
        let a = axis_index(axis)?;
        self.world.axes[a].abort(false);
        Ok(())
    }

    /// SET_AXIS_POSITION_LIMITS.
    pub(super) fn set_axis_position_limits(
        &mut self,
        axis: i32,
        min: f64,
        max: f64,
    ) -> CommandResult {
        let a = axis_index(axis)?;
        let min = Self::finite(Quantity::MinimumLimit, min)?;
        let max = Self::finite(Quantity::MaximumLimit, max)?;
        if min > max {
            return Err(Reject::LimitsReversed { min, max });
        }
        let cfg = &mut self.world.axes[a].cfg;
        cfg.min_pos_limit = min;
        cfg.max_pos_limit = max;
        Ok(())
    }

    /// SET_AXIS_VEL_LIMIT.
    pub(super) fn set_axis_vel_limit(&mut self, axis: i32, vel: f64) -> CommandResult {
        let a = axis_index(axis)?;
        self.world.axes[a].cfg.vel_limit = Self::positive(Quantity::VelocityLimit, vel)?;
        Ok(())
    }

    /// SET_AXIS_ACC_LIMIT.
    pub(super) fn set_axis_acc_limit(&mut self, axis: i32, acc: f64) -> CommandResult {
        let a = axis_index(axis)?;
        self.world.axes[a].cfg.acc_limit = Self::positive(Quantity::AccelerationLimit, acc)?;
        Ok(())
    }

    /// SET_AXIS_JERK_LIMIT.
    pub(super) fn set_axis_jerk_limit(&mut self, axis: i32, jerk: f64) -> CommandResult {
        let a = axis_index(axis)?;
        self.world.axes[a].cfg.jerk_limit = Self::non_negative(Quantity::JerkLimit, jerk)?;
        Ok(())
    }

    /// SET_AXIS_EOFFSET_RATIO: only while disabled, so that no offset is
    /// moving or held when its share of the limits changes.
    pub(super) fn set_axis_eoffset_ratio(&mut self, axis: i32, ratio: f64) -> CommandResult {
        let a = axis_index(axis)?;
        if !crate::eoffset::ratio_ok(ratio) {
            return Err(Reject::BadValue {
                what: Quantity::EoffsetRatio,
                value: ratio,
            });
        }
        if self.enabled {
            return Err(Reject::MustBeDisabled);
        }
        self.world.axes[a].cfg.eoffset_ratio = ratio;
        Ok(())
    }

    /// Ends every axis jog (ABORT: at the acceleration limits, each axis on
    /// its own, not along a path).
    pub(super) fn abort_axis_jogs(&mut self, immediate: bool) {
        for ax in &mut self.world.axes {
            ax.abort(immediate);
        }
    }

    // ----------------------------------------------------------------
    // Cycle hooks

    /// `motion.jog-stop(-immediate)`: ends the axis jogs too.
    pub(super) fn stop_axis_jogs(&mut self, immediate: bool) {
        for ax in &mut self.world.axes {
            if ax.jogging() {
                ax.abort(immediate);
            }
        }
    }

    /// A probe contact stops moving axis planners at once; true if any did.
    pub(super) fn stop_axis_jogs_on_probe(&mut self) -> bool {
        let mut stopped = false;
        for ax in &mut self.world.axes {
            if ax.jogging() || ax.teleop_tp.active {
                ax.abort(true);
                stopped = true;
            }
        }
        stopped
    }

    /// Whether an axis planner moves or is about to: in a world mode that
    /// moves the joints the kinematics drive.
    pub(super) fn axes_moving(&self) -> bool {
        self.world
            .axes
            .iter()
            .any(|a| a.teleop_tp.active || a.jogging())
    }

    /// After a kinematics switch the pose was recomputed from the joints
    /// by the new kinematics: the axis planners start again from it, at
    /// rest, or the next teleop cycle would feed the old kinematics' pose
    /// to the new inverse and jump.
    pub(super) fn world_kins_switched(&mut self) {
        let planned = self.without_eoffsets(&self.carte_pos_cmd);
        for (a, ax) in self.world.axes.iter_mut().enumerate() {
            ax.set_at_rest(planned.0[a]);
        }
    }

    /// Whether a keyboard or wheel jog moves any axis.
    pub(super) fn axis_jogging(&self) -> bool {
        self.world.axes.iter().any(Axis::jogging)
    }

    /// Σ v² over the axis planners (for `motion.current-vel`; zero outside
    /// teleop, where they stand still).
    pub(super) fn teleop_vel_squared(&self) -> f64 {
        self.world
            .axes
            .iter()
            .map(|a| a.teleop_tp.curr_vel * a.teleop_tp.curr_vel)
            .sum()
    }

    /// Axis jog wheels (`axis.L.jog-*`), in teleop mode: each count moves
    /// the axis planner's target by `jog-scale`.
    pub(super) fn handle_axis_jog_wheels(&mut self) {
        let first = self.world.wheel_first_pass;
        self.world.wheel_first_pass = false;
        let may_move = self.state == MotionState::Teleop
            && !self.inputs.jog_inhibit
            && !self.on_soft_limit
            && !self.error
            && self.net_feed_scale >= 0.0001;
        for a in 0..NUM_AXES {
            let inp = self.axis_inputs[a];
            let in_kins = self.axis_in_kinematics(a);
            let ax = &mut self.world.axes[a];
            // Always consumed, so counts turned while the wheel may not
            // move the axis never move it later.
            let delta = inp.jog_counts.wrapping_sub(ax.old_jog_counts);
            ax.old_jog_counts = inp.jog_counts;
            if first || delta == 0 || !may_move || !inp.jog_enable || !in_kins {
                continue;
            }
            // A locking indexer axis is not wheel jogged (as LinuxCNC).
            if self.indexer_joint[a].is_some() {
                continue;
            }
            if ax.kb_jog_active {
                continue;
            }
            let distance = f64::from(delta) * inp.jog_scale;
            if !distance.is_finite() {
                continue;
            }
            let cfg = ax.cfg;
            let (min, max) = ax.planned_limits();
            let mut pos = ax.teleop_tp.pos_cmd + distance;
            if pos > max || pos < min {
                continue;
            }
            let acc = wheel_acc(cfg.plan_acc(), inp.jog_accel_fraction);
            if inp.jog_vel_mode {
                // Stop when the wheel stops: never more than a stopping
                // distance ahead of the axis.
                let here = ax.teleop_tp.curr_pos;
                let stop_dist = cfg.plan_vel() * cfg.plan_vel() / (2.0 * acc);
                if pos > here + stop_dist {
                    pos = here + stop_dist;
                } else if pos < here - stop_dist {
                    pos = here - stop_dist;
                }
            }
            ax.teleop_tp.pos_cmd = pos;
            ax.teleop_tp.max_vel = cfg.plan_vel();
            ax.teleop_tp.max_acc = acc;
            ax.wheel_jog_active = true;
            ax.teleop_tp.enable = true;
        }
    }

    /// TELEOP position commands: the axis planners make the planned pose,
    /// the external offsets are added, the inverse kinematics give the
    /// joint commands.
    pub(super) fn teleop_pos_cmds(&mut self, period: f64) {
        self.inpos = true;
        let mut planned = self.carte_pos_cmd;
        for a in 0..NUM_AXES {
            let frac = self.axis_inputs[a].jog_accel_fraction;
            let ax = &mut self.world.axes[a];
            ax.update(period, self.scale, frac);
            if ax.teleop_tp.active {
                self.inpos = false;
                if self.override_limit_mask != 0 {
                    self.overriding = true;
                }
            } else {
                ax.kb_jog_active = false;
                ax.wheel_jog_active = false;
            }
            planned.0[a] = ax.teleop_tp.curr_pos;
        }
        self.carte_pos_cmd = self.add_eoffsets(period, &planned);
        self.carte_pos_cmd_ok = true;
        self.joints_from_world(period);
        if self.overriding && self.inpos {
            self.override_limit_mask = 0;
            self.overriding = false;
        }
    }

    /// The backup soft-limit check in teleop: while a homed joint's command
    /// is beyond its soft limits, the motion error stays set and axis jogs
    /// are stopped every cycle (as LinuxCNC; jog off in free mode).
    pub(super) fn teleop_soft_limit_stop(&mut self) {
        if self.state == MotionState::Teleop && self.on_soft_limit {
            self.error = true;
            for ax in &mut self.world.axes {
                if ax.jogging() || ax.teleop_tp.enable {
                    ax.abort(false);
                }
            }
        }
    }
}
