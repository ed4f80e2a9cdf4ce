//! The bus trait: SMBus-style register transfers to a chip at a 7-bit
//! address, with a real backend ([`crate::linux`], `/dev/i2c-N`) and a
//! simulated one ([`crate::sim::SimBus`], register models of the chips).
//!
//! In the driver layer's shape: `&self` accessors and an `errors()`
//! count. Unlike a register window a transfer can fail visibly (no
//! acknowledge, a stuck bus), and the chip drivers need to know, so each
//! returns the kernel's errno. Only the bus's helper thread and `loadrt`
//! call these: an I2C transfer takes hundreds of microseconds and may
//! sleep, so it never runs in a realtime function.
//!
//! The transfers are the SMBus ones Linux's i2c-dev offers and the
//! kernel's i2c-stub answers: byte data, word data (low byte first on the
//! wire) and I2C block data (up to 32 bytes) at a register.

use std::fmt;

/// The most bytes of one block transfer.
pub const BLOCK_MAX: usize = 32;

/// A failed transfer: the kernel's errno.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusError(pub i32);

impl BusError {
    /// Whether the chip did not answer (no acknowledge of its address):
    /// it is missing, unpowered, or at another address.
    pub fn is_no_answer(self) -> bool {
        matches!(self.0, libc::ENXIO | libc::EREMOTEIO | libc::ENODEV)
    }
}

impl fmt::Display for BusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", std::io::Error::from_raw_os_error(self.0))?;
        if self.is_no_answer() {
            write!(
                f,
                " (no answer: is the chip there, at this address, and powered?)"
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for BusError {}

/// Register transfers on one I2C bus.
pub trait I2cBus: Send + Sync {
    /// Takes `addr` for this process (`I2C_SLAVE`): refused while a
    /// kernel driver owns the address. Sends nothing on the bus.
    fn claim(&self, addr: u8) -> Result<(), BusError>;
    /// Writes `value` to register `reg`.
    fn write_byte_data(&self, addr: u8, reg: u8, value: u8) -> Result<(), BusError>;
    /// Reads register `reg`.
    fn read_byte_data(&self, addr: u8, reg: u8) -> Result<u8, BusError>;
    /// Writes two bytes from register `reg`: `value`'s low byte first.
    fn write_word_data(&self, addr: u8, reg: u8, value: u16) -> Result<(), BusError>;
    /// Reads two bytes from register `reg`; the first is the low byte.
    fn read_word_data(&self, addr: u8, reg: u8) -> Result<u16, BusError>;
    /// Writes `data` (at most [`BLOCK_MAX`] bytes) from register `reg`.
    fn write_block(&self, addr: u8, reg: u8, data: &[u8]) -> Result<(), BusError>;
    /// Reads `out.len()` bytes (at most [`BLOCK_MAX`]) from register `reg`.
    fn read_block(&self, addr: u8, reg: u8, out: &mut [u8]) -> Result<(), BusError>;
    /// Failed transfers so far.
    fn errors(&self) -> u64;
    /// The bus, for messages (`/dev/i2c-1`).
    fn describe(&self) -> String;
    /// Lets a simulated bus's chips see time pass up to `now_ns`
    /// (CLOCK_MONOTONIC); hardware ignores it.
    fn tick(&self, now_ns: u64) {
        let _ = now_ns;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_answer_says_what_to_check() {
        let e = BusError(libc::ENXIO).to_string();
        assert!(e.contains("no answer"), "{e}");
        assert!(!BusError(libc::EIO).is_no_answer());
        assert!(!BusError(libc::EIO).to_string().contains("no answer"));
    }
}
