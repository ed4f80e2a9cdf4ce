//! The crate's one error type.

use std::path::PathBuf;

/// Why hal-web could not start or serve.
#[derive(Debug, thiserror::Error)]
pub enum WebError {
    /// The command line is wrong.
    #[error("{0}")]
    Usage(String),
    /// The HAL instance could not be reached.
    #[error("attaching to the HAL instance: {0}")]
    Hal(#[from] hal_core::HalError),
    /// The listening address could not be bound.
    #[error("listening on {addr}: {source}")]
    Bind {
        /// The address asked for.
        addr: String,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// Serving stopped on an I/O error.
    #[error("serving HTTP: {0}")]
    Serve(#[source] std::io::Error),
    /// The async runtime could not start.
    #[error("starting the runtime: {0}")]
    Runtime(#[source] std::io::Error),
    /// The kernel gave no random bytes for the token.
    #[error("generating the access token: {0}")]
    Random(#[source] getrandom::Error),
    /// The token file could not be written.
    #[error("storing the access token in {path}: {source}")]
    TokenFile {
        /// The token file.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
}

impl WebError {
    /// A usage error with `msg`.
    pub fn usage(msg: impl Into<String>) -> WebError {
        WebError::Usage(msg.into())
    }
}
