//! The error of the HAL command language.

use std::path::PathBuf;
use std::process::ExitStatus;

use hal_core::HalError;

use crate::protocol::ClientError;
use crate::values::ValueError;

/// Why a halcmd command, or starting or reaching a host, failed.
///
/// Every message is halcmd's, word for word as LinuxCNC's halcmd prints
/// it where LinuxCNC has one (the golden files compare them byte for
/// byte). Errors of the HAL library and of the host's socket keep their
/// own text and stay reachable as the source.
#[derive(Debug, thiserror::Error)]
pub enum LangError {
    /// The HAL library refused.
    #[error(transparent)]
    Hal(#[from] HalError),
    /// The host could not be reached, or refused the request (its message).
    #[error(transparent)]
    Host(#[from] ClientError),
    /// A command this language does not have.
    #[error("Unknown command '{name}'")]
    UnknownCommand {
        /// The first word.
        name: String,
    },
    /// `show`, `list`, `save` or `status` given a kind it does not have.
    #[error("Unknown '{command}' type '{kind}'")]
    UnknownKind {
        /// The command.
        command: &'static str,
        /// The word given as its kind.
        kind: String,
    },
    /// A `-tTYPE` filter naming no HAL type.
    #[error("unknown type '{name}'")]
    UnknownType {
        /// The word after `-t`.
        name: String,
    },
    /// `help COMMAND` for a command that does not exist.
    #[error("No help for unknown command '{command}'")]
    NoHelp {
        /// The word given.
        command: String,
    },
    /// No parameter and no pin of this name.
    #[error("parameter or pin '{name}': not found")]
    NoPinOrParam {
        /// The name given.
        name: String,
    },
    /// No signal of this name.
    #[error("signal '{name}': not found")]
    NoSignal {
        /// The name given.
        name: String,
    },
    /// A value that does not parse as the object's type.
    #[error("{what} '{name}': {source}")]
    BadValue {
        /// `pin`, `parameter` or `signal`.
        what: &'static str,
        /// The object's name.
        name: String,
        /// What is wrong with the value.
        #[source]
        source: ValueError,
    },
    /// A pin, parameter or signal that may not be written.
    #[error("{what} '{name}': not writable")]
    NotWritable {
        /// `pin`, `parameter` or `signal`.
        what: &'static str,
        /// The object's name.
        name: String,
    },
    /// `lock WORD` or `unlock WORD` with a word it does not know.
    #[error("{action} failed: unknown {command} type '{word}' (use all, none, tune, load, config, params or run)")]
    LockWord {
        /// `Locking` or `Unlocking`.
        action: &'static str,
        /// `lock` or `unlock`.
        command: &'static str,
        /// The word given.
        word: String,
    },
    /// A file `source` or `save` could not read or write.
    #[error("{command} {file}: {source}")]
    File {
        /// `source`, or `save:` (as LinuxCNC words it).
        command: &'static str,
        /// The file.
        file: String,
        /// The error from the file system.
        #[source]
        source: std::io::Error,
    },
    /// `loadusr` could not start its program.
    #[error("loadusr: cannot run '{program}': {source}")]
    Spawn {
        /// The program.
        program: String,
        /// The error from exec.
        #[source]
        source: std::io::Error,
    },
    /// A host is already running for the instance.
    #[error("realtime is already running for instance '{instance}'")]
    AlreadyRunning {
        /// The instance.
        instance: String,
    },
    /// The host program could not be started.
    #[error("starting {}: {source}", binary.display())]
    HostSpawn {
        /// The `hal-host` program.
        binary: PathBuf,
        /// The error from exec.
        #[source]
        source: std::io::Error,
    },
    /// The host exited before it answered.
    #[error("the HAL host exited at start-up ({status}){why}")]
    HostExited {
        /// How it exited.
        status: ExitStatus,
        /// `: ` and its log, for a detached host; else empty.
        why: String,
    },
    /// A detached host's log file.
    #[error("{}: {source}", path.display())]
    Log {
        /// The log file.
        path: PathBuf,
        /// The error from the file system.
        #[source]
        source: std::io::Error,
    },
    /// A command refused by the session's [`crate::CommandFilter`] (the
    /// launcher's TWOPASS merging), with the filter's own error.
    #[error(transparent)]
    Filter(Box<dyn std::error::Error + Send + Sync>),
    /// Any other failure of a command, in halcmd's words. These messages
    /// are LinuxCNC's text (compared byte for byte by the golden files),
    /// one for nearly each check of each command: they are kept as text
    /// rather than a variant each.
    #[error("{message}")]
    Halcmd {
        /// The message, without file and line.
        message: String,
    },
}

impl LangError {
    /// A failure in halcmd's words.
    pub fn halcmd(message: impl Into<String>) -> LangError {
        LangError::Halcmd {
            message: message.into(),
        }
    }
}

/// A result of the HAL command language.
pub type Result<T, E = LangError> = std::result::Result<T, E>;
