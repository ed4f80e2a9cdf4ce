//! The crate's error type: what can go wrong reading the parameters,
//! reaching the ports and finding the boards. Realtime functions never
//! return errors; they trip the bus's fault latch ([`crate::hal`]).

use hal_driver::DriverError;

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum PpmcError {
    /// A slot's ID names no Pico board.
    #[error(
        "slot {slot} answers with ID {id:#04x}, which is no Pico board (is the port in EPP mode \
         and the cable right?)"
    )]
    UnknownBoard {
        /// The slot.
        slot: usize,
        /// The ID byte.
        id: u8,
    },
    /// No board on a bus.
    #[error(
        "no boards found on bus {bus} (port {port:#x}): every slot's ID reads empty; check the \
         cable, the board's power and that the port can do EPP"
    )]
    NoBoards {
        /// The bus number.
        bus: usize,
        /// Its port address.
        port: u16,
    },
    /// An option names a slot with no board that has the feature.
    #[error("{param}={code:#04x}: {reason}")]
    BadOption {
        /// The parameter (`extradac`, `timestamp`, ...).
        param: &'static str,
        /// The bus/slot code as given.
        code: i64,
        /// What is wrong there.
        reason: String,
    },
    /// The port could not be opened.
    #[error("port {port:#x}: {source}")]
    Port {
        /// The port address.
        port: u16,
        /// Why.
        #[source]
        source: DriverError,
    },
    /// hal_parport's port choice refused a bus's port (no such port,
    /// or one port given twice).
    #[error("port_addr item {bus}: {source}")]
    PortChoice {
        /// The bus (its item in `port_addr`).
        bus: usize,
        /// Why.
        #[source]
        source: hal_parport::port::PortError,
    },
    /// The shared driver layer failed (a parameter).
    #[error(transparent)]
    Driver(#[from] DriverError),
}

impl PpmcError {
    /// The error as a `loadrt` failure of `module`.
    pub fn into_hal(self, module: &str) -> hal_core::HalError {
        match self {
            PpmcError::Driver(e) => e.into_hal(module),
            other => hal_core::HalError::module_failed(module, other),
        }
    }
}
