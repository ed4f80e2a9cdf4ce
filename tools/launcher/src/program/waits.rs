//! The ops of a program that wait on the world, carried out by task:
//! G10 L0's tool table reload, M19's wait for the spindle oriented and
//! the user M-code programs.

use std::path::Path;

use super::{user_m, Program, ProgramError};
use crate::iocontrol::IoControl;
use crate::motion_setup::MotionLink;

impl Program {
    /// G10 L0: iocontrol takes the tool table file as it is now; a file
    /// that cannot be read completely leaves the table in use (and stops
    /// write-backs over the user's half-made edit), and fails the run.
    pub(super) fn reload_tools(
        &mut self,
        io: &mut IoControl,
        line: i32,
    ) -> Result<(), ProgramError> {
        let Some(path) = self.tool_table.clone() else {
            return Err(ProgramError::NoToolTable { line });
        };
        match crate::iocontrol::ToolTable::load(&path, io.table().random) {
            Ok(table) => {
                io.reload(table);
                Ok(())
            }
            Err(source) => {
                io.hold_write_back();
                Err(ProgramError::ToolTable { line, path, source })
            }
        }
    }

    /// M19's wait: whether spindle `spindle` is oriented (or was never
    /// asked to be); an error when its orientation failed or `timeout`
    /// seconds passed, as LinuxCNC's task reports them.
    pub(super) fn oriented(
        &mut self,
        motion: &MotionLink,
        spindle: i32,
        timeout: f64,
        line: i32,
    ) -> Result<bool, ProgramError> {
        let status = motion.status().ok_or(ProgramError::NoMotionStatus)?;
        let state = usize::try_from(spindle)
            .ok()
            .and_then(|n| status.spindles.get(n));
        let Some(state) = state else {
            return Ok(true);
        };
        match state.orient {
            motion::OrientState::None | motion::OrientState::Complete => {
                self.orient_deadline = None;
                Ok(true)
            }
            motion::OrientState::Faulted => {
                self.orient_deadline = None;
                Err(ProgramError::OrientFault {
                    line,
                    fault: state.orient_fault,
                })
            }
            motion::OrientState::InProgress => {
                let now = std::time::Instant::now();
                let wait = std::time::Duration::try_from_secs_f64(timeout.max(0.0))
                    .unwrap_or(std::time::Duration::MAX);
                let deadline = *self
                    .orient_deadline
                    .get_or_insert_with(|| now.checked_add(wait).unwrap_or(now));
                if now >= deadline {
                    self.orient_deadline = None;
                    return Err(ProgramError::OrientTimeout { line });
                }
                Ok(false)
            }
        }
    }

    /// Starts the user M-code program (the first time) and tells whether
    /// it has exited well; an error if it could not start or failed.
    pub(super) fn user_m_done(
        &mut self,
        number: i32,
        program: &Path,
        p: f64,
        q: f64,
        at: &str,
    ) -> Result<bool, ProgramError> {
        let running = match &mut self.user_m_running {
            Some(r) => r,
            None => self
                .user_m_running
                .insert(user_m::Running::start(program, p, q).map_err(|source| {
                    ProgramError::UserMStart {
                        at: at.to_string(),
                        number,
                        program: program.to_path_buf(),
                        source,
                    }
                })?),
        };
        let status = running.poll().map_err(|source| ProgramError::UserMStart {
            at: at.to_string(),
            number,
            program: program.to_path_buf(),
            source,
        })?;
        let Some(status) = status else {
            return Ok(false);
        };
        self.user_m_running = None;
        if status.success() {
            Ok(true)
        } else {
            Err(ProgramError::UserMFailed {
                at: at.to_string(),
                number,
                program: program.to_path_buf(),
                how: user_m::exit_text(status),
            })
        }
    }
}
