//! The machine's shape as task gives it at start-up: how many joints and
//! spindles it uses (SET_NUM_JOINTS, SET_NUM_SPINDLES), and the tool
//! offset in effect (SET_OFFSET).

use super::super::*;
use crate::command::{CommandResult, Quantity, Reject};

/// `count` as a number of joints or spindles motion was loaded with
/// `loaded` of: 1 to `loaded`, else `None`.
fn count_within(count: i32, loaded: usize) -> Option<usize> {
    usize::try_from(count)
        .ok()
        .filter(|&n| (1..=loaded).contains(&n))
}

impl MotionCore {
    /// SET_NUM_JOINTS: commands may name joints `0..joints` only; the
    /// joints above are made inactive. Only while disabled.
    pub(in crate::core) fn set_num_joints(&mut self, joints: i32) -> CommandResult {
        let loaded = self.joints.len();
        let n = count_within(joints, loaded).ok_or(Reject::BadJointCount {
            count: joints,
            loaded,
        })?;
        if self.enabled {
            return Err(Reject::MustBeDisabled);
        }
        for jt in &mut self.joints[n..] {
            jt.active = false;
            jt.enabled = false;
            jt.free_tp.enable = false;
        }
        self.joints_in_use = n;
        Ok(())
    }

    /// The joints commands may name (SET_NUM_JOINTS).
    pub fn joints_in_use(&self) -> usize {
        self.joints_in_use
    }

    /// SET_NUM_SPINDLES: commands may name spindles `0..spindles` only;
    /// the spindles above are stopped, brake applied. Only while
    /// disabled.
    pub(in crate::core) fn set_num_spindles(&mut self, spindles: i32) -> CommandResult {
        let loaded = self.cfg.num_spindles;
        let n = count_within(spindles, loaded).ok_or(Reject::BadSpindleCount {
            count: spindles,
            loaded,
        })?;
        if self.enabled {
            return Err(Reject::MustBeDisabled);
        }
        for s in &mut self.spindles[n..loaded] {
            s.on = false;
            s.speed = 0.0;
            s.brake = true;
        }
        self.spindles_in_use = n;
        Ok(())
    }

    /// The spindles commands may name (SET_NUM_SPINDLES).
    pub fn spindles_in_use(&self) -> usize {
        self.spindles_in_use
    }

    /// SET_OFFSET: the tool offset in effect, every coordinate finite.
    pub(in crate::core) fn set_tool_offset(&mut self, offset: Pose) -> CommandResult {
        for v in offset.0 {
            Self::finite(Quantity::ToolOffset, v)?;
        }
        self.tool_offset = offset;
        Ok(())
    }

    /// The tool offset SET_OFFSET gave (`motion.tooloffset.L`).
    pub fn tool_offset(&self) -> Pose {
        self.tool_offset
    }
}
