//! The EPP transport: HostMot2 register bursts as EPP address and data
//! cycles on a parallel port ([`super`] describes the cycles).
//!
//! Like a memory window it needs no batching: queued reads are read when
//! the receive asks for them, queued writes are written at once. Every
//! burst ends with a look at the status register: a timeout there (the
//! board did not answer a cycle) is cleared and reported.

use std::sync::Arc;

use hal_driver::bus::PortBus;

use super::{ecr, reg, ADDRESS_MASK, AUTO_INCREMENT, CONTROL_EPP, STATUS_TIMEOUT};
use crate::transport::{ReadQueue, TransferStats, Transport, TransportError};

/// The highest byte address (exclusive) EPP reaches.
const EPP_WINDOW: u32 = ADDRESS_MASK as u32 + 1;

/// A [`Transport`] of EPP cycles on the parallel port at `base`.
pub struct EppTransport {
    bus: Arc<dyn PortBus>,
    base: u16,
    base_hi: Option<u16>,
    wide: bool,
    reads: ReadQueue,
    stats: TransferStats,
    errors: u64,
    timeouts: u64,
}

impl std::fmt::Debug for EppTransport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EppTransport")
            .field("base", &format_args!("{:#x}", self.base))
            .field("base_hi", &self.base_hi)
            .field("wide", &self.wide)
            .finish()
    }
}

impl EppTransport {
    /// A transport on the port at `base` (ECR block at `base_hi`, if the
    /// port has one) over `bus`; `wide`: 32-bit data accesses.
    pub fn new(bus: Arc<dyn PortBus>, base: u16, base_hi: Option<u16>, wide: bool) -> EppTransport {
        let errors = bus.errors();
        EppTransport {
            bus,
            base,
            base_hi,
            wide,
            reads: ReadQueue::default(),
            stats: TransferStats::default(),
            errors,
            timeouts: 0,
        }
    }

    /// Puts the port in EPP mode (ECR, when the port has one; control
    /// lines) and clears a timeout left from before. Fails if the
    /// timeout does not clear or the bus refused the accesses.
    pub fn set_up(&mut self) -> Result<(), TransportError> {
        if let Some(hi) = self.base_hi {
            self.bus.outb(hi.wrapping_add(reg::ECR_HI), ecr::EPP);
        }
        self.bus
            .outb(self.base.wrapping_add(reg::CONTROL), CONTROL_EPP);
        if !self.clear_timeout() {
            return Err(TransportError::EppTimeout {
                addr: 0,
                port: self.base,
            });
        }
        self.check_bus()
    }

    /// EPP timeouts seen since the transport was made.
    pub fn timeouts(&self) -> u64 {
        self.timeouts
    }

    fn status(&self) -> u8 {
        self.bus.inb(self.base.wrapping_add(reg::STATUS))
    }

    fn clear_timeout(&self) -> bool {
        clear_timeout(&*self.bus, self.base)
    }

    /// The 7I43's CPLD behind this transport's port, for loading its FPGA
    /// before the board is registered.
    pub fn cpld(&self) -> super::cpld::Cpld<'_> {
        super::cpld::Cpld::new(&*self.bus, self.base)
    }

    fn read_words(&self, addr: u32, buf: &mut [u32]) {
        read_words(&*self.bus, self.base, self.wide, addr, buf);
    }

    fn write_words(&self, addr: u32, data: &[u32]) {
        select(&*self.bus, self.base, addr);
        let at = self.base.wrapping_add(reg::EPP_DATA);
        for &w in data {
            if self.wide {
                self.bus.outl(at, w);
            } else {
                for b in w.to_le_bytes() {
                    self.bus.outb(at, b);
                }
            }
        }
    }

    fn check_bus(&mut self) -> Result<(), TransportError> {
        let now = self.bus.errors();
        if now != self.errors {
            self.errors = now;
            return Err(TransportError::Bus { count: now });
        }
        Ok(())
    }

    /// After a burst at `addr`: a timeout (cleared) or bus errors fail it.
    fn check(&mut self, addr: u32) -> Result<(), TransportError> {
        if self.status() & STATUS_TIMEOUT != 0 {
            self.timeouts += 1;
            self.clear_timeout();
            return Err(TransportError::EppTimeout {
                addr,
                port: self.base,
            });
        }
        self.check_bus()
    }
}

/// Whether the status register of the port at `base` shows an EPP timeout.
pub(super) fn timed_out(bus: &dyn PortBus, base: u16) -> bool {
    bus.inb(base.wrapping_add(reg::STATUS)) & STATUS_TIMEOUT != 0
}

/// Clears the status register's timeout bit of the port at `base`: port
/// chips differ (some clear it when read, some when it is written as 1,
/// some as 0), so all three. True if it is clear now.
pub(super) fn clear_timeout(bus: &dyn PortBus, base: u16) -> bool {
    if !timed_out(bus, base) {
        return true;
    }
    let at = base.wrapping_add(reg::STATUS);
    let _ = bus.inb(at);
    let st = bus.inb(at);
    bus.outb(at, st | STATUS_TIMEOUT);
    bus.outb(at, st & !STATUS_TIMEOUT);
    !timed_out(bus, base)
}

/// An address cycle pair on the port at `base`: `addr` with
/// auto-increment.
fn select(bus: &dyn PortBus, base: u16, addr: u32) {
    let a = (addr as u16 & ADDRESS_MASK) | AUTO_INCREMENT;
    let at = base.wrapping_add(reg::EPP_ADDRESS);
    bus.outb(at, a as u8);
    bus.outb(at, (a >> 8) as u8);
}

/// Reads `buf.len()` registers from `addr` on the port at `base`.
fn read_words(bus: &dyn PortBus, base: u16, wide: bool, addr: u32, buf: &mut [u32]) {
    select(bus, base, addr);
    let at = base.wrapping_add(reg::EPP_DATA);
    for w in buf {
        *w = if wide {
            bus.inl(at)
        } else {
            (0..4).fold(0u32, |v, i| v | (bus.inb(at) as u32) << (8 * i))
        };
    }
}

/// Refuses a burst that leaves the 15-bit EPP address range.
fn check_range(addr: u32, words: usize) -> Result<(), TransportError> {
    let end = (addr as u64).saturating_add(4 * words as u64);
    if end > EPP_WINDOW as u64 {
        return Err(TransportError::EppRange { addr, words });
    }
    Ok(())
}

impl Transport for EppTransport {
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError> {
        check_range(addr, buf.len())?;
        self.read_words(addr, buf);
        self.stats.words_read += buf.len() as u64;
        self.stats.read_bursts += 1;
        self.check(addr)
    }

    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        check_range(addr, data.len())?;
        self.write_words(addr, data);
        self.stats.words_written += data.len() as u64;
        self.stats.write_bursts += 1;
        self.check(addr)
    }

    fn reserve(&mut self, reads: usize, _read_words: usize, _writes: usize, _write_words: usize) {
        self.reads.reserve(reads);
    }

    fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
        check_range(addr, words)?;
        self.reads.push(addr, words)
    }

    fn send_queued_reads(&mut self) -> Result<(), TransportError> {
        Ok(())
    }

    fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError> {
        let first = self.reads.items().first().map_or(0, |&(a, _)| a);
        let (bus, base, wide) = (&*self.bus, self.base, self.wide);
        self.reads.receive(out, &mut self.stats, |addr, dst| {
            read_words(bus, base, wide, addr, dst)
        })?;
        self.check(first)
    }

    fn send_queued_writes(&mut self) -> Result<(), TransportError> {
        self.check_bus()
    }

    fn stats(&self) -> TransferStats {
        self.stats
    }

    /// One EPP port serves one thread at a time (LinuxCNC's 7I43 llio is
    /// not thread-safe either): no `read_gpio`/`write_gpio`.
    fn threadsafe(&self) -> bool {
        false
    }

    fn describe(&self) -> String {
        format!(
            "parallel port at {:#x} (EPP{}), {}",
            self.base,
            if self.wide { ", 32-bit" } else { "" },
            self.bus.describe()
        )
    }
}
