//! The HAL tools: the host process, its socket protocol, and halcmd's
//! language (used by the `halcmd` and `halrun` binaries).

pub mod cli;
pub mod meter;
pub mod motion_queue_args;
pub mod tool_args;

pub mod stdio;
mod error;

pub use error::ToolsError;
/// Printing to a standard output that may close: [`hal_core::stdio`].
pub use hal_core::{out, outln};
