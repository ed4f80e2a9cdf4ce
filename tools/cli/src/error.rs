//! The error of the programs' own glue: command lines, numbers given to
//! them, and what the crates below them report.

/// What went wrong in a program of the suite, with the cause behind it.
#[derive(Debug, thiserror::Error)]
pub enum ToolsError {
    /// The command line is wrong; the message says how, in the program's
    /// words (some are LinuxCNC's, compared by tests).
    #[error("{0}")]
    Usage(String),
    /// A number of seconds given on the command line is not usable.
    #[error("{what}: {reason}")]
    Seconds {
        /// The option that took it (`--timeout`).
        what: String,
        /// Why it was refused, with the text given.
        reason: String,
    },
    /// The HAL instance refused or failed.
    #[error(transparent)]
    Hal(#[from] hal_core::HalError),
    /// The HAL command language (an INI file, a host).
    #[error(transparent)]
    Lang(#[from] hal_lang::LangError),
    /// An INI file given on the command line.
    #[error(transparent)]
    Ini(#[from] hal_lang::IniError),
    /// A sampler or streamer FIFO.
    #[error(transparent)]
    Fifo(#[from] hal_scope::ScopeError),
    /// A file named on the command line.
    #[error("{path}: {source}")]
    File {
        /// The file.
        path: String,
        /// The error from the file system.
        #[source]
        source: std::io::Error,
    },
    /// Reading input or writing output failed.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// halmeter's object does not exist.
    #[error("no pin, signal or parameter named '{name}'")]
    NotFound {
        /// The name given.
        name: String,
    },
    /// The motion controller's status could not be read.
    #[error(transparent)]
    Motion(#[from] motion::ClientError),
    /// The motion controller of an instance could not be reached.
    #[error("instance '{instance}': {source}")]
    MotionAttach {
        /// The instance.
        instance: String,
        /// Why.
        #[source]
        source: motion::ClientError,
    },
    /// Task refused a request; its words.
    #[error("{0}")]
    TaskRefused(String),
    /// Task could not be asked (not running, the socket failed).
    #[error(transparent)]
    TaskClient(#[from] hal_launcher::TaskClientError),
    /// A command refused because task runs the machine.
    #[error("refused: a task runs the machine on instance '{instance}': {why}")]
    TaskOwns {
        /// The instance.
        instance: String,
        /// Why, and what to do instead.
        why: String,
    },
    /// A joint the status has no entry for.
    #[error("joint {joint} does not exist (there are {count})")]
    NoSuchJoint {
        /// The joint asked about.
        joint: usize,
        /// The joints there are.
        count: usize,
    },
    /// A compensation file could not be read.
    #[error(transparent)]
    CompFile(#[from] motion::comp_file::CompFileError),
    /// gcode-run needs an enabled machine.
    #[error("the machine is not enabled (motion-cmd enable)")]
    NotEnabled,
    /// The motion controller refused coordinated mode.
    #[error("can't enter coordinated mode: {source}")]
    Coord {
        /// Its answer.
        #[source]
        source: motion::Reject,
    },
    /// The motion controller did not reach coordinated mode in time.
    #[error("the controller did not enter coordinated mode")]
    CoordTimeout,
}

impl ToolsError {
    /// A command-line error with this message.
    pub fn usage(message: impl Into<String>) -> ToolsError {
        ToolsError::Usage(message.into())
    }
}
