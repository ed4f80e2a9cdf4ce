//! EPP cycles on a PC parallel port, over the shared driver layer's port
//! bus (raw port I/O or a simulated port): the address and data cycles
//! the Pico boards answer.
//!
//! An address cycle is a byte written to the port's EPP address register
//! (`base + 3`); a data cycle a byte read or written at its EPP data
//! register (`base + 4`). The boards step their address after each data
//! cycle, so a run of registers takes one address cycle and one data
//! cycle per byte. Before an address cycle the control register is set
//! for output ([`CONTROL_WRITE`]); before a read's data cycle, with
//! `epp_dir=0` (the default, as LinuxCNC 2.7.8 and later), it is turned
//! for input ([`CONTROL_READ`]), which some port chips need; with
//! `epp_dir=1` it is left as it is. A cycle the board does not answer
//! sets the status register's timeout bit ([`STATUS_TIMEOUT`]), cleared
//! before each address cycle.
//!
//! Nothing here allocates or blocks: the realtime functions call it.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use hal_driver::bus::PortBus;
use hal_parport::regs;

/// The status register's EPP timeout bit.
pub const STATUS_TIMEOUT: u8 = 0x01;
/// Control register for address cycles and writes: nInit high, data
/// lines driven.
pub const CONTROL_WRITE: u8 = 0x04;
/// Control register for reads: as [`CONTROL_WRITE`] with the data lines
/// turned to input.
pub const CONTROL_READ: u8 = 0x04 | regs::CONTROL_DIR_IN;

/// One parallel port, in EPP mode.
#[derive(Clone)]
pub struct Epp {
    bus: Arc<dyn PortBus>,
    base: u16,
    turn_for_reads: bool,
    timeouts: Arc<AtomicU64>,
}

impl std::fmt::Debug for Epp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Epp")
            .field("base", &format_args!("{:#x}", self.base))
            .field("turn_for_reads", &self.turn_for_reads)
            .finish()
    }
}

impl Epp {
    /// The port at `base` over `bus`; `turn_for_reads`: set the data
    /// direction before each read (`epp_dir=0`).
    pub fn new(bus: Arc<dyn PortBus>, base: u16, turn_for_reads: bool) -> Epp {
        Epp {
            bus,
            base,
            turn_for_reads,
            timeouts: Arc::new(AtomicU64::new(0)),
        }
    }

    /// The port's base address.
    pub fn base(&self) -> u16 {
        self.base
    }

    /// The bus the cycles go over.
    pub fn bus(&self) -> &Arc<dyn PortBus> {
        &self.bus
    }

    /// Puts the port in EPP mode: the ECR (at `base_hi + 2`, when the
    /// port has one) and the control lines; clears a stale timeout.
    pub fn set_up(&self, base_hi: Option<u16>) {
        if let Some(hi) = base_hi {
            self.bus
                .outb(hi.wrapping_add(regs::ECR), regs::ECR_EPP_MODE);
        }
        self.bus
            .outb(self.base.wrapping_add(regs::CONTROL), CONTROL_WRITE);
        self.clear_timeout();
    }

    /// Whether the last cycles timed out (the status register's bit 0).
    #[inline]
    pub fn timed_out(&self) -> bool {
        self.bus.inb(self.base.wrapping_add(regs::STATUS)) & STATUS_TIMEOUT != 0
    }

    /// Timeouts found (and cleared) before address cycles so far.
    pub fn timeouts(&self) -> u64 {
        self.timeouts.load(Relaxed)
    }

    /// Clears a timeout: some chips clear it on a second read, others
    /// when it is written as 1. Whether it is clear now.
    #[inline]
    pub fn clear_timeout(&self) -> bool {
        let status = self.base.wrapping_add(regs::STATUS);
        if self.bus.inb(status) & STATUS_TIMEOUT == 0 {
            return true;
        }
        self.timeouts.fetch_add(1, Relaxed);
        let s = self.bus.inb(status);
        self.bus.outb(status, s | STATUS_TIMEOUT);
        self.bus.inb(status) & STATUS_TIMEOUT == 0
    }

    #[inline]
    fn address(&self, addr: u8) {
        self.clear_timeout();
        self.bus
            .outb(self.base.wrapping_add(regs::CONTROL), CONTROL_WRITE);
        self.bus.outb(self.base.wrapping_add(regs::EPP_ADDR), addr);
    }

    /// An address cycle to `addr`, then one data read.
    #[inline]
    pub fn select_read(&self, addr: u8) -> u8 {
        self.address(addr);
        if self.turn_for_reads {
            self.bus
                .outb(self.base.wrapping_add(regs::CONTROL), CONTROL_READ);
        }
        self.read_more()
    }

    /// The next data read (the board has stepped its address).
    #[inline]
    pub fn read_more(&self) -> u8 {
        self.bus.inb(self.base.wrapping_add(regs::EPP_DATA))
    }

    /// An address cycle to `addr`, then one data write.
    #[inline]
    pub fn select_write(&self, addr: u8, value: u8) {
        self.address(addr);
        self.write_more(value);
    }

    /// The next data write.
    #[inline]
    pub fn write_more(&self, value: u8) {
        self.bus.outb(self.base.wrapping_add(regs::EPP_DATA), value);
    }

    /// Reads the registers of `map` (bit n: register `base + n`) into
    /// `buf[n]`: each run of set bits is one address cycle and its data
    /// cycles.
    #[inline]
    pub fn read_map(&self, base: u8, map: u32, buf: &mut [u8; 32]) {
        let mut in_run = false;
        for (n, b) in buf.iter_mut().enumerate() {
            if map & (1 << n) == 0 {
                in_run = false;
                continue;
            }
            *b = if in_run {
                self.read_more()
            } else {
                self.select_read(base.wrapping_add(n as u8))
            };
            in_run = true;
        }
    }

    /// Writes `buf[n]` to the registers of `map`, in runs as
    /// [`read_map`](Self::read_map) reads.
    #[inline]
    pub fn write_map(&self, base: u8, map: u32, buf: &[u8; 32]) {
        let mut in_run = false;
        for (n, b) in buf.iter().enumerate() {
            if map & (1 << n) == 0 {
                in_run = false;
                continue;
            }
            if in_run {
                self.write_more(*b);
            } else {
                self.select_write(base.wrapping_add(n as u8), *b);
            }
            in_run = true;
        }
    }
}

/// The bitmap of registers `first..=last`.
pub const fn block(first: u8, last: u8) -> u32 {
    let mut m = 0u32;
    let mut n = first;
    while n <= last && n < 32 {
        m |= 1 << n;
        n += 1;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks() {
        assert_eq!(block(0, 0), 1);
        assert_eq!(block(0x0D, 0x0E), 0x6000);
        assert_eq!(block(0x10, 0x1E), 0x7FFF_0000);
        assert_eq!(block(3, 2), 0);
    }
}
