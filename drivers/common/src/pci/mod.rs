//! PCI discovery through sysfs, as LinuxCNC's user-space PCI layer does
//! it (hardware.md §1.3): list the devices, match vendor, device and
//! (where the table says so) subsystem IDs against the driver's table,
//! enable the device, read its `resource` file, map a memory BAR's
//! `resourceN` or open an I/O BAR's.
//!
//! The sysfs root is a value ([`Sysfs`]), never a global: the real one is
//! [`Sysfs::system`], tests build a fake tree in a temp dir
//! ([`Sysfs::at`]; plain files for `vendor`, `resource`, `resourceN`),
//! and the VM rig's ivshmem device is found like any board.
//!
//! ```no_run
//! use hal_driver::pci::{self, PciMatch, Sysfs};
//! use hal_driver::bus::RegWindow;
//!
//! const BOARDS: &[PciMatch] = &[PciMatch::new(0x2718, 0x5125, "5i25").subsystem(0x2718, 0x5125)];
//! # fn main() -> hal_driver::Result<()> {
//! for dev in pci::find(&Sysfs::system(), BOARDS)? {
//!     let _enabled = dev.enable()?; // disabled again when dropped
//!     let regs = dev.map_bar_window(0, 0x10000)?;
//!     println!("{} at {}: cookie {:#x}", dev.name(), dev.address, regs.read32(0x100));
//! }
//! # Ok(()) }
//! ```

mod device;
#[cfg(any(test, feature = "testing"))]
pub mod fake;
pub mod resource;

pub use device::{EnableGuard, PciDevice};
pub use resource::Resource;

use std::path::{Path, PathBuf};

use crate::error::{DriverError, Result};

/// Where the PCI devices are listed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sysfs {
    root: PathBuf,
}

impl Sysfs {
    /// The system's `/sys/bus/pci/devices`.
    pub fn system() -> Sysfs {
        Sysfs::at("/sys/bus/pci/devices")
    }

    /// A tree at `dir` laid out like `/sys/bus/pci/devices` (one directory
    /// per device, named by its bus address).
    pub fn at(dir: impl Into<PathBuf>) -> Sysfs {
        Sysfs { root: dir.into() }
    }

    /// The directory listed.
    pub fn root(&self) -> &Path {
        &self.root
    }
}

/// One entry of a driver's ID table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PciMatch {
    /// Vendor ID.
    pub vendor: u16,
    /// Device ID.
    pub device: u16,
    /// Subsystem vendor ID, when the board is told apart by it.
    pub subvendor: Option<u16>,
    /// Subsystem device ID, when the board is told apart by it.
    pub subdevice: Option<u16>,
    /// The board's name (`5i25`, `MOTENC-100`), for messages and HAL
    /// names.
    pub name: &'static str,
}

impl PciMatch {
    /// Matches `vendor:device` with any subsystem.
    pub const fn new(vendor: u16, device: u16, name: &'static str) -> PciMatch {
        PciMatch {
            vendor,
            device,
            subvendor: None,
            subdevice: None,
            name,
        }
    }

    /// The same, matching only subsystem `subvendor:subdevice` too.
    pub const fn subsystem(self, subvendor: u16, subdevice: u16) -> PciMatch {
        PciMatch {
            subvendor: Some(subvendor),
            subdevice: Some(subdevice),
            ..self
        }
    }

    /// Whether a device with `ids` is this board.
    pub fn matches(&self, ids: &PciIds) -> bool {
        self.vendor == ids.vendor
            && self.device == ids.device
            && self.subvendor.is_none_or(|v| v == ids.subvendor)
            && self.subdevice.is_none_or(|d| d == ids.subdevice)
    }
}

impl std::fmt::Display for PciMatch {
    /// `5i25 (2718:5125, subsystem 2718:5125)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({:04x}:{:04x}", self.name, self.vendor, self.device)?;
        match (self.subvendor, self.subdevice) {
            (Some(v), Some(d)) => write!(f, ", subsystem {v:04x}:{d:04x})"),
            (Some(v), None) => write!(f, ", subsystem {v:04x}:*)"),
            (None, Some(d)) => write!(f, ", subsystem *:{d:04x})"),
            (None, None) => write!(f, ")"),
        }
    }
}

/// A device's four IDs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PciIds {
    /// Vendor ID.
    pub vendor: u16,
    /// Device ID.
    pub device: u16,
    /// Subsystem vendor ID.
    pub subvendor: u16,
    /// Subsystem device ID.
    pub subdevice: u16,
}

impl std::fmt::Display for PciIds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:04x}:{:04x} (subsystem {:04x}:{:04x})",
            self.vendor, self.device, self.subvendor, self.subdevice
        )
    }
}

/// Reads a sysfs ID file (`0x2718\n`).
fn read_id(dir: &Path, file: &str) -> Result<u16> {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).map_err(|e| DriverError::Io {
        path: path.clone(),
        op: "reading",
        source: e,
    })?;
    parse_id(&text, &path)
}

/// Parses the text of a sysfs ID file read from `path`: `0x` and four
/// hex digits or fewer, surrounding whitespace allowed.
pub fn parse_id(text: &str, path: &Path) -> Result<u16> {
    let t = text.trim();
    t.strip_prefix("0x")
        .filter(|h| !h.is_empty() && h.len() <= 4 && h.bytes().all(|b| b.is_ascii_hexdigit()))
        .and_then(|h| u16::from_str_radix(h, 16).ok())
        .ok_or_else(|| DriverError::BadSysfs {
            path: path.to_path_buf(),
            reason: format!("expected a 16-bit ID like 0x2718, found '{t}'"),
        })
}

/// Sort key of a bus address `DDDD:BB:DD.F`: numeric where it parses, so
/// a five-digit domain sorts after four-digit ones.
fn address_key(address: &str) -> (Vec<u64>, String) {
    let parts: Option<Vec<u64>> = address
        .split([':', '.'])
        .map(|part| u64::from_str_radix(part, 16).ok())
        .collect();
    (parts.unwrap_or_else(|| vec![u64::MAX]), address.to_string())
}

/// Every device under `sysfs` that matches an entry of `table`, in bus
/// address order, each with the first entry it matches. An empty result
/// is not an error here (a board tool lists what there is); drivers that
/// need a board use [`find`].
pub fn scan(sysfs: &Sysfs, table: &[PciMatch]) -> Result<Vec<PciDevice>> {
    let root = sysfs.root();
    let entries = std::fs::read_dir(root).map_err(|e| DriverError::Io {
        path: root.to_path_buf(),
        op: "listing PCI devices in",
        source: e,
    })?;
    let mut found = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| DriverError::Io {
            path: root.to_path_buf(),
            op: "listing PCI devices in",
            source: e,
        })?;
        let path = entry.path();
        // Not a device directory (no vendor file): not ours to judge.
        if !path.join("vendor").exists() {
            continue;
        }
        let (vendor, device) = (read_id(&path, "vendor")?, read_id(&path, "device")?);
        if !table
            .iter()
            .any(|m| m.vendor == vendor && m.device == device)
        {
            continue;
        }
        let ids = PciIds {
            vendor,
            device,
            subvendor: read_id(&path, "subsystem_vendor")?,
            subdevice: read_id(&path, "subsystem_device")?,
        };
        if let Some(m) = table.iter().find(|m| m.matches(&ids)) {
            found.push(PciDevice {
                address: entry.file_name().to_string_lossy().into_owned(),
                ids,
                path,
                matched: *m,
            });
        }
    }
    found.sort_by_cached_key(|d| address_key(&d.address));
    Ok(found)
}

/// [`scan`], failing with [`DriverError::PciNotFound`] (naming the
/// boards and where it looked) when nothing matches.
pub fn find(sysfs: &Sysfs, table: &[PciMatch]) -> Result<Vec<PciDevice>> {
    let found = scan(sysfs, table)?;
    if found.is_empty() {
        return Err(DriverError::PciNotFound {
            wanted: table
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            searched: sysfs.root().to_path_buf(),
        });
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_entries_match_with_and_without_subsystem() {
        let ids = PciIds {
            vendor: 0x10b5,
            device: 0x9054,
            subvendor: 0x10b5,
            subdevice: 0x3314,
        };
        assert!(PciMatch::new(0x10b5, 0x9054, "plx").matches(&ids));
        assert!(PciMatch::new(0x10b5, 0x9054, "5i22")
            .subsystem(0x10b5, 0x3314)
            .matches(&ids));
        assert!(!PciMatch::new(0x10b5, 0x9054, "5i23")
            .subsystem(0x10b5, 0x3315)
            .matches(&ids));
        assert!(!PciMatch::new(0x10b5, 0x9030, "5i20").matches(&ids));
        assert_eq!(
            PciMatch::new(0x2718, 0x5125, "5i25")
                .subsystem(0x2718, 0x5125)
                .to_string(),
            "5i25 (2718:5125, subsystem 2718:5125)"
        );
        assert_eq!(ids.to_string(), "10b5:9054 (subsystem 10b5:3314)");
    }

    #[test]
    fn addresses_sort_by_number() {
        let mut v = [
            "0000:02:00.0",
            "10000:00:00.0",
            "0000:00:1f.3",
            "0000:00:02.0",
        ];
        v.sort_by_cached_key(|a| address_key(a));
        assert_eq!(
            v,
            [
                "0000:00:02.0",
                "0000:00:1f.3",
                "0000:02:00.0",
                "10000:00:00.0"
            ]
        );
    }
}
