//! A fake sysfs PCI tree in a temp dir, for the tests of every PCI
//! driver: device directories with `vendor`, `device`,
//! `subsystem_vendor`, `subsystem_device`, `enable`, `resource` and one
//! plain file per BAR, which [`MmapWindow`](crate::bus::MmapWindow) maps
//! and [`SysfsIoBar`](crate::bus::SysfsIoBar) reads like the real ones.
//! Test support only: nothing at run time uses it.

use std::io;
use std::path::{Path, PathBuf};

use super::resource::{IORESOURCE_IO, IORESOURCE_MEM};
use super::{PciIds, Sysfs};

/// One BAR of a fake device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FakeBar {
    /// Not implemented.
    Unused,
    /// A memory BAR of `len` bytes at bus address `start`.
    Mem {
        /// Bus address.
        start: u64,
        /// Size in bytes.
        len: u64,
    },
    /// An I/O BAR of `len` ports from `start`.
    Io {
        /// First port.
        start: u16,
        /// Number of ports.
        len: u16,
    },
}

/// A fake `/sys/bus/pci/devices`, removed when dropped.
#[derive(Debug)]
pub struct FakeSysfs {
    /// Held for its removal on drop.
    _tree: tempfile::TempDir,
    dir: PathBuf,
}

impl FakeSysfs {
    /// An empty tree in a new private directory (mode 0700, a random
    /// name made by `mkdtemp`, so nobody can plant it first) whose name
    /// starts with `tag`.
    pub fn new(tag: &str) -> io::Result<FakeSysfs> {
        let tree = tempfile::Builder::new()
            .prefix(&format!("hal-fake-sysfs-{tag}-"))
            .tempdir()?;
        let dir = tree.path().to_path_buf();
        Ok(FakeSysfs { _tree: tree, dir })
    }

    /// The tree as a [`Sysfs`] root.
    pub fn sysfs(&self) -> Sysfs {
        Sysfs::at(&self.dir)
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Adds a device at bus `address` with `ids` and up to six `bars`;
    /// returns its directory. BAR files are zero-filled, of the BAR's
    /// size.
    pub fn add_device(&self, address: &str, ids: PciIds, bars: &[FakeBar]) -> io::Result<PathBuf> {
        let d = self.dir.join(address);
        std::fs::create_dir(&d)?;
        let id = |v: u16| format!("0x{v:04x}\n");
        std::fs::write(d.join("vendor"), id(ids.vendor))?;
        std::fs::write(d.join("device"), id(ids.device))?;
        std::fs::write(d.join("subsystem_vendor"), id(ids.subvendor))?;
        std::fs::write(d.join("subsystem_device"), id(ids.subdevice))?;
        std::fs::write(d.join("enable"), "0\n")?;
        let mut resource = String::new();
        for i in 0..7 {
            let (start, end, flags) = match bars.get(i).copied().unwrap_or(FakeBar::Unused) {
                FakeBar::Unused => (0, 0, 0),
                FakeBar::Mem { start, len } => (start, start + len - 1, IORESOURCE_MEM | 0x40000),
                FakeBar::Io { start, len } => (
                    start as u64,
                    start as u64 + len as u64 - 1,
                    IORESOURCE_IO | 0x40000,
                ),
            };
            resource.push_str(&format!("0x{start:016x} 0x{end:016x} 0x{flags:016x}\n"));
            let len = match bars.get(i) {
                Some(FakeBar::Mem { len, .. }) => *len,
                Some(FakeBar::Io { len, .. }) => *len as u64,
                _ => continue,
            };
            let f = std::fs::File::create(d.join(format!("resource{i}")))?;
            f.set_len(len)?;
        }
        std::fs::write(d.join("resource"), resource)?;
        Ok(d)
    }
}
