//! The world modes: teleop (axis jogs through the inverse kinematics) and
//! coordinated mode, the FREE/TELEOP/COORD mode requests, the axis jog and
//! axis configuration commands, and the hooks the servo cycle calls for
//! them.
//!
//! Mode requests (reference §2.2, §3.3), with this design's deviations:
//! * A request is checked when it arrives and is either carried out at
//!   once or refused with a [`Reject`]; LinuxCNC instead defers it,
//!   silently, until motion is in position. Refused: any mode change while
//!   something moves ([`Reject::NotInPosition`]), teleop/coordinated mode
//!   with non-identity kinematics before every active joint is homed
//!   ([`Reject::NotHomed`]), with forward-only kinematics (no inverse), and
//!   when the kinematics cannot reproduce the joint positions from the
//!   pose they compute for them ([`Reject::KinematicsFailed`],
//!   [`Reject::ModeChangeJump`], e.g. an unsquared identity gantry, whose
//!   second joint LinuxCNC would snap onto the first).
//! * While motion is disabled the requested mode is remembered and entered
//!   on enable, as LinuxCNC keeps its TELEOP/COORD flags over a disable.
//!   If it cannot be entered then (joints unhomed meanwhile, kinematics
//!   failing), motion enables in free mode and reports
//!   [`Event::WorldModeDropped`]. Inverse-only kinematics cannot tell
//!   where a disabled machine went, so as in LinuxCNC they do not keep a
//!   world mode over a disable, and a world-mode request needs motion
//!   enabled.
//! * Entering teleop or coordinated mode from free mode: the commanded pose
//!   is the forward kinematics of the joints' commands; the teleop planners
//!   are put at rest there; the motion error flag is cleared; entering
//!   coordinated mode also ends any hard-limit override. Between the two
//!   world modes the pose is kept. Leaving for free mode: every joint's
//!   free planner starts at rest at the joint's command.
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
//! Coordinated mode: there is no queued trajectory planner yet (SET_LINE,
//! SET_CIRCLE, PROBE and friends come with it), so coordinated mode holds
//! the pose it was entered with, as LinuxCNC does with an empty queue, and
//! runs the inverse kinematics every cycle; it is always in position.
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
//! [`crate::axis::Axis`]).
//!
//! Other safety details: while a homed joint's command is beyond its soft
//! limits in teleop, axis jogs are stopped and the motion error is set
//! every cycle, as in LinuxCNC (jog off in free mode); a kinematics fault
//! disables motion in the cycle it happens (LinuxCNC: the next one); a
//! joint cannot be deactivated while the axis planners move; after a
//! kinematics switch the axis planners restart, at rest, from the pose the
//! new kinematics compute.

use super::*;
use crate::axis::{wheel_acc, Axis, AxisStatus};
use crate::kins::NUM_AXES;

/// The largest joint step, in joint units, entering a world mode may cause
/// (the rounding of the kinematics' round trip); beyond it the request is
/// refused with [`Reject::ModeChangeJump`].
pub const MODE_ENTRY_TOLERANCE: f64 = 1e-6;

/// The mode motion is in, or enters on enable (LinuxCNC's TELEOP and COORD
/// flags, which survive a disable; neither means free mode).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    Free,
    Teleop,
    Coord,
}

/// The state of the world modes.
#[derive(Debug, Clone)]
pub(crate) struct World {
    pub(crate) mode: Mode,
    pub(crate) axes: [Axis; NUM_AXES],
    /// The first wheel pass only records the counts.
    wheel_first_pass: bool,
}

impl Default for World {
    fn default() -> Self {
        World {
            mode: Mode::Free,
            axes: [Axis::default(); NUM_AXES],
            wheel_first_pass: true,
        }
    }
}

/// The axis index of an axis number from a command.
fn axis_index(axis: i32) -> Result<usize, Reject> {
    usize::try_from(axis)
        .ok()
        .filter(|&a| a < NUM_AXES)
        .ok_or(Reject::NoSuchAxis { axis })
}

impl MotionCore {
    // ----------------------------------------------------------------
    // Status

    /// Whether motion is in teleop mode, or will be on enable
    /// (`motion.teleop-mode`, LinuxCNC's TELEOP flag).
    pub fn teleop_mode(&self) -> bool {
        self.world.mode == Mode::Teleop
    }

    /// Whether motion is in coordinated mode, or will be on enable
    /// (`motion.coord-mode`, LinuxCNC's COORD flag).
    pub fn coord_mode(&self) -> bool {
        self.world.mode == Mode::Coord
    }

    /// A copy of world axis `axis`'s state (0..=8: X Y Z A B C U V W), or
    /// `None` if there is no such axis.
    pub fn axis(&self, axis: usize) -> Option<AxisStatus> {
        self.world.axes.get(axis).map(Axis::status)
    }

    /// Whether the kinematics compute world axis `axis` (true when they do
    /// not say).
    pub fn axis_in_kinematics(&self, axis: usize) -> bool {
        self.kins.has_axis(axis) != Some(false)
    }

    pub(crate) fn axis_ref(&self, axis: usize) -> &Axis {
        &self.world.axes[axis]
    }

    /// The state the cycle derives from the enable flag and the mode.
    pub(super) fn operating_state(&self) -> MotionState {
        if !self.enabled {
            return MotionState::Disabled;
        }
        match self.world.mode {
            Mode::Free => MotionState::Free,
            Mode::Teleop => MotionState::Teleop,
            Mode::Coord => MotionState::Coord,
        }
    }

    // ----------------------------------------------------------------
    // Mode requests

    /// FREE, TELEOP and COORD (see the module documentation).
    pub(super) fn request_mode(&mut self, mode: Mode) -> CommandResult {
        if mode != Mode::Free {
            self.world_mode_allowed()?;
            if !self.enabled && self.kins_type == KinematicsType::InverseOnly {
                return Err(Reject::NotEnabled);
            }
        }
        if !self.enabled {
            // Remembered; the enable edge enters it.
            self.world.mode = mode;
            return Ok(());
        }
        if mode == self.world.mode {
            return Ok(());
        }
        if self.something_moves() {
            return Err(Reject::NotInPosition);
        }
        if mode == Mode::Free {
            self.enter_free();
        } else {
            if self.world.mode == Mode::Free {
                self.carte_pos_cmd = self.entry_pose()?;
            }
            self.enter_world(mode);
        }
        Ok(())
    }

    /// The requirements of TELEOP and COORD that do not depend on motion.
    fn world_mode_allowed(&self) -> CommandResult {
        if self.kins_type == KinematicsType::ForwardOnly {
            return Err(Reject::Unsupported {
                what: Feature::WorldModeWithoutInverse,
            });
        }
        if self.kins_type != KinematicsType::Identity && !self.is_all_homed() {
            return Err(Reject::NotHomed);
        }
        Ok(())
    }

    /// Whether any planner moves or is about to (a jog accepted since the
    /// last cycle), or homing runs.
    fn something_moves(&self) -> bool {
        !self.inpos
            || self.homing_active()
            || self.joints.iter().any(|j| {
                j.active && (j.free_tp.active || j.kb_jog_active || j.wheel_jog_active || j.homing)
            })
            || self.axes_moving()
    }

    /// The pose for entering a world mode from free mode: forward
    /// kinematics of the joint commands, checked by running it back
    /// through the inverse kinematics. Changes nothing.
    fn entry_pose(&self) -> Result<Pose, Reject> {
        let n = self.kins_joints;
        let mut q = [0.0; MAX_JOINTS];
        for (p, jt) in q.iter_mut().zip(&self.joints[..n]) {
            *p = jt.coarse_pos;
        }
        let mut flags = self.kins_flags;
        let mut pose = self.pose_guess();
        self.kins
            .forward(&q[..n], &mut pose, &mut flags)
            .map_err(|_| Reject::KinematicsFailed)?;
        if pose.0.iter().any(|v| !v.is_finite()) {
            return Err(Reject::KinematicsFailed);
        }
        let mut back = q;
        self.kins
            .inverse(&pose, &mut back[..n], &mut flags)
            .map_err(|_| Reject::KinematicsFailed)?;
        for (j, jt) in self.joints[..n].iter().enumerate() {
            if !jt.active {
                continue;
            }
            let jump = (back[j] - q[j]).abs();
            if !jump.is_finite() {
                return Err(Reject::KinematicsFailed);
            }
            if jump > MODE_ENTRY_TOLERANCE {
                return Err(Reject::ModeChangeJump { joint: j, jump });
            }
        }
        Ok(pose)
    }

    /// The starting pose of a forward-kinematics call: the current command
    /// (axes the kinematics do not compute keep their value), or the world
    /// home when an iterative solver has no valid previous result.
    fn pose_guess(&self) -> Pose {
        if self.kins_type == KinematicsType::Both && !self.carte_pos_cmd_ok {
            self.world_home
        } else {
            self.carte_pos_cmd
        }
    }

    /// Enters teleop or coordinated mode at `carte_pos_cmd`.
    fn enter_world(&mut self, mode: Mode) {
        for jt in &mut self.joints {
            jt.rest_planner_at(jt.free_tp.curr_pos);
        }
        for (a, ax) in self.world.axes.iter_mut().enumerate() {
            ax.set_at_rest(self.carte_pos_cmd.0[a]);
        }
        self.carte_pos_cmd_ok = true;
        if mode == Mode::Coord {
            self.override_limit_mask = 0;
            self.overriding = false;
        }
        self.world.mode = mode;
        self.error = false;
        self.inpos = true;
        self.state = self.operating_state();
    }

    /// Leaves a world mode for free mode: each joint's free planner at rest
    /// at the joint's command, the axis planners at rest.
    fn enter_free(&mut self) {
        for jt in &mut self.joints {
            jt.rest_planner_at(jt.pos_cmd);
            jt.coarse_pos = jt.pos_cmd;
        }
        for ax in &mut self.world.axes {
            let here = ax.teleop_tp.curr_pos;
            ax.set_at_rest(here);
        }
        self.world.mode = Mode::Free;
        self.error = false;
        self.inpos = true;
        self.state = self.operating_state();
    }

    /// The disable edge: axis jogs end at once (the drives are off);
    /// inverse-only kinematics fall back to free mode.
    pub(super) fn world_disable_edge(&mut self) {
        for ax in &mut self.world.axes {
            ax.abort(true);
        }
        self.inpos = true;
        if self.kins_type == KinematicsType::InverseOnly {
            self.world.mode = Mode::Free;
        }
    }

    /// The enable edge, after the joints are enabled with their commands
    /// at the feedback: re-enters a remembered world mode at the forward
    /// kinematics of the joint commands, or falls back to free mode. No
    /// round-trip check here: feedback noise between gantry joints would
    /// fail it, and the following-error check guards the drives.
    pub(super) fn world_enable_edge(&mut self) {
        let mode = self.world.mode;
        if mode == Mode::Free {
            return;
        }
        let n = self.kins_joints;
        for jt in &mut self.joints[..n] {
            jt.coarse_pos = jt.pos_cmd;
        }
        let mut ok = self.world_mode_allowed().is_ok();
        if ok {
            self.load_positions(|jt| jt.pos_cmd);
            let mut pose = self.pose_guess();
            ok = self
                .kins
                .forward(&self.positions[..n], &mut pose, &mut self.kins_flags)
                .is_ok()
                && pose.0.iter().all(|v| v.is_finite());
            if ok {
                self.carte_pos_cmd = pose;
            }
        }
        if ok {
            self.enter_world(mode);
        } else {
            self.events.push(Event::WorldModeDropped);
            self.world.mode = Mode::Free;
        }
    }

    // ----------------------------------------------------------------
    // Axis commands

    /// The requirements every axis jog shares; returns the axis.
    fn axis_jog_checks(&self, axis: i32, vel: f64) -> Result<usize, Reject> {
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
        Ok(a)
    }

    /// Where an incremental jog starts from: the target of a running
    /// planner, the position of a stopped one.
    fn axis_jog_base(&self, a: usize) -> f64 {
        let tp = &self.world.axes[a].teleop_tp;
        if tp.enable {
            tp.pos_cmd
        } else {
            tp.curr_pos
        }
    }

    /// What every accepted axis jog does once its target is set.
    fn start_axis_jog(&mut self, a: usize, vel: f64) {
        let ax = &mut self.world.axes[a];
        ax.teleop_tp.max_vel = vel.abs().min(ax.cfg.vel_limit);
        ax.teleop_tp.max_acc = ax.cfg.acc_limit;
        ax.kb_jog_active = true;
        ax.teleop_tp.enable = true;
    }

    /// AXIS_JOG_CONT: towards the axis limit in the direction of `vel`.
    pub(super) fn axis_jog_cont(&mut self, axis: i32, vel: f64) -> CommandResult {
        let a = self.axis_jog_checks(axis, vel)?;
        let ax = &self.world.axes[a];
        let here = ax.teleop_tp.curr_pos;
        // From beyond a limit the jog would head for the limit, backwards.
        if vel > 0.0 && here > ax.cfg.max_pos_limit {
            return Err(Reject::AxisPastLimit {
                axis: a,
                dir: Direction::Positive,
            });
        }
        if vel < 0.0 && here < ax.cfg.min_pos_limit {
            return Err(Reject::AxisPastLimit {
                axis: a,
                dir: Direction::Negative,
            });
        }
        let target = if vel > 0.0 {
            ax.cfg.max_pos_limit
        } else {
            ax.cfg.min_pos_limit
        };
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
        let cfg = self.world.axes[a].cfg;
        if target > cfg.max_pos_limit || target < cfg.min_pos_limit {
            return Err(Reject::AxisTargetOutsideLimits {
                axis: a,
                target,
                min: cfg.min_pos_limit,
                max: cfg.max_pos_limit,
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
        let cfg = self.world.axes[a].cfg;
        // Written out: `f64::clamp` would panic on reversed bounds, which
        // the limit commands never allow anyway.
        let target = if pos > cfg.max_pos_limit {
            cfg.max_pos_limit
        } else if pos < cfg.min_pos_limit {
            cfg.min_pos_limit
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
        for (a, ax) in self.world.axes.iter_mut().enumerate() {
            ax.set_at_rest(self.carte_pos_cmd.0[a]);
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
            if ax.kb_jog_active {
                continue;
            }
            let distance = f64::from(delta) * inp.jog_scale;
            if !distance.is_finite() {
                continue;
            }
            let cfg = ax.cfg;
            let mut pos = ax.teleop_tp.pos_cmd + distance;
            if pos > cfg.max_pos_limit || pos < cfg.min_pos_limit {
                continue;
            }
            let acc = wheel_acc(cfg.acc_limit, inp.jog_accel_fraction);
            if inp.jog_vel_mode {
                // Stop when the wheel stops: never more than a stopping
                // distance ahead of the axis.
                let here = ax.teleop_tp.curr_pos;
                let stop_dist = cfg.vel_limit * cfg.vel_limit / (2.0 * acc);
                if pos > here + stop_dist {
                    pos = here + stop_dist;
                } else if pos < here - stop_dist {
                    pos = here - stop_dist;
                }
            }
            ax.teleop_tp.pos_cmd = pos;
            ax.teleop_tp.max_vel = cfg.vel_limit;
            ax.teleop_tp.max_acc = acc;
            ax.wheel_jog_active = true;
            ax.teleop_tp.enable = true;
        }
    }

    /// TELEOP position commands: the axis planners make the pose, the
    /// inverse kinematics the joint commands.
    pub(super) fn teleop_pos_cmds(&mut self, period: f64) {
        self.inpos = true;
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
            self.carte_pos_cmd.0[a] = ax.teleop_tp.curr_pos;
        }
        self.carte_pos_cmd_ok = true;
        self.joints_from_world(period);
        if self.overriding && self.inpos {
            self.override_limit_mask = 0;
            self.overriding = false;
        }
    }

    /// COORD position commands: the pose is held (no queued planner yet).
    pub(super) fn coord_pos_cmds(&mut self, period: f64) {
        self.abort_axis_jogs(true);
        self.carte_pos_cmd_ok = true;
        self.joints_from_world(period);
        self.inpos = true;
    }

    /// Inverse kinematics of `carte_pos_cmd` into the commands of the
    /// active kinematic joints. On failure nothing is written: an event,
    /// the motion error, and motion disabled in this same cycle.
    fn joints_from_world(&mut self, period: f64) {
        // The previous solution is the starting guess of iterative solvers.
        let n = self.load_positions(|jt| jt.coarse_pos);
        let solved = self.kins.inverse(
            &self.carte_pos_cmd,
            &mut self.positions[..n],
            &mut self.kins_flags,
        );
        if solved.is_err() {
            self.events.push(Event::InverseKinsFailed);
            self.world_fault();
            return;
        }
        let bad = (0..n).find(|&j| self.joints[j].active && !self.positions[j].is_finite());
        if let Some(joint) = bad {
            self.events.push(Event::NonFiniteJoint { joint });
            self.world_fault();
            return;
        }
        for (jt, &q) in self.joints[..n].iter_mut().zip(&self.positions[..n]) {
            if !jt.active {
                continue;
            }
            let prev = jt.pos_cmd;
            jt.coarse_pos = q;
            jt.pos_cmd = q;
            jt.vel_cmd = if period > 0.0 {
                (q - prev) / period
            } else {
                0.0
            };
            jt.acc_cmd = 0.0;
            jt.jerk_cmd = 0.0;
        }
    }

    /// A kinematics fault in a world mode: motion error and disable now
    /// (in LinuxCNC the next cycle; a command arriving in between could
    /// re-enable and repeat the fault every cycle).
    fn world_fault(&mut self) {
        self.error = true;
        self.abort_axis_jogs(true);
        self.enabling = false;
        self.set_operating_mode();
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
