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
pub use config::{Config, Features};
pub use error::{InterpError, Result};
pub use interp::{ActiveCodes, Interp, Location, Status};
pub use params::file as parameter_file;
pub use print_canon::{PrintCanon, STANDALONE_LENGTH_UNITS};
pub use refusals::{list_refusals, list_refusals_within, Refusal, MAX_CHECKED_BLOCKS};
pub use setup::Setup;
pub use source::{read_bounded, LINELEN, MAX_PROGRAM_BYTES};
