//! The two register buses a driver talks through, and their real
//! backends. The simulated backends are [`crate::sim::SimBoard`]s.
//!
//! * [`RegWindow`]: a window of 32-bit registers in memory (a PCI memory
//!   BAR, a simulated board), addressed by byte offset.
//! * [`PortBus`]: x86 I/O ports by absolute address, 8/16/32 bits wide.
//!
//! Both are `Send + Sync` with `&self` accessors, so the `read` and
//! `write` functions of one board may run in different HAL threads.
//! Accessors are what realtime functions call, so they never fail
//! visibly and never panic: an access that cannot be made (outside the
//! window or the declared port ranges, misaligned, a failed system call,
//! a port permission missing in this thread) reads as all ones, as a PCI
//! master abort does, writes nothing, and is counted in `errors()`, which
//! the driver reports from non-realtime code (at unload, in a status
//! pin).
//!
//! Real backends:
//!
//! | backend | bus | what it uses |
//! |---|---|---|
//! | [`MmapWindow`] | `RegWindow` | memmap2 over a file: a sysfs `resourceN` of a memory BAR (or a plain file in tests) |
//! | [`IopermPorts`] | `PortBus` | `ioperm` over declared ranges and x86 `in`/`out`; the permission is taken per thread on first use |
//! | [`DevPortPorts`] | `PortBus` | `pread`/`pwrite` on `/dev/port` |
//! | [`SysfsIoBar`] | `PortBus` | `pread`/`pwrite` of 1, 2 or 4 bytes on an I/O BAR's sysfs `resourceN` |
//! | [`Spidev`] | [`SpiBus`] | the `SPI_IOC_MESSAGE` ioctl on `/dev/spidevB.C` (a third bus: a full-duplex SPI link) |
//!
//! Every backend and the simulator also take [`RegWindow::tick`] /
//! [`PortBus::tick`]: a driver's `read` function passes the HAL thread's
//! time (`FunctCtx::now_ns`) once per cycle; hardware ignores it, a
//! simulated board advances its model by the time elapsed.

mod devport;
mod ioperm;
mod mmap;
mod ranges;
mod spi;
mod sysfs_io;

pub use devport::DevPortPorts;
pub use ioperm::IopermPorts;
pub use mmap::MmapWindow;
pub use ranges::PortRange;
pub use spi::{SpiBus, Spidev, MAX_MESSAGE_WORDS};
pub use sysfs_io::SysfsIoBar;

use std::sync::Arc;

/// What a failed read returns (a PCI master abort, an empty ISA bus).
pub const ALL_ONES: u32 = u32::MAX;

/// A window of 32-bit memory-mapped registers.
pub trait RegWindow: Send + Sync {
    /// The window's size in bytes.
    fn len(&self) -> usize;

    /// Whether the window is empty (it never is for a mapped BAR).
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Reads the register at byte `offset` (4-aligned, inside the window;
    /// otherwise reads all ones and counts an error).
    fn read32(&self, offset: usize) -> u32;

    /// Writes the register at byte `offset` (4-aligned, inside the
    /// window; otherwise writes nothing and counts an error).
    fn write32(&self, offset: usize, value: u32);

    /// Reads `out.len()` consecutive registers from byte `offset`.
    fn read_burst(&self, offset: usize, out: &mut [u32]) {
        for (i, v) in out.iter_mut().enumerate() {
            *v = self.read32(offset.wrapping_add(4 * i));
        }
    }

    /// Writes `data` to consecutive registers from byte `offset`.
    fn write_burst(&self, offset: usize, data: &[u32]) {
        for (i, v) in data.iter().enumerate() {
            self.write32(offset.wrapping_add(4 * i), *v);
        }
    }

    /// How many accesses failed since the window was opened.
    fn errors(&self) -> u64;

    /// What this window is, for messages (a BAR's file, "simulated 5i25").
    fn describe(&self) -> String;

    /// The HAL thread's time (CLOCK_MONOTONIC ns), passed once per cycle
    /// by the driver's `read` function. Hardware ignores it; a simulated
    /// board that follows thread time advances by the time elapsed.
    #[inline]
    fn tick(&self, now_ns: u64) {
        let _ = now_ns;
    }
}

/// x86 I/O ports by absolute address.
pub trait PortBus: Send + Sync {
    /// Reads a byte (all ones on failure, counted).
    fn inb(&self, port: u16) -> u8;
    /// Writes a byte (nothing on failure, counted).
    fn outb(&self, port: u16, value: u8);
    /// Reads 16 bits.
    fn inw(&self, port: u16) -> u16;
    /// Writes 16 bits.
    fn outw(&self, port: u16, value: u16);
    /// Reads 32 bits.
    fn inl(&self, port: u16) -> u32;
    /// Writes 32 bits.
    fn outl(&self, port: u16, value: u32);
    /// How many accesses failed since the bus was opened.
    fn errors(&self) -> u64;
    /// What this bus is, for messages.
    fn describe(&self) -> String;
    /// The HAL thread's time, as [`RegWindow::tick`].
    #[inline]
    fn tick(&self, now_ns: u64) {
        let _ = now_ns;
    }
}

macro_rules! forward_reg_window {
    ($($ty:ty),*) => {$(
        impl<T: RegWindow + ?Sized> RegWindow for $ty {
            #[inline]
            fn len(&self) -> usize { (**self).len() }
            #[inline]
            fn read32(&self, offset: usize) -> u32 { (**self).read32(offset) }
            #[inline]
            fn write32(&self, offset: usize, value: u32) { (**self).write32(offset, value) }
            #[inline]
            fn read_burst(&self, offset: usize, out: &mut [u32]) { (**self).read_burst(offset, out) }
            #[inline]
            fn write_burst(&self, offset: usize, data: &[u32]) { (**self).write_burst(offset, data) }
            fn errors(&self) -> u64 { (**self).errors() }
            fn describe(&self) -> String { (**self).describe() }
            #[inline]
            fn tick(&self, now_ns: u64) { (**self).tick(now_ns) }
        }
    )*};
}

macro_rules! forward_port_bus {
    ($($ty:ty),*) => {$(
        impl<T: PortBus + ?Sized> PortBus for $ty {
            #[inline]
            fn inb(&self, port: u16) -> u8 { (**self).inb(port) }
            #[inline]
            fn outb(&self, port: u16, value: u8) { (**self).outb(port, value) }
            #[inline]
            fn inw(&self, port: u16) -> u16 { (**self).inw(port) }
            #[inline]
            fn outw(&self, port: u16, value: u16) { (**self).outw(port, value) }
            #[inline]
            fn inl(&self, port: u16) -> u32 { (**self).inl(port) }
            #[inline]
            fn outl(&self, port: u16, value: u32) { (**self).outl(port, value) }
            fn errors(&self) -> u64 { (**self).errors() }
            fn describe(&self) -> String { (**self).describe() }
            #[inline]
            fn tick(&self, now_ns: u64) { (**self).tick(now_ns) }
        }
    )*};
}

forward_reg_window!(Arc<T>, Box<T>, &T);
forward_port_bus!(Arc<T>, Box<T>, &T);
