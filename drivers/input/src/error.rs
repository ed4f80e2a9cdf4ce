//! The crate's error type.

use std::path::PathBuf;

/// What can go wrong: the command line, finding or using a device, the
/// simulated devices' description, HAL.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// A bad command line.
    #[error("{0}")]
    Usage(String),
    /// There are no event nodes at all.
    #[error("no input devices: {dir} has no event nodes")]
    NoDevices {
        /// Where the devices were looked for.
        dir: String,
    },
    /// No event node could be opened.
    #[error(
        "none of the {count} input devices in {dir} could be opened (the last: {why}); \
         hal_input needs read and write access to them (a udev rule, or this user in \
         the group that owns them)"
    )]
    NothingOpens {
        /// Where the devices were looked for.
        dir: String,
        /// How many nodes there are.
        count: usize,
        /// Why the last open failed.
        why: String,
    },
    /// No device matches an inputspec.
    #[error("no input device matching '{spec}' was found ({checked} devices checked)")]
    NoMatch {
        /// The inputspec (without `+` and `:N`).
        spec: String,
        /// How many devices were looked at.
        checked: usize,
    },
    /// A device operation failed.
    #[error("{op} {}", path.display())]
    Device {
        /// What was being done.
        op: &'static str,
        /// The event node.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A read returned a length that is not a whole number of records.
    #[error("read {len} bytes, not a whole number of {record}-byte input_event records")]
    PartialRecord {
        /// The bytes read.
        len: usize,
        /// The record size.
        record: usize,
    },
    /// The device went away (unplugged).
    #[error("{} ('{name}') is gone", path.display())]
    Gone {
        /// The event node.
        path: PathBuf,
        /// The device's name.
        name: String,
        /// What the kernel said, if it said anything.
        #[source]
        source: Option<std::io::Error>,
    },
    /// A device hal_input was serving went away.
    #[error(
        "{prefix}: the device went away (every key now reads released, every absolute axis centred)"
    )]
    Lost {
        /// The device's pins (`input.N`).
        prefix: String,
        /// What was seen.
        #[source]
        source: Box<InputError>,
    },
    /// The simulated devices' description could not be read.
    #[error("simulated devices file {}", path.display())]
    SimFile {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A line of the simulated devices' description is wrong.
    #[error("{file}:{line}: {what}")]
    SimLine {
        /// The file.
        file: String,
        /// Its line (from 1).
        line: usize,
        /// What is wrong.
        what: SimProblem,
    },
    /// HAL failed (boxed: HAL's error is large).
    #[error(transparent)]
    Hal(Box<hal_core::HalError>),
}

/// What is wrong with a line of the simulated devices' description.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SimProblem {
    /// More devices than hal_input takes.
    #[error("more than {0} devices")]
    TooManyDevices(usize),
    /// More script steps than a device may have.
    #[error("more than {0} steps")]
    TooManySteps(usize),
    /// A device line before any `device` line.
    #[error("'{0}' before the first 'device' line")]
    NoDevice(String),
    /// A word that starts no known line.
    #[error("unknown word '{0}'")]
    UnknownWord(String),
    /// A line's arguments do not fit its form.
    #[error("{0}")]
    Usage(&'static str),
    /// A code name hal_input does not know for that event type.
    #[error("'{name}' is no {kind} code hal_input knows")]
    UnknownCode {
        /// The name as written.
        name: String,
        /// The event type (EV_KEY, ...).
        kind: String,
    },
    /// `abs` with its minimum above its maximum.
    #[error("abs {name}: minimum {minimum} above maximum {maximum}")]
    Range {
        /// The axis.
        name: String,
        /// Its minimum.
        minimum: i32,
        /// Its maximum.
        maximum: i32,
    },
    /// Script steps out of time order.
    #[error("steps must be in time order")]
    OutOfOrder,
    /// An unknown event type in a step.
    #[error("'{0}' is no event type")]
    EventType(String),
    /// An unknown event code in a step.
    #[error("'{code}' is no code of {kind}")]
    EventCode {
        /// The code as written.
        code: String,
        /// The event type as written.
        kind: String,
    },
    /// A step's value does not fit 32 bits.
    #[error("'{0}' is no 32-bit value")]
    Value(String),
}

impl From<hal_core::HalError> for InputError {
    fn from(e: hal_core::HalError) -> InputError {
        InputError::Hal(Box::new(e))
    }
}

/// The crate's result.
pub type Result<T, E = InputError> = std::result::Result<T, E>;
