//! The crate's error type: what can go wrong finding, probing and
//! opening a Servo-To-Go. Realtime functions never return errors; they
//! trip the board's fault latch ([`crate::hal`]).

use hal_driver::params::NumberError;
use hal_driver::DriverError;

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum StgError {
    /// Every board-test read returned 0xff: nothing decodes the ports.
    #[error("no board answers at {base:#x} (its board test register reads 0xff: nothing decodes the port)")]
    NothingAnswers {
        /// The base address probed.
        base: u16,
    },
    /// Something answers, but not with a Servo-To-Go signature.
    #[error(
        "the board at {base:#x} is not a Servo-To-Go: its signature is {signature:#04x} \
         (Model I is 0x75, Model II 0x74)"
    )]
    NotAnStg {
        /// The base address probed.
        base: u16,
        /// The signature read.
        signature: u8,
    },
    /// Autodetection found nothing.
    #[error(
        "no Servo-To-Go found at any base address 0x200..0x3e0 (none gives signature 0x75 or \
         0x74); set base= (and model= to skip the check)"
    )]
    NotFound,
    /// A backend that cannot drive the board.
    #[error("{0}")]
    Backend(String),
    /// `hal-board probe --via` names no way to the ports.
    #[error("'{text}' is not a way to the ports (ioperm, devport, sim, sim1)")]
    NotAWay {
        /// The name as given.
        text: String,
    },
    /// A base address given to `hal-board probe` is not a number.
    #[error("'{text}': {source}")]
    BadBase {
        /// The address as given.
        text: String,
        /// Why it is not a number.
        #[source]
        source: NumberError,
    },
    /// A base address the board's jumpers cannot select.
    #[error("{base:#x} is not a Servo-To-Go base address (0x200, 0x220, ... 0x3e0)")]
    NotABase {
        /// The address.
        base: u64,
    },
    /// The shared driver layer failed (port access, a parameter).
    #[error(transparent)]
    Driver(#[from] DriverError),
}

impl StgError {
    /// The error as a `loadrt` failure of `module`.
    pub fn into_hal(self, module: &str) -> hal_core::HalError {
        match self {
            StgError::Driver(e) => e.into_hal(module),
            other => hal_core::HalError::module_failed(module, other),
        }
    }
}
