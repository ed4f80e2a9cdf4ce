//! Locking indexers (`[AXIS_L]LOCKING_INDEXER_JOINT`): which axis is one,
//! and the rules for queued moves of it. A rapid that moves such an axis,
//! and no other, is queued as an indexer move (the planner unlocks the
//! joint around it, see [`crate::tp`]); a feed move, arc or probing move
//! of it, or a rapid that moves other axes with it, is refused: the
//! configuration reference says moving other joints together with a
//! locked rotary joint is not allowed, and LinuxCNC leaves such a move
//! unchecked (it would drive a clamped joint).

use super::teleop::axis_index;
use super::*;
use crate::command::{CommandResult, Reject};

/// Axes that differ by less than this between start and end are taken as
/// not moving (the planner's own shortest move).
const STILL: f64 = 1e-9;

impl MotionCore {
    /// SET_AXIS_LOCKING_INDEXER: `joint` (or -1 for none) drives world
    /// axis `axis` as a locking indexer. The joint needs unlock pins; only
    /// while disabled.
    pub(super) fn set_axis_locking_indexer(&mut self, axis: i32, joint: i32) -> CommandResult {
        let a = axis_index(axis)?;
        let j = if joint == -1 {
            None
        } else {
            let j = self.joint_index(joint)?;
            let lockable = j < 32 && self.cfg.unlock_joints_mask & (1 << j) != 0;
            if !lockable {
                return Err(Reject::NoUnlockPins { joint });
            }
            Some(j as u8)
        };
        if self.enabled {
            return Err(Reject::MustBeDisabled);
        }
        self.indexer_joint[a] = j;
        Ok(())
    }

    /// The locking indexer joint of the rapid to `end`, if it moves an
    /// indexer axis; `Err` for a move the rules refuse (`rapid`: whether
    /// it is a rapid).
    pub(super) fn indexer_move(&self, end: &Pose, rapid: bool) -> Result<Option<usize>, Reject> {
        let start = self.tp.goal();
        let moves = |a: usize| (end.0[a] - start.0[a]).abs() > STILL;
        let Some(axis) = (0..NUM_AXES).find(|&a| self.indexer_joint[a].is_some() && moves(a))
        else {
            return Ok(None);
        };
        if !rapid {
            return Err(Reject::IndexerNeedsRapid { axis });
        }
        if (0..NUM_AXES).any(|a| a != axis && moves(a)) {
            return Err(Reject::IndexerNotAlone { axis });
        }
        Ok(self.indexer_joint[axis].map(usize::from))
    }

    /// An arc or probing move may not move an indexer axis (it is never
    /// a rapid).
    pub(super) fn no_indexer_move(&self, end: &Pose) -> CommandResult {
        self.indexer_move(end, false).map(|_| ())
    }

    /// Each joint's `is-unlocked` as a mask (bit n: joint n).
    pub(super) fn unlocked_mask(&self) -> u32 {
        self.joint_inputs
            .iter()
            .take(32)
            .enumerate()
            .filter(|(_, inp)| inp.is_unlocked)
            .fold(0, |m, (j, _)| m | (1 << j))
    }

    /// Reports an indexer wait that ran out (the planner aborts the
    /// queue).
    pub(super) fn report_indexer_fault(&mut self) {
        if let Some(f) = self.tp.take_indexer_fault() {
            self.error = true;
            self.events.push(crate::events::Event::IndexerTimeout {
                joint: f.joint,
                unlocking: f.unlocking,
            });
        }
    }
}
