//! What task does for a program, one [`Op`] at a time in program order:
//! the canon queues them, task carries them out.

use std::path::PathBuf;

use motion::command::ProbeType;
use motion::Command;

use crate::iocontrol::IoRequest;

/// One thing task does for the program, in program order.
#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    /// A command for motion's queue (moves, dwell, planner settings).
    Motion(Command),
    /// An iocontrol request (tool prepare, change, number; coolant), once
    /// the moves before it have finished.
    Io(IoRequest),
    /// A motion command sent once the moves before it have ended, as
    /// LinuxCNC's task sends them: spindle starts, speed changes and
    /// stops (the feed move after a start or speed change waits in
    /// motion for `spindle.N.at-speed`), and the immediate outputs M64,
    /// M65, M68 (which therefore break blending, as LinuxCNC's).
    AfterMoves {
        /// The command.
        command: Command,
        /// The program line it comes from.
        line: i32,
    },
    /// M66: once the moves before it end, wait for an input.
    WaitInput {
        /// The input number.
        index: i32,
        /// `motion.digital-in-NN` (P), else `motion.analog-in-NN` (E).
        digital: bool,
        /// LinuxCNC's L: 0 at once, 1 rise, 2 fall, 3 high, 4 low.
        mode: i32,
        /// Seconds at most (Q).
        timeout: f64,
    },
    /// M0 (or M1 when `optional`): stop once the moves before it end.
    Stop {
        /// M1: stops only with the optional stop switch on.
        optional: bool,
    },
    /// M2, M30: the program ends once the moves before it end.
    End,
    /// (MSG,...), (DEBUG,...), (PRINT,...): text for the operator.
    Message(String),
    /// G10 L0: once the moves before it end, read the tool table file
    /// again; reading waits, then the interpreter takes the new table.
    ReloadTools {
        /// The program line.
        line: i32,
    },
    /// M19 with Q: once the moves before it end, wait until spindle
    /// `spindle` is oriented (`is-oriented`), at most `timeout` seconds.
    WaitOrient {
        /// The spindle number.
        spindle: i32,
        /// Seconds at most.
        timeout: f64,
        /// The program line.
        line: i32,
    },
    /// After a G38.2 or G38.4 move: once it has ended, a probe that did
    /// not find what it looked for fails the run.
    ProbeCheck {
        /// What the move looked for.
        probe: ProbeType,
        /// The program line.
        line: i32,
    },
    /// M100 to M199: once the moves before it end, run the user program
    /// with P and Q and wait for it to exit.
    UserM {
        /// The M-code number.
        number: i32,
        /// The program found for it.
        program: PathBuf,
        /// The P and Q words (-1 when absent).
        p: f64,
        /// See `p`.
        q: f64,
        /// The program place (file:line, or the MDI line), for errors;
        /// task fills it in after the block executed.
        at: String,
    },
}
