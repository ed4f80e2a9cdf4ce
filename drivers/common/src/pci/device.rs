//! One PCI device found by [`scan`](super::scan): enabling it, its
//! regions, and opening them as register buses.

use std::path::{Path, PathBuf};

use super::resource::{self, Resource};
use super::{PciIds, PciMatch};
use crate::bus::{MmapWindow, PortRange, SysfsIoBar};
use crate::error::{classify, DriverError, Result};

/// A device that matched a driver's ID table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PciDevice {
    /// Its bus address, `DDDD:BB:DD.F` (the sysfs directory's name).
    pub address: String,
    /// Its IDs.
    pub ids: PciIds,
    /// Its sysfs directory.
    pub path: PathBuf,
    /// The table entry it matched.
    pub matched: PciMatch,
}

/// Keeps a device enabled; writes 0 to its enable file when dropped
/// (sysfs counts enables, so this undoes exactly this driver's).
#[derive(Debug)]
pub struct EnableGuard {
    path: PathBuf,
}

impl EnableGuard {
    /// The enable file written.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for EnableGuard {
    fn drop(&mut self) {
        // Nothing to report to: the device goes away with the driver.
        let _ = std::fs::write(&self.path, "0");
    }
}

impl PciDevice {
    /// The board's name from the table entry it matched.
    pub fn name(&self) -> &'static str {
        self.matched.name
    }

    /// Enables the device (writes 1 to `enable`, or to `enabled` on
    /// kernels that call it that), which makes its BARs decode. The
    /// returned guard disables it again.
    pub fn enable(&self) -> Result<EnableGuard> {
        let path = ["enable", "enabled"]
            .iter()
            .map(|f| self.path.join(f))
            .find(|p| p.exists())
            .unwrap_or_else(|| self.path.join("enable"));
        std::fs::write(&path, "1").map_err(|e| classify("writing 1 to", &path, e))?;
        Ok(EnableGuard { path })
    }

    /// Every region the `resource` file lists (BARs 0..5 first).
    pub fn resources(&self) -> Result<Vec<Resource>> {
        let path = self.path.join("resource");
        let text = std::fs::read_to_string(&path).map_err(|e| DriverError::Io {
            path: path.clone(),
            op: "reading",
            source: e,
        })?;
        resource::parse(&text, &path)
    }

    /// BAR `bar`, failing with [`DriverError::BarMissing`] when the device
    /// does not implement it.
    pub fn bar(&self, bar: usize) -> Result<Resource> {
        let r = self.resources()?.get(bar).copied().unwrap_or_default();
        if bar > 5 || !r.is_present() {
            return Err(DriverError::BarMissing {
                device: self.address.clone(),
                bar,
            });
        }
        Ok(r)
    }

    /// The sysfs file of BAR `bar` (`resourceN`).
    pub fn resource_path(&self, bar: usize) -> PathBuf {
        self.path.join(format!("resource{bar}"))
    }

    fn mem_bar(&self, bar: usize) -> Result<Resource> {
        let r = self.bar(bar)?;
        if !r.is_mem() {
            return Err(DriverError::BarKind {
                device: self.address.clone(),
                bar,
                found: r.kind(),
                expected: "a memory BAR",
            });
        }
        Ok(r)
    }

    /// Maps the whole memory BAR `bar`.
    pub fn map_bar(&self, bar: usize) -> Result<MmapWindow> {
        let len = self.mem_bar(bar)?.len();
        self.map(bar, len)
    }

    /// Maps the first `len` bytes of memory BAR `bar`, failing with
    /// [`DriverError::BarTooSmall`] when the BAR is shorter.
    pub fn map_bar_window(&self, bar: usize, len: usize) -> Result<MmapWindow> {
        let size = self.mem_bar(bar)?.len();
        if size < len as u64 {
            return Err(DriverError::BarTooSmall {
                device: self.address.clone(),
                bar,
                size,
                needed: len as u64,
            });
        }
        self.map(bar, len as u64)
    }

    fn map(&self, bar: usize, len: u64) -> Result<MmapWindow> {
        let path = self.resource_path(bar);
        let len = usize::try_from(len).map_err(|_| DriverError::BarTooSmall {
            device: self.address.clone(),
            bar,
            size: len,
            needed: len,
        })?;
        // The resource file must cover the mapping: a shorter one (a
        // broken fake tree) would SIGBUS on access.
        let file_len = std::fs::metadata(&path)
            .map_err(|e| classify("opening", &path, e))?
            .len();
        if file_len < len as u64 {
            return Err(DriverError::BarTooSmall {
                device: self.address.clone(),
                bar,
                size: file_len,
                needed: len as u64,
            });
        }
        MmapWindow::open_len(&path, len)
    }

    /// Opens I/O BAR `bar` through its resource file.
    pub fn io_bar(&self, bar: usize) -> Result<SysfsIoBar> {
        let r = self.bar(bar)?;
        if !r.is_io() {
            return Err(DriverError::BarKind {
                device: self.address.clone(),
                bar,
                found: r.kind(),
                expected: "an I/O BAR",
            });
        }
        let range = u16::try_from(r.start)
            .ok()
            .zip(u16::try_from(r.len()).ok())
            .and_then(|(base, len)| PortRange::new(base, len).ok())
            .ok_or_else(|| DriverError::BadSysfs {
                path: self.path.join("resource"),
                reason: format!(
                    "BAR {bar}: I/O range {:#x}..{:#x} is outside the 16-bit port space",
                    r.start, r.end
                ),
            })?;
        SysfsIoBar::open(&self.resource_path(bar), range)
    }
}
