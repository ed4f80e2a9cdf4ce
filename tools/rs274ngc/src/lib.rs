//! An RS274NGC G-code interpreter in LinuxCNC's dialect.
//!
//! The interpreter reads a program (or MDI lines) block by block and
//! makes canonical machining calls through the [`Canon`] trait, which
//! the caller implements; it asks the same trait about the world (the
//! position after a probe, the tool table). [`PrintCanon`] is a canon
//! that prints the calls as LinuxCNC's `rs274` does.
//!
//! ```no_run
//! use rs274ngc::{Config, Interp, PrintCanon, Status};
//! let mut canon = PrintCanon::new(Some(Box::new(std::io::stdout())), Vec::new());
//! let mut interp = Interp::new(Config::default());
//! interp.init(&mut canon)?;
//! interp.open(std::path::Path::new("part.ngc"), &mut canon)?;
//! loop {
//!     if interp.read(&mut canon)? == Status::EndFile {
//!         break;
//!     }
//!     if interp.execute(&mut canon)? == Status::Exit {
//!         break;
//!     }
//! }
//! # Ok::<(), rs274ngc::InterpError>(())
//! ```
//!
//! For task: [`Interp::read`] takes the next block and [`Interp::execute`]
//! runs it; reading ahead is calling them without waiting for motion,
//! until [`Status::ExecuteFinish`] says the world must be asked again
//! ([`Interp::synch`]: after a probe, a tool change, an input wait).
//! [`Interp::read_mdi`]/[`Interp::execute_mdi`] run typed lines,
//! [`Interp::reset`] and [`Interp::abort`] stop, and
//! [`Interp::sequence_number`], [`Interp::line_text`],
//! [`Interp::active_codes`] and [`Interp::settings`] report the line,
//! the modal state and the active offsets. [`list_refusals`] runs a whole
//! program against a canon that moves nothing and lists what is refused.
//!
//! The reader is this crate's own: LinuxCNC's dialect has bracketed
//! expressions, `#` and `#<name>` parameters, O-words and comments that
//! act (`(MSG,`, `(DEBUG,`, `(PRINT,`, `(LOG...`), which a plain G-code
//! tokenizer does not read, and the refusals must carry LinuxCNC's texts
//! and places. Spindle-synchronised moves (G33, G33.1 and the G76 threading
//! cycle) come out as LinuxCNC's canonical calls (START_SPEED_FEED_SYNCH,
//! RIGID_TAP, ...). The lathe cycles are LinuxCNC 2.9's: G70 finishing,
//! G71/G71.1/G71.2 roughing along Z and G72/G72.1/G72.2 roughing along X
//! (facing), with the profile in the O-word subroutine `Q` names (G0-G3
//! moves, U/W increments, A fillets and C chamfers), D the allowance
//! left (G70: the first pass's distance, E the last's, P the passes), I
//! the depth of cut, R the retract; .1 leaves the pockets and .2 cuts
//! only them. Their moves print as LinuxCNC's to the last digit (the
//! geometry rounds as C++'s `std::complex` does). Unlike LinuxCNC, a
//! profile subroutine that never returns and a cycle that would make
//! more than [`Config::max_cycle_moves`] moves are refused with a
//! message instead of running without end.

#![forbid(unsafe_code)]

mod arc;
mod block;
mod canon;
mod cfmt;
mod check;
mod codes;
mod comp;
mod config;
mod control;
mod cycles;
mod error;
mod exec;
mod find;
mod interp;
mod ld;
mod params;
mod print_canon;
mod read;
mod refusals;
mod setup;
mod source;
mod text;
pub mod tooltable;

pub mod fuzzing;

pub use canon::{
    Arc, Canon, ControlPoint, Direction, FeedReference, InputKind, MotionMode, Plane, Pose,
    ToolEntry, Units,
};
pub use cfmt::f as format_fixed;
pub use codes::g_text;
pub use config::{Config, Features};
pub use error::{InterpError, Result};
pub use interp::{ActiveCodes, Interp, Location, Status};
pub use params::file as parameter_file;
pub use print_canon::{PrintCanon, STANDALONE_LENGTH_UNITS};
pub use refusals::{
    list_refusals, list_refusals_for_machine, list_refusals_within, Refusal, MAX_CHECKED_BLOCKS,
};
pub use setup::Setup;
pub use source::{read_bounded, LINELEN, MAX_PROGRAM_BYTES};
