//! The error type of the HAL core.

use std::io;
use std::path::PathBuf;

use crate::types::HalType;

/// Everything that can go wrong in the HAL core. Every variant leaves the
/// instance unchanged: an operation either completes or is rolled back.
#[derive(Debug, thiserror::Error)]
pub enum HalError {
    #[error("bad {kind} name '{name}': {reason}")]
    BadName {
        kind: &'static str,
        name: String,
        reason: &'static str,
    },
    #[error("{kind} name '{name}' is {len} bytes long, at most {max} are allowed")]
    NameTooLong {
        kind: &'static str,
        name: String,
        len: usize,
        max: usize,
    },
    #[error("duplicate {kind} '{name}'")]
    Duplicate { kind: &'static str, name: String },
    #[error("{kind} '{name}' not found")]
    NotFound { kind: &'static str, name: String },
    #[error("{kind} '{name}' is {actual}, not {expected}")]
    WrongType {
        kind: &'static str,
        name: String,
        expected: HalType,
        actual: HalType,
    },
    #[error("type mismatch: pin '{pin}' is {pin_type}, signal '{signal}' is {signal_type}")]
    TypeMismatch {
        pin: String,
        pin_type: HalType,
        signal: String,
        signal_type: HalType,
    },
    #[error("signal '{signal}' already has output pin '{writer}', cannot add output pin '{pin}'")]
    SignalHasWriter {
        signal: String,
        writer: String,
        pin: String,
    },
    #[error("signal '{signal}' already has I/O pin(s), cannot add output pin '{pin}'")]
    SignalHasIoPins { signal: String, pin: String },
    #[error("signal '{signal}' already has an output pin, cannot add I/O pin '{pin}'")]
    SignalHasOutputForIo { signal: String, pin: String },
    #[error("pin '{pin}' is already linked to signal '{signal}'")]
    PinAlreadyLinked { pin: String, signal: String },
    #[error("pin '{pin}' is connected to signal '{signal}' and cannot be set directly")]
    PinConnected { pin: String, signal: String },
    #[error("signal '{signal}' has writer '{writer}' and cannot be set directly")]
    SignalDriven { signal: String, writer: String },
    #[error("param '{name}' is read-only")]
    ParamReadOnly { name: String },
    #[error("pin '{name}' is an output pin and cannot be set directly")]
    PinIsOutput { name: String },
    #[error("realtime not running for instance '{instance}'")]
    NotRunning { instance: String },
    #[error("a HAL host is already running for instance '{instance}'")]
    AlreadyRunning { instance: String },
    #[error("{op} {path}: {source}")]
    Io {
        op: &'static str,
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("{op}: {source}")]
    Os {
        op: &'static str,
        #[source]
        source: nix::Error,
    },
    #[error("segment of instance '{instance}' is not usable: {reason}")]
    BadSegment { instance: String, reason: String },
    #[error("offset {offset:#x} read from the segment is outside it or misaligned (segment size {size:#x})")]
    BadOffset { offset: u64, size: u64 },
    #[error("HAL shared memory is full: {requested} bytes wanted, {available} left (raise the segment size)")]
    OutOfMemory { requested: u64, available: u64 },
    #[error("the change is too large for one transaction ({limit} journal entries)")]
    JournalFull { limit: usize },
    #[error("thread '{name}': period must be greater than zero")]
    ZeroPeriod { name: String },
    #[error("thread '{name}': period {period} ns is shorter than the base period {base} ns")]
    PeriodBelowBase {
        name: String,
        period: i64,
        base: i64,
    },
    #[error("thread '{name}': period {period} ns is shorter than the period {previous} ns of thread '{previous_name}'; create threads fastest first")]
    ThreadOrder {
        name: String,
        period: i64,
        previous: i64,
        previous_name: String,
    },
    #[error("function '{funct}' is not reentrant and is already in thread '{thread}'")]
    FunctInUse { funct: String, thread: String },
    #[error("function '{funct}' is not in thread '{thread}'")]
    FunctNotInThread { funct: String, thread: String },
    #[error("function '{funct}' is in thread '{thread}'; remove it with delf first")]
    FunctStillInThread { funct: String, thread: String },
    #[error("position {position} is out of range for thread '{thread}' with {len} functions")]
    BadPosition {
        thread: String,
        position: i32,
        len: usize,
    },
    #[error("component '{comp}' is not ready")]
    NotReady { comp: String },
    #[error("component '{comp}' belongs to process {owner}, not to this one")]
    NotOwner { comp: String, owner: i32 },
    #[error("too many {kind}s: the limit is {limit}")]
    TooMany { kind: &'static str, limit: usize },
    #[error("bad value for {what}: {reason}")]
    BadValue { what: String, reason: String },
    #[error("{module}: parameter '{param}': {reason}")]
    ModuleParam {
        module: String,
        param: String,
        reason: String,
    },
    #[error("module '{name}' not found")]
    UnknownModule { name: String },
    #[error("module '{name}' is already loaded")]
    ModuleLoaded { name: String },
    #[error("{module}: {reason}")]
    ModuleLoad { module: String, reason: String },
    #[error("this operation needs the HAL host process")]
    NotHost,
    #[error("threads of instance '{instance}' are halted after a fault in function '{funct}'; unload and reload to recover")]
    Faulted { instance: String, funct: String },
}

impl HalError {
    pub(crate) fn io(op: &'static str, path: impl Into<PathBuf>, source: io::Error) -> Self {
        HalError::Io {
            op,
            path: path.into(),
            source,
        }
    }
}

/// Result type of the HAL core.
pub type Result<T, E = HalError> = std::result::Result<T, E>;
