//! The crate's error type.

use std::path::PathBuf;

/// What can go wrong: the command line, the button file, the device, HAL.
#[derive(Debug, thiserror::Error)]
pub enum UsbError {
    /// A bad command line.
    #[error("{0}")]
    Usage(String),
    /// An option with a value out of range.
    #[error("option {option} '{value}': {reason}")]
    BadOption {
        /// The option.
        option: &'static str,
        /// Its value.
        value: String,
        /// Why it is refused.
        reason: String,
    },
    /// The button file could not be read.
    #[error("button file {}", path.display())]
    ButtonFile {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: Box<hal_lang::ini::IniError>,
    },
    /// A `BUTTON=` line that does not say `CODE:button-name`.
    #[error("{file}:{line}: BUTTON={value}: {reason}")]
    BadButton {
        /// The file.
        file: String,
        /// Its line.
        line: usize,
        /// The value.
        value: String,
        /// Why it is refused.
        reason: String,
    },
    /// The device failed.
    #[error("{op} {}", path.display())]
    Device {
        /// What was being done.
        op: &'static str,
        /// The device node or sysfs path.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// HAL failed (boxed: HAL's error is large).
    #[error(transparent)]
    Hal(Box<hal_core::HalError>),
}

impl From<hal_core::HalError> for UsbError {
    fn from(e: hal_core::HalError) -> UsbError {
        UsbError::Hal(Box::new(e))
    }
}

/// The crate's result.
pub type Result<T, E = UsbError> = std::result::Result<T, E>;
