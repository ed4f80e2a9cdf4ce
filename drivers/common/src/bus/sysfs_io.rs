//! [`SysfsIoBar`]: a PCI I/O BAR through its sysfs `resourceN` file.
//!
//! I/O BARs cannot be mapped; the kernel lets their resource file be read
//! and written with `pread`/`pwrite` of exactly 1, 2 or 4 bytes at the
//! offset into the BAR, and turns each into one `in`/`out` of that width.
//! This backend is addressed by absolute port number like every
//! [`PortBus`], so a driver runs unchanged on it or on
//! [`IopermPorts`](super::IopermPorts) at the BAR's start. It needs only access to the
//! file (a udev rule), no capability; kernel lockdown refuses it.

use std::fs::{File, OpenOptions};
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::ranges::PortRange;
use super::{PortBus, ALL_ONES};
use crate::error::{classify, Result};

/// An I/O BAR reached through its resource file.
#[derive(Debug)]
pub struct SysfsIoBar {
    file: File,
    path: PathBuf,
    range: PortRange,
    errors: AtomicU64,
}

impl SysfsIoBar {
    /// Opens the resource file `path` of an I/O BAR occupying `range`.
    pub fn open(path: &Path, range: PortRange) -> Result<SysfsIoBar> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| classify("opening", path, e))?;
        Ok(SysfsIoBar {
            file,
            path: path.to_path_buf(),
            range,
            errors: AtomicU64::new(0),
        })
    }

    /// The ports the BAR occupies.
    pub fn range(&self) -> PortRange {
        self.range
    }

    #[inline]
    fn read<const N: usize>(&self, port: u16) -> Option<[u8; N]> {
        let mut b = [0u8; N];
        let ok = self.range.covers(port, N as u16)
            && self
                .file
                .read_at(&mut b, (port - self.range.base) as u64)
                .ok()
                == Some(N);
        if ok {
            Some(b)
        } else {
            self.errors.fetch_add(1, Relaxed);
            None
        }
    }

    #[inline]
    fn write(&self, port: u16, bytes: &[u8]) {
        let ok = self.range.covers(port, bytes.len() as u16)
            && self
                .file
                .write_at(bytes, (port - self.range.base) as u64)
                .ok()
                == Some(bytes.len());
        if !ok {
            self.errors.fetch_add(1, Relaxed);
        }
    }
}

impl PortBus for SysfsIoBar {
    fn inb(&self, port: u16) -> u8 {
        self.read::<1>(port).map_or(ALL_ONES as u8, |b| b[0])
    }
    fn outb(&self, port: u16, value: u8) {
        self.write(port, &[value])
    }
    fn inw(&self, port: u16) -> u16 {
        self.read::<2>(port)
            .map_or(ALL_ONES as u16, u16::from_le_bytes)
    }
    fn outw(&self, port: u16, value: u16) {
        self.write(port, &value.to_le_bytes())
    }
    fn inl(&self, port: u16) -> u32 {
        self.read::<4>(port).map_or(ALL_ONES, u32::from_le_bytes)
    }
    fn outl(&self, port: u16, value: u32) {
        self.write(port, &value.to_le_bytes())
    }
    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }
    fn describe(&self) -> String {
        format!("{} (I/O ports {})", self.path.display(), self.range)
    }
}
