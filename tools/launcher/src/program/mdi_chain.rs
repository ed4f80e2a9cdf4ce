//! Queued MDI lines run back to back, as LinuxCNC's task runs them: the
//! next line is read as soon as everything the last one asked for has gone
//! out (its moves queued in motion), not once the machine has stopped, so
//! the moves of consecutive lines blend as a program's do (`G64`). A line
//! that needs the machine settled first (a queue buster: tool change,
//! probe, a parameter read after motion) still waits for motion to end.

use super::{Program, ProgramError, RunState};

impl Program {
    /// Whether the next queued MDI line may start while motion still runs
    /// the last one's moves.
    pub(super) fn can_chain_mdi(&self) -> bool {
        self.state == RunState::Running
            && self.is_mdi
            && self.read_done
            && !self.mdi.is_empty()
            && !self.needs_synch
            && !self.io_busy
            && self.canon.ops.is_empty()
            && self.input_wait.is_none()
            && self.orient_deadline.is_none()
            && self.user_m_running.is_none()
    }

    /// Reads the next queued MDI line into the running MDI run, without
    /// synchronising the interpreter with a machine that is still moving
    /// (it carries on from where the last line left it).
    pub(super) fn chain_next_mdi(&mut self) -> Result<(), ProgramError> {
        let Some(text) = self.mdi.pop_front() else {
            return Ok(());
        };
        self.read_done = false;
        self.mdi_text.clone_from(&text);
        self.execute_mdi(&text)
    }
}
