//! The error of capture and plots.

use hal_core::HalError;

/// A boxed cause: a file system or plotting error.
pub type Cause = Box<dyn std::error::Error + Send + Sync>;

/// Everything that can stop a capture, a latency test, a plot or a FIFO.
#[derive(Debug, thiserror::Error)]
pub enum ScopeError {
    /// The command line asks for something that cannot be done.
    #[error("{0}")]
    Usage(String),
    /// The HAL instance refused or failed.
    #[error("HAL: {0}")]
    Hal(#[from] HalError),
    /// The instance could not be attached.
    #[error("HAL: instance '{instance}': {source}")]
    Attach {
        /// The instance.
        instance: String,
        /// Why.
        #[source]
        source: HalError,
    },
    /// A request to the host failed (`loadrt sampler`, `addf`, ...).
    #[error("HAL: {command}: {source}")]
    Request {
        /// The request's words.
        command: String,
        /// Why.
        #[source]
        source: hal_lang::ClientError,
    },
    /// The sampler halscope reads from could not be opened.
    #[error("HAL: {0}")]
    Sampler(#[source] Box<ScopeError>),
    /// The host went away during the capture.
    #[error("HAL: the HAL host exited")]
    HostExited,
    /// No complete record came in time.
    #[error("{0}")]
    Timeout(String),
    /// Interrupted before the record was complete.
    #[error("interrupted before the record was complete")]
    Interrupted,
    /// Writing an output failed.
    #[error("writing {path}: {source}")]
    Output {
        /// The file.
        path: String,
        /// Why.
        #[source]
        source: Cause,
    },
    /// Drawing a plot failed.
    #[error("{path}: {source}")]
    Plot {
        /// The PNG file.
        path: String,
        /// The plotting library's error.
        #[source]
        source: Cause,
    },
    /// A sampler or streamer channel that does not exist.
    #[error("{module} channel {chan} does not exist")]
    NoChannel {
        /// `sampler` or `streamer`.
        module: &'static str,
        /// The channel.
        chan: usize,
    },
    /// A channel whose FIFO does not match its pins.
    #[error("{module} channel {chan}: FIFO does not match its pins")]
    FifoMismatch {
        /// `sampler` or `streamer`.
        module: &'static str,
        /// The channel.
        chan: usize,
    },
    /// A streamer input line that ends before a column's value.
    #[error("missing value for column {column}")]
    MissingValue {
        /// The column, from 0.
        column: usize,
    },
    /// A streamer input field not followed by whitespace (the last line
    /// without a newline).
    #[error("value '{value}' for column {column} is not followed by whitespace")]
    NoWhitespace {
        /// The field.
        value: String,
        /// The column, from 0.
        column: usize,
    },
    /// A streamer input field that is not a value of its column's type.
    #[error("bad value '{value}' for column {column} ({hal_type})")]
    BadValue {
        /// The field.
        value: String,
        /// The column, from 0.
        column: usize,
        /// The column's type.
        hal_type: hal_core::HalType,
    },
    /// The latency test's private host did not start or refused a request.
    #[error("the HAL host: {0}")]
    Host(#[source] hal_lang::LangError),
    /// A request to the latency test's private host failed.
    #[error("the HAL host: {command}: {source}")]
    HostRequest {
        /// The request's words.
        command: String,
        /// Why.
        #[source]
        source: hal_lang::ClientError,
    },
    /// The latency test's private host did not shut down.
    #[error("the HAL host: {0}")]
    HostStop(#[source] hal_lang::ClientError),
    /// The latency test's private host went away during the test.
    #[error("the HAL host: the host exited during the test")]
    HostGone,
    /// Reading the latency test's instance failed.
    #[error("reading the threads of instance '{instance}': {source}")]
    Instance {
        /// The private instance.
        instance: String,
        /// What the HAL core said.
        #[source]
        source: HalError,
    },
    /// A samples file line that does not hold nine numbers.
    #[error("{file}:{line}: expected nine numbers (X Y Z commanded, X Y Z measured, three following errors)")]
    BadLine {
        /// The file.
        file: String,
        /// The line, from 1.
        line: usize,
    },
    /// A samples file without samples.
    #[error("{file}: no samples")]
    Empty {
        /// The file.
        file: String,
    },
    /// A histogram CSV without a line.
    #[error("empty CSV")]
    CsvEmpty,
    /// A histogram CSV whose header is not latency-test's.
    #[error("unexpected header '{header}'")]
    CsvHeader {
        /// The first line.
        header: String,
    },
    /// A histogram CSV line that is not a bucket's.
    #[error("line {line}: '{text}'")]
    CsvLine {
        /// The line, from 1.
        line: usize,
        /// Its text.
        text: String,
    },
    /// A bucket's count that is not a number.
    #[error("line {line}: bad count '{value}'")]
    CsvCount {
        /// The line, from 1.
        line: usize,
        /// The field.
        value: String,
    },
    /// scope_rt refused the capture's settings, or its shared region
    /// holds what its layout does not allow.
    #[error(transparent)]
    ScopeRt(#[from] hal_components::CompError),
}

impl ScopeError {
    /// A plotting library's error while drawing `path`.
    pub(crate) fn plot<E: std::error::Error + Send + Sync + 'static>(path: &str, e: E) -> Self {
        ScopeError::Plot {
            path: path.to_string(),
            source: Box::new(e),
        }
    }
}
