//! External axis offsets in the controller: each axis's
//! [`ExtOffset`](crate::eoffset::ExtOffset) takes its pins every cycle,
//! moves in teleop and coordinated mode, and is added to the planned pose
//! there (the commanded pose is planned + offset; the kinematics see the
//! sum).
//!
//! Where the planned pose comes from when a world mode is entered: the
//! commanded pose less the offsets, so entering a mode, or switching
//! kinematics, moves nothing. In free mode the offsets stand still (the
//! joints keep the positions they had, offsets included); counts still add
//! to the requests, which the offsets follow once a world mode is entered
//! again. Free mode is refused while an offset moves.
//!
//! Machine off and on, as LinuxCNC's documentation has it: disabling keeps
//! everything where it is (the commands follow the feedback, which holds
//! the offset, and `axis.L.eoffset` still shows it); the enable edge zeroes
//! every offset and its request before the world mode is re-entered at the
//! feedback, so the planned position takes over the offset's place and
//! nothing moves. A program's end changes nothing here (that is task's).

use super::*;
use crate::eoffset::Intake;
use crate::events::Event;

impl MotionCore {
    /// Takes the `axis.L.eoffset-*` inputs of this cycle. Counts are taken
    /// while motion is enabled and every joint homed. An enable input
    /// falling while its offset is not zero is reported (as LinuxCNC
    /// does): the offset stays.
    pub(super) fn take_eoffset_inputs(&mut self, period: f64) {
        let may_request = self.enabled && self.is_all_homed();
        let axes = self.world.axes.iter_mut().zip(&self.axis_inputs);
        for (a, (ax, inp)) in axes.enumerate() {
            let intake = if ax.cfg.eoffset_ratio <= 0.0 {
                Intake::Off
            } else if may_request {
                Intake::Accept
            } else {
                Intake::Hold
            };
            let was_enabled = ax.eoffset.enabled();
            ax.eoffset.take_inputs(&inp.eoffset, intake);
            let (_, acc) = ax.cfg.eoffset_limits();
            if was_enabled
                && !ax.eoffset.enabled()
                && self.enabled
                && ax.eoffset.is_active(acc, period)
            {
                self.events
                    .push(Event::EoffsetDisabledWhileApplied { axis: a });
            }
        }
    }

    /// The enable edge: every offset and request back to zero.
    pub(super) fn reset_eoffsets(&mut self) {
        for ax in &mut self.world.axes {
            ax.eoffset.reset();
        }
        self.world.eoffset_limited = false;
    }

    /// One period of every offset in a world mode: moved, bounded by the
    /// soft limits around `planned`, and added to it. Returns the commanded
    /// pose and sets `motion.eoffset-limited`.
    pub(super) fn add_eoffsets(&mut self, period: f64, planned: &Pose) -> Pose {
        let mut pose = *planned;
        let mut limited = false;
        for (a, ax) in self.world.axes.iter_mut().enumerate() {
            let cfg = ax.cfg;
            let limits = (cfg.min_pos_limit, cfg.max_pos_limit);
            let o = ax
                .eoffset
                .update(period, cfg.eoffset_limits(), planned.0[a], limits);
            if o != 0.0 {
                pose.0[a] = planned.0[a] + o;
            }
            limited |= ax.eoffset.limited();
        }
        self.world.eoffset_limited = limited;
        pose
    }

    /// `pose` less the applied offsets: the planned pose of a commanded
    /// one.
    pub(super) fn without_eoffsets(&self, pose: &Pose) -> Pose {
        let mut planned = *pose;
        for (p, ax) in planned.0.iter_mut().zip(&self.world.axes) {
            let o = ax.eoffset.applied();
            if o != 0.0 {
                *p -= o;
            }
        }
        planned
    }

    /// Whether any offset planner moves.
    pub(super) fn eoffsets_moving(&self) -> bool {
        self.world.axes.iter().any(|ax| ax.eoffset.moving())
    }

    /// After the position commands: `motion.eoffset-active` for this
    /// cycle, and no limit flag outside the world modes.
    pub(super) fn eoffset_flags(&mut self, period: f64) {
        if !matches!(self.state, MotionState::Teleop | MotionState::Coord) {
            self.world.eoffset_limited = false;
        }
        self.world.eoffset_active = self.world.axes.iter().any(|ax| {
            let (_, acc) = ax.cfg.eoffset_limits();
            ax.eoffset.is_active(acc, period)
        });
    }

    /// `motion.eoffset-active`: some applied offset is not zero.
    pub fn eoffset_active(&self) -> bool {
        self.world.eoffset_active
    }

    /// `motion.eoffset-limited`: an axis with an offset sits on a soft
    /// limit.
    pub fn eoffset_limited(&self) -> bool {
        self.world.eoffset_limited
    }
}
