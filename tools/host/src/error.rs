//! The error of the host.

use hal_core::HalError;

/// What `setthread` takes, for its messages.
pub(crate) const SETTHREAD_USAGE: &str =
    "setthread THREAD [timing=0|1] [cpu=N|default] [missed=skip|catch-up]";

/// Why the host could not start, or refused a request. A refusal's
/// message goes back to the requester as the reply's text.
#[derive(Debug, thiserror::Error)]
pub enum HostError {
    /// The HAL library refused (its message is the reply).
    #[error(transparent)]
    Hal(#[from] HalError),
    /// The control socket could not be made.
    #[error("control socket: {source}")]
    Bind {
        /// Why (the runtime directory, its permissions).
        #[source]
        source: HalError,
    },
    /// The control socket failed.
    #[error("control socket: {source}")]
    Socket {
        /// The error from the socket.
        #[source]
        source: std::io::Error,
    },
    /// `loadrt` of a module the registry does not have.
    #[error("module '{name}' not found")]
    UnknownModule {
        /// The module's name.
        name: String,
    },
    /// `addf`'s position is not a number.
    #[error("bad position '{text}'")]
    BadPosition {
        /// The word given.
        text: String,
    },
    /// A request this host does not know.
    #[error("unknown host request '{word}'")]
    UnknownRequest {
        /// The request's first word.
        word: String,
    },
    /// `setthread` without a thread.
    #[error("setthread: no thread given; usage: {SETTHREAD_USAGE}")]
    NoThread,
    /// `setthread THREAD` without a switch.
    #[error("setthread {thread}: no switch given; usage: {SETTHREAD_USAGE}")]
    NoSwitch {
        /// The thread.
        thread: String,
    },
    /// A `setthread` word that is not `KEY=VALUE`.
    #[error("setthread {thread}: '{word}' is not KEY=VALUE; usage: {SETTHREAD_USAGE}")]
    NotKeyValue {
        /// The thread.
        thread: String,
        /// The word.
        word: String,
    },
    /// A switch `setthread` does not have.
    #[error("setthread {thread}: unknown switch '{key}'; usage: {SETTHREAD_USAGE}")]
    UnknownSwitch {
        /// The thread.
        thread: String,
        /// The key.
        key: String,
    },
    /// A switch's value is not one it takes.
    #[error("setthread {thread}: {key}='{value}': {reason}")]
    BadSwitch {
        /// The thread.
        thread: String,
        /// The switch.
        key: String,
        /// The value given.
        value: String,
        /// What it takes instead.
        reason: String,
    },
    /// `setthread cpu=N` with a CPU this process may not use (the HAL
    /// library's message).
    #[error("setthread {thread}: {source}")]
    BadCpu {
        /// The thread.
        thread: String,
        /// Why the CPU was refused.
        #[source]
        source: hal_core::HalError,
    },
    /// `adopt` of a word that is no process id.
    #[error("adopt: '{pid}' is not a process id")]
    BadPid {
        /// The word given.
        pid: String,
    },
    /// `adopt` over a connection whose peer is unknown.
    #[error("adopt: the requesting process is unknown (no peer credentials)")]
    NoPeer,
    /// `adopt` of a process that cannot be opened or read.
    #[error("adopt: process {pid}: {source}")]
    Process {
        /// The process.
        pid: i32,
        /// The error from the kernel.
        #[source]
        source: std::io::Error,
    },
    /// `adopt` of a process that the requester did not start.
    #[error("adopt: process {pid} is a child of {parent}, not of the requester {requester}")]
    NotAChild {
        /// The process.
        pid: i32,
        /// Its parent.
        parent: i32,
        /// Who asked.
        requester: i32,
    },
}
