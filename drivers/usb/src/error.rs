//! The crate's error type.

use std::path::PathBuf;

/// Why a `BUTTON=` line of the button file is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ButtonProblem {
    /// No `:` between code and name.
    #[error("expected CODE:pin-name, e.g. 0D:button-step")]
    NoColon,
    /// The code is not a hex byte.
    #[error("button code '{0}' is not a hex byte")]
    BadCode(String),
    /// Code 00, which the pendant reports for no button.
    #[error("button code 00 means no button")]
    ZeroCode,
    /// An empty or too long pin name.
    #[error("pin name must be 1..={max} characters")]
    NameLength {
        /// The longest name allowed.
        max: usize,
    },
    /// A character a HAL pin name should not have.
    #[error("pin name '{0}' may hold only letters, digits, '-', '_' and '.'")]
    NameCharacters(String),
    /// More buttons than the driver keeps.
    #[error("more than {max} buttons")]
    TooMany {
        /// The most buttons allowed.
        max: usize,
    },
    /// The same pin name on two lines.
    #[error("pin name '{0}' given twice")]
    Twice(String),
}

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
    #[error("{file}:{line}: BUTTON={value}: {problem}")]
    BadButton {
        /// The file.
        file: String,
        /// Its line.
        line: usize,
        /// The value.
        value: String,
        /// Why it is refused.
        #[source]
        problem: ButtonProblem,
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
