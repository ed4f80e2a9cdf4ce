//! The register sequences of `setsserial` on one channel of a Smart
//! Serial port (hostmot2-more.md 2.2, 2.3): starting it in setup mode,
//! the non-volatile and flash access modes, reads and writes of the
//! remote's memory and the cookie. Every wait for the command register
//! is bounded by [`WAIT`].

use std::time::{Duration, Instant};

use crate::error::{Hm2Error, Result};
use crate::md::ModuleDescriptor;
use crate::modules::sserial::discovery::describe_status;
use crate::sserial::{access, cmd, flash, lbp, local, reg};
use crate::transport::Transport;

/// How long a command may take.
pub const WAIT: Duration = Duration::from_secs(1);

/// One channel of a port, driven directly.
pub struct Channel<'a> {
    /// The board's registers.
    pub t: &'a mut dyn Transport,
    /// The Smart Serial module.
    pub md: ModuleDescriptor,
    /// The port.
    pub port: u8,
    /// The channel.
    pub chan: u8,
    /// The mode the remote was found in.
    pub mode: u8,
}

impl Channel<'_> {
    fn at(&self, r: usize, per_channel: bool) -> u32 {
        let c = if per_channel { self.chan as u32 } else { 0 };
        self.md.inst_reg(r, self.port as usize) + 4 * c
    }

    fn fail(&self, reason: String) -> Hm2Error {
        Hm2Error::Sserial {
            port: self.port,
            channel: Some(self.chan),
            reason,
        }
    }

    fn read(&mut self, addr: u32) -> Result<u32> {
        let mut w = [0u32];
        self.t
            .read(addr, &mut w)
            .map_err(|source| Hm2Error::Transport {
                op: format!("error reading the Smart Serial register at 0x{addr:04X}"),
                source,
            })?;
        Ok(w[0])
    }

    fn write(&mut self, addr: u32, v: u32) -> Result<()> {
        self.t
            .write(addr, &[v])
            .map_err(|source| Hm2Error::Transport {
                op: format!("error writing the Smart Serial register at 0x{addr:04X}"),
                source,
            })
    }

    /// Writes command `c` and waits for the register to read 0.
    fn command(&mut self, c: u32) -> Result<()> {
        let at = self.at(reg::COMMAND, false);
        self.write(at, c)?;
        let t0 = Instant::now();
        loop {
            if self.read(at)? == 0 {
                return Ok(());
            }
            if t0.elapsed() > WAIT {
                return Err(self.fail(format!(
                    "command 0x{c:04X} not done after {} ms",
                    WAIT.as_millis()
                )));
            }
            std::thread::sleep(Duration::from_micros(50));
        }
    }

    /// Fails when the data register says the channel failed.
    fn check(&mut self, what: &str) -> Result<()> {
        let data = self.read(self.at(reg::DATA, false))?;
        if data & (1 << self.chan) == 0 {
            return Ok(());
        }
        let st = self.read(self.at(reg::CS, true))?;
        Err(self.fail(format!(
            "{what} (status 0x{st:08X}: {})",
            describe_status(st)
        )))
    }

    /// The port's SSLBP version (its minor revision).
    pub fn sslbp_version(&mut self) -> Result<u8> {
        self.command(cmd::READ_LOCAL | local::MINOR_REV as u32)?;
        Ok(self.read(self.at(reg::DATA, false))? as u8)
    }

    /// Stops every channel of the port.
    pub fn stop_all(&mut self) -> Result<()> {
        self.command(cmd::STOP | 0xFF)
    }

    /// Stops every channel and starts this one in setup mode.
    pub fn start_setup(&mut self) -> Result<()> {
        self.stop_all()?;
        let cs = self.at(reg::CS, true);
        self.write(cs, (self.mode as u32) << 24)?;
        self.command(cmd::START_SETUP | 1 << self.chan)?;
        self.check("the remote did not start in setup mode")
    }

    /// One transfer: CS, then interfaces 0 and 1 if given, a DoIt;
    /// returns interface 0.
    fn transfer(&mut self, cs: u32, i0: Option<u32>, i1: Option<u32>) -> Result<u32> {
        let at_cs = self.at(reg::CS, true);
        let at_i0 = self.at(reg::INTERFACE0, true);
        let at_i1 = self.at(reg::INTERFACE0 + 1, true);
        self.write(at_cs, cs)?;
        if let Some(v) = i0 {
            self.write(at_i0, v)?;
        }
        if let Some(v) = i1 {
            self.write(at_i1, v)?;
        }
        self.command(cmd::DOIT | 1 << self.chan)?;
        self.check("the remote did not answer")?;
        self.read(at_i0)
    }

    /// The non-volatile access command: RAM, EEPROM or flash
    /// ([`access`]).
    pub fn access(&mut self, which: u32) -> Result<()> {
        self.transfer((lbp::NONVOLATILE as u32) << 24, Some(which), None)?;
        if which == access::FLASH {
            let cs = self.at(reg::CS, true);
            self.write(cs, 0)?;
        }
        Ok(())
    }

    /// Writes `value` (`bits` wide) at `addr` of the remote's memory.
    pub fn write_value(&mut self, addr: u16, bits: u8, value: u64) -> Result<()> {
        let size = match bits {
            0..=8 => 0,
            9..=16 => 1,
            17..=32 => 2,
            _ => 3,
        };
        let cs = ((lbp::WRITE + size) as u32) << 24 | addr as u32;
        self.transfer(cs, Some(value as u32), Some((value >> 32) as u32))
            .map(drop)
    }

    /// Reads the byte at `addr` of the remote's memory.
    pub fn read_byte(&mut self, addr: u16) -> Result<u8> {
        let cs = (lbp::READ as u32) << 24 | addr as u32;
        Ok(self.transfer(cs, None, None)? as u8)
    }

    /// Writes a long at `addr`.
    pub fn write_long(&mut self, addr: u16, v: u32) -> Result<()> {
        let cs = (lbp::WRITE_LONG as u32) << 24 | addr as u32;
        self.transfer(cs, Some(v), None).map(drop)
    }

    /// Writes a byte at `addr`.
    pub fn write_byte(&mut self, addr: u16, v: u8) -> Result<()> {
        let cs = (lbp::WRITE_BYTE as u32) << 24 | addr as u32;
        self.transfer(cs, Some(v as u32), None).map(drop)
    }

    /// Writes eight bytes at `addr` (little-endian, interfaces 0 and 1).
    pub fn write_double(&mut self, addr: u16, b: [u8; 8]) -> Result<()> {
        let cs = (lbp::WRITE_DOUBLE as u32) << 24 | addr as u32;
        let lo = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        let hi = u32::from_le_bytes([b[4], b[5], b[6], b[7]]);
        self.transfer(cs, Some(lo), Some(hi)).map(drop)
    }

    /// Reads the cookie and fails unless it says the remote is in step.
    pub fn check_cookie(&mut self) -> Result<()> {
        let c = self.transfer((lbp::COOKIE as u32) << 24, None, None)? as u8;
        if c == flash::COOKIE {
            Ok(())
        } else {
            Err(Hm2Error::FlashSyncFailed { cookie: c })
        }
    }
}
