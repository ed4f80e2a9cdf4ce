//! The machine's commands: ABORT, ENABLE, DISABLE and the legacy
//! amplifier commands (the mode requests are in `modes`).

use super::super::*;
use crate::command::{CommandResult, Reject};

impl MotionCore {
    /// ABORT: stops every free-mode move and queued motion, ends homing
    /// and jogs, clears the error flags.
    pub(in crate::core) fn abort(&mut self) -> CommandResult {
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

    /// ENABLE: the cycle enables once `motion.enable` allows.
    pub(in crate::core) fn enable(&mut self) -> CommandResult {
        if !self.inputs.enable {
            return Err(Reject::EnableInputFalse);
        }
        self.enabling = true;
        Ok(())
    }

    /// DISABLE.
    pub(in crate::core) fn disable(&mut self) -> CommandResult {
        self.enabling = false;
        Ok(())
    }

    /// ENABLE_AMPLIFIER and DISABLE_AMPLIFIER: taken and nothing done
    /// once the joint number is checked, as LinuxCNC 2.9's motion does.
    /// A joint's amplifier follows ENABLE/DISABLE and the joint's active
    /// state, so an amplifier can never be off while motion runs its
    /// joint (that would skip its limit and following-error checks).
    pub(in crate::core) fn amplifier(&mut self, joint: i32) -> CommandResult {
        self.joint_index(joint)?;
        Ok(())
    }
}
