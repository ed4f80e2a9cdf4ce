//! What status readers see of the program side, and starting the
//! interpreter afresh (the `stat` and `reset-interpreter` requests).

use super::{IoControl, MotionLink, Program, ProgramError};

/// What status readers see of the program side ([`Program::view`]).
pub struct ProgramView<'a> {
    /// The open program.
    pub file: Option<&'a std::path::Path>,
    /// The program line of the last block read.
    pub read_line: i32,
    /// The modal codes, feed and speed in effect.
    pub codes: rs274ngc::ActiveCodes,
    /// MDI lines waiting to run.
    pub queued_mdi: usize,
}

impl Program {
    /// The open program, if any; the program line read last; the
    /// interpreter's modal codes; the MDI lines waiting.
    pub fn view(&self) -> ProgramView<'_> {
        ProgramView {
            file: self.file.as_deref(),
            read_line: self.read_line,
            codes: self.interp.active_codes(),
            queued_mdi: self.mdi.len(),
        }
    }

    /// Starts the interpreter afresh (LinuxCNC's reset_interpreter): its
    /// start-up modal state and the parameter file as saved, then the
    /// INI's `RS274NGC_STARTUP_CODE` (in the next cycle). Refused while
    /// something runs.
    pub fn reset_interpreter(
        &mut self,
        motion: &MotionLink,
        io: &IoControl,
    ) -> Result<(), ProgramError> {
        if !self.settled() {
            return Err(ProgramError::Running {
                hint: " (abort it before resetting the interpreter)",
            });
        }
        self.initialised = false;
        self.synch(motion, io)?;
        self.startup_due = self.startup_code.is_some();
        Ok(())
    }
}
