//! Task watching motion while a program or MDI line runs: the line
//! motion executes, and the faults motion reports (its message count and
//! last message in the status snapshot), which end the run.

use std::path::Path;

use super::{Program, ProgramError, RunState};
use crate::motion_setup::MotionLink;

impl Program {
    /// Starts watching motion's messages and lines for a new run.
    pub(super) fn watch_from(&mut self, motion: &MotionLink) {
        self.motion_line = 0;
        if let Some(status) = motion.status() {
            self.seen_faults = status.faults_reported;
        }
    }

    /// Follows the line motion executes; a fault motion reported since
    /// the run started (a following error, a limit, an amplifier fault,
    /// motion disabled by its enable input...) ends the run, naming the
    /// line that was moving, as LinuxCNC's task aborts on a motion error.
    pub(super) fn watch_motion(
        &mut self,
        status: &motion::MotionStatus,
    ) -> Result<(), ProgramError> {
        if self.state == RunState::Idle {
            return Ok(());
        }
        if status.traj.exec_id > 0 {
            self.motion_line = status.traj.exec_id;
        }
        if status.faults_reported == self.seen_faults {
            return Ok(());
        }
        self.seen_faults = status.faults_reported;
        match status.last_fault {
            Some(fault) => Err(ProgramError::MotionFault {
                at: self.motion_place(),
                fault,
            }),
            None => Ok(()),
        }
    }

    /// Where the run is, as motion sees it: `file:line` of the line
    /// moving (or last moved), or the MDI line.
    fn motion_place(&self) -> String {
        if self.is_mdi {
            return format!("MDI '{}'", self.mdi_text);
        }
        let file = self.file.as_deref().unwrap_or(Path::new(""));
        format!("{}:{}", file.display(), self.motion_line)
    }
}
