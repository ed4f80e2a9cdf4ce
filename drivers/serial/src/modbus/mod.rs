//! The Modbus RTU master and the transactions the VFD components use.
//!
//! * [`frame`]: building requests, finding the end of a reply, checking
//!   it (CRC, address, function, exception).
//! * [`Master`]: one transaction at a time on a
//!   [`SerialLine`]: the silence before each
//!   request (3.5 characters, or 1.75 ms above 19 200 baud), the reply
//!   and byte timeouts, retries of lost or garbled replies and of busy
//!   slaves, and reopening a line that failed.
//! * Standard Modbus register transactions (here) and the HY protocol's
//!   ([`hy`]) on a master.

pub mod frame;
pub mod hy;
mod master;

pub use frame::ReplyLength;
pub use master::{hex, Master, MasterConfig, MasterStats};

use crate::error::{Result, SerialError};
use crate::line::SerialLine;
use crate::regs::modbus as mb;

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
        if !matches!(
            function,
            mb::READ_HOLDING_REGISTERS | mb::READ_INPUT_REGISTERS
        ) {
            return Err(SerialError::BadRequest(format!(
                "function {function:#04x} does not read registers"
            )));
        }
        if count == 0 || count > mb::MAX_READ_COUNT {
            return Err(SerialError::BadRequest(format!(
                "cannot read {count} registers (1..={})",
                mb::MAX_READ_COUNT
            )));
        }
        if slave == mb::BROADCAST || slave > mb::MAX_SLAVE {
            return Err(SerialError::BadRequest(format!(
                "cannot read from slave address {slave}"
            )));
        }
        let mut data = start.to_be_bytes().to_vec();
        data.extend_from_slice(&count.to_be_bytes());
        let body = self.transact(slave, function, &data, ReplyLength::CountAt2)?;
        let expected = 2 * usize::from(count);
        match body.split_first() {
            Some((&n, values)) if usize::from(n) == expected && values.len() == expected => {
                Ok(values
                    .chunks_exact(2)
                    .map(|c| u16::from_be_bytes([c[0], c[1]]))
                    .collect())
            }
            _ => Err(SerialError::BadReply {
                slave,
                function,
                what: format!(
                    "{} data bytes for {count} registers",
                    body.len().saturating_sub(1)
                ),
            }),
        }
    }

    /// Writes one register (function 0x06); the slave echoes the request.
    pub fn write_register(&mut self, slave: u8, address: u16, value: u16) -> Result<()> {
        let function = mb::WRITE_SINGLE_REGISTER;
        if slave > mb::MAX_SLAVE {
            return Err(SerialError::BadRequest(format!("slave address {slave}")));
        }
        let mut data = address.to_be_bytes().to_vec();
        data.extend_from_slice(&value.to_be_bytes());
        let body = self.transact(slave, function, &data, ReplyLength::Fixed(8))?;
        if slave != mb::BROADCAST && body != data {
            return Err(SerialError::BadReply {
                slave,
                function,
                what: format!("echo {:02X?} differs from the request {data:02X?}", body),
            });
        }
        Ok(())
    }

    /// Writes consecutive registers from `start` (function 0x10).
    pub fn write_registers(&mut self, slave: u8, start: u16, values: &[u16]) -> Result<()> {
        let function = mb::WRITE_MULTIPLE_REGISTERS;
        let count = values.len();
        if count == 0 || count > usize::from(mb::MAX_WRITE_COUNT) || slave > mb::MAX_SLAVE {
            return Err(SerialError::BadRequest(format!(
                "cannot write {count} registers (1..={}) to slave {slave}",
                mb::MAX_WRITE_COUNT
            )));
        }
        let mut data = start.to_be_bytes().to_vec();
        data.extend_from_slice(&(count as u16).to_be_bytes());
        data.push((count * 2) as u8);
        for v in values {
            data.extend_from_slice(&v.to_be_bytes());
        }
        let body = self.transact(slave, function, &data, ReplyLength::Fixed(8))?;
        if slave != mb::BROADCAST && body != data[..4] {
            return Err(SerialError::BadReply {
                slave,
                function,
                what: format!("reply {:02X?} does not name the registers written", body),
            });
        }
        Ok(())
    }
}
