//! The crate's error type: what can go wrong finding, identifying and
//! opening MOTENC boards. Realtime functions never return errors; they
//! trip the board's fault latch ([`crate::hal`]).

use hal_driver::DriverError;

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum MotencError {
    /// The board's registers read all ones: nothing decodes the BAR.
    #[error("{board}: nothing answers (boardVersion and statusControl read 0xffffffff)")]
    NoAnswer {
        /// The board (bus address or "simulated MOTENC-100").
        board: String,
    },
    /// boardVersion holds neither MOTENC-100 (0) nor MOTENC-Lite (1).
    #[error("{board}: boardVersion is {found:#x}, expected 0 (MOTENC-100) or 1 (MOTENC-Lite)")]
    UnknownVersion {
        /// The board.
        board: String,
        /// What the register held.
        found: u32,
    },
    /// A `sim_boards` item names no board kind.
    #[error("not a board kind: 100 or lite")]
    NotABoardKind,
    /// More boards than jumper IDs.
    #[error("{found} MOTENC boards found; at most 4 can be used (board IDs 0..3)")]
    TooManyBoards {
        /// How many were found.
        found: usize,
    },
    /// The shared driver layer failed (PCI discovery, BAR mapping, a
    /// parameter).
    #[error(transparent)]
    Driver(#[from] DriverError),
}

impl MotencError {
    /// The error as a `loadrt` failure of `module`.
    pub fn into_hal(self, module: &str) -> hal_core::HalError {
        match self {
            MotencError::Driver(e) => e.into_hal(module),
            other => hal_core::HalError::module_failed(module, other),
        }
    }
}
