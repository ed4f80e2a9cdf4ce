//! The FREE/TELEOP/COORD mode requests, what entering and leaving a mode
//! does, and the world modes' inverse kinematics.
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

use super::*;
use crate::axis::{Axis, AxisStatus};
use crate::command::{CommandResult, Feature, Reject};
use crate::events::Event;

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
    pub(super) wheel_first_pass: bool,
    /// `motion.eoffset-active`.
    pub(super) eoffset_active: bool,
    /// `motion.eoffset-limited`.
    pub(super) eoffset_limited: bool,
}

impl Default for World {
    fn default() -> Self {
        World {
            mode: Mode::Free,
            axes: [Axis::default(); NUM_AXES],
            wheel_first_pass: true,
            eoffset_active: false,
            eoffset_limited: false,
        }
    }
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
        if self.something_moves() || (mode == Mode::Free && self.eoffsets_moving()) {
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
    pub(super) fn world_mode_allowed(&self) -> CommandResult {
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
    pub(super) fn something_moves(&self) -> bool {
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
    pub(super) fn entry_pose(&self) -> Result<Pose, Reject> {
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
    pub(super) fn pose_guess(&self) -> Pose {
        if self.kins_type == KinematicsType::Both && !self.carte_pos_cmd_ok {
            self.world_home
        } else {
            self.carte_pos_cmd
        }
    }

    /// Enters teleop or coordinated mode at `carte_pos_cmd`: the planners
    /// start from it less the external offsets.
    pub(super) fn enter_world(&mut self, mode: Mode) {
        for jt in &mut self.joints {
            jt.rest_planner_at(jt.free_tp.curr_pos);
        }
        let planned = self.without_eoffsets(&self.carte_pos_cmd);
        for (a, ax) in self.world.axes.iter_mut().enumerate() {
            ax.set_at_rest(planned.0[a]);
        }
        self.carte_pos_cmd_ok = true;
        if mode == Mode::Coord {
            self.override_limit_mask = 0;
            self.overriding = false;
        }
        // The queue starts empty at the pose (LinuxCNC's tpSetPos).
        self.tp.set_pos(planned);
        self.world.mode = mode;
        self.error = false;
        self.inpos = true;
        self.state = self.operating_state();
    }

    /// Leaves a world mode for free mode: each joint's free planner at rest
    /// at the joint's command, the axis planners at rest.
    pub(super) fn enter_free(&mut self) {
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
        // The drives are off: the queue goes at once (LinuxCNC's tpClear).
        self.tp.clear();
        self.end_probing();
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

    /// Inverse kinematics of `carte_pos_cmd` into the commands of the
    /// active kinematic joints. On failure nothing is written: an event,
    /// the motion error, and motion disabled in this same cycle.
    pub(super) fn joints_from_world(&mut self, period: f64) {
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
    pub(super) fn world_fault(&mut self) {
        self.error = true;
        self.abort_axis_jogs(true);
        self.enabling = false;
        self.set_operating_mode();
    }
}
