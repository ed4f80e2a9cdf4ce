//! Why task's program side refused a request or stopped a run.

use std::path::PathBuf;

use motion::Reject;
use rs274ngc::{InterpError, Location};

use super::RunState;
use crate::iocontrol::IoError;

/// A refusal of a program request, or the failure that ended a run.
#[derive(Debug, thiserror::Error)]
pub enum ProgramError {
    /// A program runs, so the request has to wait for its end.
    #[error("a program is running{hint}")]
    Running {
        /// What the operator can do (empty, or a parenthesised hint).
        hint: &'static str,
    },
    /// The tool changer faulted and the M6 was given up (iov2).
    #[error("{text}")]
    Toolchanger {
        /// `[TASK]IO_ERROR` with the reason, or the fault's description.
        text: String,
    },
    /// `run` before `open`.
    #[error("no program is open (task-cmd open FILE)")]
    NoProgram,
    /// Pause, resume or step asked in a state where it means nothing.
    #[error("{what} (program {})", .state.name())]
    WrongState {
        /// What was refused, in the operator's words.
        what: &'static str,
        /// The program's state.
        state: RunState,
    },
    /// The motion controller's status segment could not be read.
    #[error("the motion controller's status cannot be read")]
    NoMotionStatus,
    /// The interpreter failed outside a program line (starting,
    /// synchronising, saving its parameter file).
    #[error("{doing}: {source}")]
    Interpreter {
        /// What task was doing.
        doing: &'static str,
        /// The interpreter's error.
        #[source]
        source: InterpError,
    },
    /// The program file could not be opened by the interpreter.
    #[error("{}: {source}", .path.display())]
    Open {
        /// The program.
        path: PathBuf,
        /// Why.
        #[source]
        source: InterpError,
    },
    /// The interpreter refused a program line.
    #[error("{at}: {source}")]
    Line {
        /// The file, line, column and word (boxed: it is large).
        at: Box<Location>,
        /// Why.
        #[source]
        source: InterpError,
    },
    /// The interpreter refused an MDI line.
    #[error("MDI '{text}': {source}")]
    Mdi {
        /// The line as given.
        text: String,
        /// Why.
        #[source]
        source: InterpError,
    },
    /// A program line asked for something task cannot do yet.
    #[error("{at}: {what}: not supported by task yet")]
    Unsupported {
        /// Where, as the interpreter reports it (a program place or
        /// `MDI 'line'`).
        at: String,
        /// The machine call, with its G- or M-code.
        what: String,
    },
    /// The motion controller refused a pause, resume or step.
    #[error(transparent)]
    Motion(Reject),
    /// The motion controller refused a command of a program line or an
    /// MDI line.
    #[error("{at}: {source}")]
    MotionAt {
        /// Where the command came from: `line N` or `MDI 'text'`.
        at: String,
        /// The controller's answer.
        #[source]
        source: Reject,
    },
    /// The motion controller reported a fault while the run moved the
    /// machine; the run is aborted.
    #[error("{at}: {fault}: the motion controller stopped; the run is aborted")]
    MotionFault {
        /// The file and the line motion was executing (or the MDI line).
        at: String,
        /// What motion reported.
        fault: motion::Fault,
    },
    /// G10 L0 on a machine without a tool table file.
    #[error("line {line}: G10 L0: the machine has no tool table file ([EMCIO]TOOL_TABLE)")]
    NoToolTable {
        /// The program line.
        line: i32,
    },
    /// G10 L0 could not read the tool table file; the table in use stays.
    #[error("line {line}: G10 L0: {}: {source}", .path.display())]
    ToolTable {
        /// The program line.
        line: i32,
        /// The tool table file.
        path: PathBuf,
        /// Why.
        #[source]
        source: crate::iocontrol::tooltable::TableError,
    },
    /// M19: the drive reported `spindle.N.orient-fault` while orienting.
    #[error("line {line}: fault {fault} during orient in progress")]
    OrientFault {
        /// The program line.
        line: i32,
        /// The fault code.
        fault: i32,
    },
    /// M19 Q: `is-oriented` did not come in time.
    #[error("line {line}: wait for orient complete: TIMED OUT")]
    OrientTimeout {
        /// The program line.
        line: i32,
    },
    /// A G38.2 or G38.4 move ended without finding what it looked for.
    #[error("line {line}: {why}")]
    Probe {
        /// The program line.
        line: i32,
        /// Motion's message.
        why: String,
    },
    /// A user M-code program (M100 to M199) could not be started.
    #[error("{at}: M{number}: cannot run {}: {source}", .program.display())]
    UserMStart {
        /// The program place (file:line, or the MDI line).
        at: String,
        /// The M-code number.
        number: i32,
        /// The program task found for it.
        program: PathBuf,
        /// Why it did not start.
        #[source]
        source: std::io::Error,
    },
    /// A user M-code program exited with a non-zero status or a signal.
    #[error("{at}: M{number}: {} {how}", .program.display())]
    UserMFailed {
        /// The program place (file:line, or the MDI line).
        at: String,
        /// The M-code number.
        number: i32,
        /// The program.
        program: PathBuf,
        /// How it ended (`exited with status 3`).
        how: String,
    },
    /// iocontrol refused a tool or coolant request of the program.
    #[error(transparent)]
    Io(#[from] IoError),
}

/// LinuxCNC's interpreter return code for an error (`INTERP_ERROR`).
pub const INTERP_ERROR: i32 = 5;

impl ProgramError {
    /// The interpreter return code LinuxCNC's task keeps for this error
    /// (`stat.interpreter_errcode`): [`INTERP_ERROR`] for what the
    /// interpreter itself refused (a program or MDI line, opening a
    /// program, its start-up or synchronisation); `None` for refusals
    /// by task, motion or iocontrol.
    pub fn interp_errcode(&self) -> Option<i32> {
        matches!(
            self,
            ProgramError::Interpreter { .. }
                | ProgramError::Open { .. }
                | ProgramError::Line { .. }
                | ProgramError::Mdi { .. }
        )
        .then_some(INTERP_ERROR)
    }
}
