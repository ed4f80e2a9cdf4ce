//! [`DevPortPorts`]: I/O ports through `/dev/port`, where the file offset
//! is the port number.
//!
//! Every access is a `pread`/`pwrite` system call, and the kernel's
//! `/dev/port` moves one byte per `inb`/`outb`: a 16- or 32-bit access
//! becomes 2 or 4 byte accesses at consecutive ports, low byte first.
//! That suits byte-wide devices (a parallel port, 8-bit ISA registers);
//! a device that needs real 16/32-bit bus cycles needs
//! [`IopermPorts`](super::IopermPorts). Opening `/dev/port` needs `CAP_SYS_RAWIO` (no
//! file permission grants it) and kernel lockdown refuses it.

use std::fs::{File, OpenOptions};
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::ranges::{self, PortRange};
use super::{PortBus, ALL_ONES};
use crate::error::{DriverError, Result};

/// The kernel's port device.
pub const DEV_PORT: &str = "/dev/port";

/// I/O ports reached through `/dev/port`, limited to declared ranges.
#[derive(Debug)]
pub struct DevPortPorts {
    file: File,
    path: PathBuf,
    ranges: Box<[PortRange]>,
    errors: AtomicU64,
}

impl DevPortPorts {
    /// Opens `/dev/port` for the port `ranges`.
    pub fn open(ranges: &[PortRange]) -> Result<DevPortPorts> {
        Self::open_at(Path::new(DEV_PORT), ranges)
    }

    /// Opens `path` as the port device (tests give a plain file).
    pub fn open_at(path: &Path, ranges: &[PortRange]) -> Result<DevPortPorts> {
        let what = format!("{} for ports {}", path.display(), ranges::describe(ranges));
        if !cfg!(target_arch = "x86_64") {
            return Err(DriverError::Unsupported {
                what,
                reason: "port I/O is x86 only".into(),
            });
        }
        if ranges.is_empty() {
            return Err(DriverError::Unsupported {
                what,
                reason: "no port range given".into(),
            });
        }
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| match e.raw_os_error() {
                Some(libc::EPERM) if crate::lockdown::active() => DriverError::Lockdown { what },
                Some(libc::EACCES) | Some(libc::EPERM) => DriverError::PortIo {
                    what,
                    source: e,
                    hint: "opening /dev/port needs CAP_SYS_RAWIO: setcap cap_sys_rawio+ep on \
                           the HAL host binary",
                },
                _ => DriverError::Io {
                    path: path.to_path_buf(),
                    op: "opening",
                    source: e,
                },
            })?;
        Ok(DevPortPorts {
            file,
            path: path.to_path_buf(),
            ranges: ranges.into(),
            errors: AtomicU64::new(0),
        })
    }

    /// Reads `N` bytes from `port` (little-endian), or None (counted).
    #[inline]
    fn read<const N: usize>(&self, port: u16) -> Option<[u8; N]> {
        let mut b = [0u8; N];
        let ok = ranges::allowed(&self.ranges, port, N as u16)
            && self.file.read_at(&mut b, port as u64).ok() == Some(N);
        if ok {
            Some(b)
        } else {
            self.errors.fetch_add(1, Relaxed);
            None
        }
    }

    #[inline]
    fn write(&self, port: u16, bytes: &[u8]) {
        let ok = ranges::allowed(&self.ranges, port, bytes.len() as u16)
            && self.file.write_at(bytes, port as u64).ok() == Some(bytes.len());
        if !ok {
            self.errors.fetch_add(1, Relaxed);
        }
    }
}

impl PortBus for DevPortPorts {
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
        format!(
            "{} at {}",
            self.path.display(),
            ranges::describe(&self.ranges)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_port_numbers_and_other_ports_are_refused() {
        // A plain file stands in for /dev/port: the file offset is the port.
        let p = std::env::temp_dir().join(format!("hal-driver-devport-{}", std::process::id()));
        std::fs::write(&p, vec![0u8; 0x400]).unwrap();
        let bus = DevPortPorts::open_at(&p, &[PortRange::new(0x378, 8).unwrap()]).unwrap();
        bus.outb(0x378, 0xA5);
        bus.outw(0x37A, 0x1234);
        bus.outl(0x37C, 0xCAFE_F00D);
        assert_eq!(bus.inb(0x378), 0xA5);
        assert_eq!(bus.inw(0x37A), 0x1234);
        assert_eq!(bus.inl(0x37C), 0xCAFE_F00D);
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(
            &bytes[0x378..0x380],
            &[0xA5, 0, 0x34, 0x12, 0x0D, 0xF0, 0xFE, 0xCA]
        );
        assert_eq!(bus.errors(), 0);
        assert_eq!(bus.inb(0x377), 0xFF);
        assert_eq!(bus.inl(0x37E), u32::MAX, "runs past the range");
        bus.outb(0x380, 1);
        assert_eq!(bus.errors(), 3);
        assert_eq!(std::fs::read(&p).unwrap()[0x380], 0);
        let _ = std::fs::remove_file(&p);
    }

    #[test]
    fn the_real_device_is_refused_clearly_or_opens() {
        match DevPortPorts::open(&[PortRange::new(0x378, 3).unwrap()]) {
            Ok(b) => assert!(b.describe().contains("/dev/port")),
            Err(e) => assert!(e.to_string().contains("/dev/port"), "{e}"),
        }
    }
}
