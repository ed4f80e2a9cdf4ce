//! The programs of the HAL suite (`src/bin`): halrun, halcmd, haltcl,
//! realtime and hal-host, halmeter, halsampler, halstreamer, halscope,
//! latency-test, linuxcnc, task-cmd, gcode-run, motion-cmd and
//! motion-plot. Each is a thin command line over the crate that does its
//! job (`hal-lang`, `hal-host`, `hal-launcher`, `hal-scope`, `motion`);
//! this library holds only what the command lines share: halcmd's and
//! halrun's options and interactive mode ([`cli`]), halmeter's reading
//! ([`meter`]), motion-cmd's queue arguments, the clap definitions the
//! man pages are built from ([`tool_args`]) and the programs' edges
//! ([`stdio`], [`out!`], [`outln!`]).
//!
//! The programs live together in this one package because their tests
//! run them together (halrun starts hal-host; linuxcnc, task-cmd and
//! motion-cmd drive one machine): cargo builds for a package's tests only
//! that package's binaries.

#![forbid(unsafe_code)]

pub mod cli;
pub mod conventions;
mod error;
pub mod gcode_check;
pub mod gcode_task;
pub mod inivar;
pub mod line_editor;
pub mod meter;
pub mod motion_queue_args;
pub mod rsh;
pub mod stdio;
pub mod task_gate;
pub mod tool_args;
pub mod usage;

pub use error::ToolsError;
/// Printing to a standard output that may close: [`hal_core::stdio`].
pub use hal_core::{out, outln};
