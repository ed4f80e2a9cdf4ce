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
    /// A page asked for more meters than one page may show.
    #[error("a page may show at most {max} meters")]
    TooManyMeters {
        /// The bound.
        max: usize,
    },
    /// A meter was asked for on something that is not a pin, signal or
    /// parameter.
    #[error("a meter shows a pin, sig or param, not a '{kind}' ({name})")]
    MeterKind {
        /// The kind the page gave.
        kind: String,
        /// The object's name.
        name: String,
    },
    /// A scope record longer than the page takes.
    #[error("--samples {asked}: the page takes at most {max} (halscope itself takes more)")]
    ScopeSamples {
        /// Samples asked for.
        asked: usize,
        /// The page's bound.
        max: usize,
    },
    /// A scope wait longer than the page waits.
    #[error("--timeout {asked}: the page waits at most {max_s} s")]
    ScopeTimeout {
        /// Seconds asked for.
        asked: f64,
        /// The page's bound, in seconds.
        max_s: u64,
    },
    /// Both an own sampler (pins and thread) and a sampler channel.
    #[error("give pins and thread, or a sampler channel, not both")]
    ScopeSourceBoth,
    /// halscope's own check refused the request.
    #[error(transparent)]
    Scope(#[from] hal_scope::scope::ScopeError),
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
