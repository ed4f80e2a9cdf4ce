//! The end of the iocontrol handshakes a run waits for, and what a tool
//! changer's fault does to the run.

use super::{Program, ProgramError};
use crate::iocontrol::IoEvent;

impl Program {
    /// Ends the iocontrol handshake an op waits for. A change that the
    /// tool changer's fault gave up (iov2) goes on without the tool on a
    /// soft fault (a positive reason) and stops the run on a hard one,
    /// as LinuxCNC's task does.
    pub(super) fn io_events(&mut self, events: &[IoEvent]) -> Result<(), ProgramError> {
        for e in events {
            match *e {
                IoEvent::Prepared { .. } | IoEvent::Changed { .. } | IoEvent::StartChangeAcked => {
                    self.io_busy = false;
                }
                IoEvent::ChangeFaulted { reason } if reason > 0 => {
                    eprintln!("task: M6: toolchanger soft fault=1, reason={reason}");
                    self.io_busy = false;
                }
                IoEvent::ChangeFaulted { reason } => {
                    return Err(ProgramError::Toolchanger {
                        text: crate::iocontrol::v2::hard_fault_text(&self.io_error, reason),
                    });
                }
            }
        }
        Ok(())
    }
}
