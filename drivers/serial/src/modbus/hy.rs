//! The Huanyang HY protocol's transactions on a [`Master`]: Modbus RTU
//! framing with the drive's own function codes, every frame carrying a
//! length byte after the function code (hardware.md §7.3).
//!
//! | function | request data | reply data |
//! |---|---|---|
//! | 0x01 read PDnnn | 3, n, 0, 0 | 3, n, value (or 2, n, one byte) |
//! | 0x02 write PDnnn | 3, n, value | 3, n, value |
//! | 0x03 control | 1, CNTR | 1, CNST |
//! | 0x04 status | 1, index | 3, index, value |
//! | 0x05 frequency | 2, 0.01 Hz | 2, value |

use super::{Master, ReplyLength};
use crate::error::{Result, SerialError};
use crate::line::SerialLine;
use crate::regs::hy;

fn bad(slave: u8, function: u8, what: String) -> SerialError {
    SerialError::BadReply {
        slave,
        function,
        what,
    }
}

impl<L: SerialLine> Master<L> {
    /// One HY transaction: `function` with its length byte and `data`;
    /// the reply's data after its length byte, checked against it.
    fn hy_transact(&mut self, slave: u8, function: u8, data: &[u8]) -> Result<Vec<u8>> {
        let mut request = vec![data.len() as u8];
        request.extend_from_slice(data);
        let body = self.transact(slave, function, &request, ReplyLength::CountAt2)?;
        match body.split_first() {
            Some((&n, rest)) if usize::from(n) == rest.len() => Ok(rest.to_vec()),
            _ => Err(bad(
                slave,
                function,
                "length byte disagrees with the data".into(),
            )),
        }
    }

    /// A parameter's value from a read or write reply: `n, value`.
    fn hy_parameter_reply(slave: u8, function: u8, n: u8, reply: &[u8]) -> Result<u16> {
        match reply {
            [pd, hi, lo] if *pd == n => Ok(u16::from_be_bytes([*hi, *lo])),
            [pd, v] if *pd == n => Ok(u16::from(*v)),
            _ => Err(bad(
                slave,
                function,
                format!("reply {reply:02X?} is not parameter PD{n:03}"),
            )),
        }
    }

    /// Reads function parameter PDn.
    pub fn hy_read_parameter(&mut self, slave: u8, n: u8) -> Result<u16> {
        let reply = self.hy_transact(slave, hy::FUNCTION_READ, &[n, 0, 0])?;
        Self::hy_parameter_reply(slave, hy::FUNCTION_READ, n, &reply)
    }

    /// Writes function parameter PDn; returns the value the drive echoes.
    pub fn hy_write_parameter(&mut self, slave: u8, n: u8, value: u16) -> Result<u16> {
        let [hi, lo] = value.to_be_bytes();
        let reply = self.hy_transact(slave, hy::FUNCTION_WRITE, &[n, hi, lo])?;
        Self::hy_parameter_reply(slave, hy::FUNCTION_WRITE, n, &reply)
    }

    /// Writes the control word CNTR; returns the status byte CNST.
    pub fn hy_write_control(&mut self, slave: u8, cntr: u8) -> Result<u8> {
        match self.hy_transact(slave, hy::WRITE_CONTROL, &[cntr])?[..] {
            [cnst] => Ok(cnst),
            ref other => Err(bad(
                slave,
                hy::WRITE_CONTROL,
                format!("{} status bytes", other.len()),
            )),
        }
    }

    /// Reads status value `index` (0 SetF .. 7 Tmp).
    pub fn hy_read_status(&mut self, slave: u8, index: u8) -> Result<u16> {
        match self.hy_transact(slave, hy::READ_STATUS, &[index])?[..] {
            [i, hi, lo] if i == index => Ok(u16::from_be_bytes([hi, lo])),
            ref other => Err(bad(
                slave,
                hy::READ_STATUS,
                format!("reply {other:02X?} is not status {index}"),
            )),
        }
    }

    /// Writes the frequency in 0.01 Hz; returns the value echoed.
    pub fn hy_write_frequency(&mut self, slave: u8, centi_hz: u16) -> Result<u16> {
        match self.hy_transact(slave, hy::WRITE_FREQUENCY, &centi_hz.to_be_bytes())?[..] {
            [hi, lo] => Ok(u16::from_be_bytes([hi, lo])),
            ref other => Err(bad(
                slave,
                hy::WRITE_FREQUENCY,
                format!("{} value bytes", other.len()),
            )),
        }
    }
}
