//! The Modbus RTU master and the transactions the components use.
//!
//! * [`frame`]: building requests, finding the end of a reply, checking
//!   it (CRC, address, function, exception).
//! * [`Master`]: one transaction at a time on a
//!   [`SerialLine`]: the silence before each
//!   request (3.5 characters, or 1.75 ms above 19 200 baud), the reply
//!   and byte timeouts, retries of lost or garbled replies and of busy
//!   slaves, and reopening a line that failed.
//! * [`Transact`]: what carries one request and its reply, RTU (a
//!   [`Master`]) or Modbus TCP (`mb2hal`'s link); the standard data
//!   functions ([`functions`]: coils, discrete inputs, registers, read
//!   and written) work on either. The HY protocol's ([`hy`]) run on a
//!   master.

pub mod frame;
pub mod functions;
pub mod hy;
mod master;

pub use frame::ReplyLength;
pub use master::{hex, Master, MasterConfig, MasterStats};

use crate::error::Result;
use crate::line::SerialLine;

/// Carries one Modbus request to a slave and returns its reply's data
/// (the bytes after the function code), or the failure: an RTU
/// [`Master`] on a serial line, or a Modbus TCP connection.
pub trait Transact {
    /// Sends `function` with `data` to `slave`; `reply` says how an RTU
    /// reply's end is found (a TCP reply carries its own length).
    fn transact(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        reply: ReplyLength,
    ) -> Result<Vec<u8>>;

    /// Whether a request to `slave` goes to every slave and gets no
    /// reply (RTU's address 0; a TCP unit identifier never is).
    fn is_broadcast(&self, slave: u8) -> bool {
        slave == crate::regs::modbus::BROADCAST
    }
}

impl<L: SerialLine> Transact for Master<L> {
    fn transact(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        reply: ReplyLength,
    ) -> Result<Vec<u8>> {
        Master::transact(self, slave, function, data, reply)
    }
}

impl<L: SerialLine> Master<L> {
    /// Reads `count` registers from `start` with function 0x03 (holding)
    /// or 0x04 (input).
    pub fn read_registers(
        &mut self,
        slave: u8,
        function: u8,
        start: u16,
        count: u16,
    ) -> Result<Vec<u16>> {
        check_rtu_slave(slave)?;
        functions::read_registers(self, slave, function, start, count)
    }

    /// Writes one register (function 0x06); the slave echoes the request.
    pub fn write_register(&mut self, slave: u8, address: u16, value: u16) -> Result<()> {
        check_rtu_slave(slave)?;
        functions::write_register(self, slave, address, value)
    }

    /// Writes consecutive registers from `start` (function 0x10).
    pub fn write_registers(&mut self, slave: u8, start: u16, values: &[u16]) -> Result<()> {
        check_rtu_slave(slave)?;
        functions::write_registers(self, slave, start, values)
    }
}

/// Refuses an RTU address above the highest unicast one.
pub fn check_rtu_slave(slave: u8) -> Result<()> {
    if slave > crate::regs::modbus::MAX_SLAVE {
        return Err(crate::error::SerialError::BadRequest(format!(
            "slave address {slave} (RTU addresses are 0 to {})",
            crate::regs::modbus::MAX_SLAVE
        )));
    }
    Ok(())
}
