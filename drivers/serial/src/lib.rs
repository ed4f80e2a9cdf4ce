//! Serial-line drivers: a Modbus RTU master on the `serialport` crate
//! and a simulated VFD that speaks the Huanyang GT (standard Modbus) and
//! HY protocols.
//!
//! * [`line`]: the bus trait [`line::SerialLine`], with the real tty
//!   backend [`line::TtyLine`] and the simulated [`line::SimLine`].
//! * [`modbus`]: framing, the [`modbus::Master`] (silence between frames,
//!   timeouts, retries, exceptions, reopening a failed line) and the
//!   register and HY transactions.
//! * [`sim`]: the simulated drive, on a [`line::SimLine`] or behind a
//!   pseudo-terminal ([`sim::PtyVfd`]).
//! * [`regs`]: the protocols' codes and register maps; [`crc`]: the CRC.

pub mod crc;
pub mod error;
pub mod fuzzing;
pub mod line;
pub mod modbus;
pub mod opts;
pub mod regs;
pub mod sim;
pub mod vfd;

pub use error::{Result, SerialError};
