//! The error of the programs' own glue: command lines, numbers given to
//! them, and what the crates below them report.

/// What went wrong in a program of the suite, with the cause behind it.
#[derive(Debug, thiserror::Error)]
pub enum ToolsError {
    /// A number of seconds given on the command line is not usable.
    #[error("{what}: {reason}")]
    Seconds {
        /// The option that took it (`--timeout`).
        what: String,
        /// Why it was refused, with the text given.
        reason: String,
    },
}
