//! Commands to the motion controller and their typed results.
//!
//! LinuxCNC answers most refused commands with "OK" and a text message
//! only; here every command is either applied completely or refused with a
//! [`Reject`] that says why, and a refusal changes nothing. Commands and
//! rejections are plain `Copy` data, so the realtime command handler can
//! take and answer them without allocating.
//!
//! Each command is described once, in `table` (its fields, its opcode and
//! the words it travels in, its command lines); `define` turns that into
//! the [`Command`] enum, its wire form (`wire`, used by the channel's
//! records), its names, [`parse`] and [`Command::to_cli`] (`cli`). The
//! refusals live in the leaf `vocab`, shared with homing.

mod cli;
mod define;
mod queueing;
mod table;
pub(crate) mod wire;

pub use crate::vocab::{
    axis_letter, reject_code, result_name, CommandResult, Direction, Feature, Quantity, Reject,
    RejectWire, WireError,
};
pub use cli::{CliError, CliGroup};
pub use queueing::{LineKind, ProbeType, TermCond};
pub use table::{cli_group, parse, Command, CLI_NAMES};

#[cfg(test)]
mod tests;
