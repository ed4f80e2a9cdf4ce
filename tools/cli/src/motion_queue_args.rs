//! `motion-cmd`'s queueing and planner commands: which commands they are,
//! and parsing their arguments into [`Command`]s, both as motion's command
//! table says ([`motion::command::parse`], [`motion::command::cli_group`]).
//! A move's end point is given as `AXIS=VALUE` words (`X=10 Y=-2.5`); the
//! axes left out stay where the last queued move ends (the status
//! snapshot's goal), so nothing moves by accident.

use motion::command::{cli_group, CliGroup, Command};
use motion::kins::Pose;

/// What went wrong with the arguments (printed with a hint to --help).
pub use motion::command::CliError as ArgError;

/// Whether `name` is one of this module's commands.
pub fn is_queue_command(name: &str) -> bool {
    cli_group(name) == Some(CliGroup::Planner)
}

/// Parses one of the queueing or planner commands. `goal` is where the
/// last queued move ends (axes left out of an end point keep it).
pub fn parse(name: &str, a: &[String], goal: Pose) -> Result<Command, ArgError> {
    if !is_queue_command(name) {
        return Err(ArgError::UnknownCommand {
            name: name.to_string(),
        });
    }
    motion::command::parse(name, a, goal)
}
