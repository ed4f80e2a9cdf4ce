//! The ppdev backend: `/dev/parportN` through the ppdev ioctls.
//!
//! The ioctls are behind [`PpIoctl`] so tests can record the sequence a
//! driver issues (`RecordingIoctl`, feature `testing`) without a device. [`DevParport`] is
//! the real implementation (nix's ioctl wrappers on the open device node).
//!
//! Two kernel behaviours shape this backend (hardware.md 1.2):
//! * `PPRCONTROL` returns the kernel's cached copy of the control lines,
//!   not live levels, so control lines cannot be inputs (`x` mode).
//! * The direction bit (control bit 5) belongs to `PPDATADIR`; parport_pc
//!   ignores the upper control bits of `PPWCONTROL`. This backend therefore
//!   sends bits 0..3 with `PPWCONTROL`, turns changes of bit 5 into
//!   `PPDATADIR`, and merges its own copy of bit 5 into control reads.

use std::fs::{File, OpenOptions};
use std::os::fd::AsRawFd;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

use super::{PortError, PortIo};
use crate::regs;

#[cfg(any(test, feature = "testing"))]
mod recording;
#[cfg(any(test, feature = "testing"))]
pub use recording::{Ioctl, RecordingIoctl};

/// `PARPORT_MODE_PCSPP`: the port is a PC-style SPP port.
pub const MODE_PCSPP: u32 = 0x01;
/// `PARPORT_MODE_TRISTATE`: the data lines can be inputs.
pub const MODE_TRISTATE: u32 = 0x02;

/// The ppdev ioctls this backend uses, one method each.
pub trait PpIoctl: Send + Sync {
    /// `PPCLAIM`.
    fn claim(&self) -> std::io::Result<()>;
    /// `PPRELEASE`.
    fn release(&self) -> std::io::Result<()>;
    /// `PPGETMODES`: the port's `PARPORT_MODE_*` capability bits.
    fn get_modes(&self) -> std::io::Result<u32>;
    /// `PPRDATA`.
    fn read_data(&self) -> std::io::Result<u8>;
    /// `PPWDATA`.
    fn write_data(&self, v: u8) -> std::io::Result<()>;
    /// `PPRSTATUS`.
    fn read_status(&self) -> std::io::Result<u8>;
    /// `PPRCONTROL`.
    fn read_control(&self) -> std::io::Result<u8>;
    /// `PPWCONTROL`.
    fn write_control(&self, v: u8) -> std::io::Result<()>;
    /// `PPDATADIR` (non-zero = data lines are inputs).
    fn data_dir(&self, input: bool) -> std::io::Result<()>;
}

mod sys {
    nix::ioctl_read!(pprstatus, b'p', 0x81, u8);
    nix::ioctl_read!(pprcontrol, b'p', 0x83, u8);
    nix::ioctl_write_ptr!(ppwcontrol, b'p', 0x84, u8);
    nix::ioctl_read!(pprdata, b'p', 0x85, u8);
    nix::ioctl_write_ptr!(ppwdata, b'p', 0x86, u8);
    nix::ioctl_none!(ppclaim, b'p', 0x8b);
    nix::ioctl_none!(pprelease, b'p', 0x8c);
    nix::ioctl_write_ptr!(ppdatadir, b'p', 0x90, libc::c_int);
    nix::ioctl_read!(ppgetmodes, b'p', 0x97, libc::c_uint);
}

/// An open `/dev/parportN`.
#[derive(Debug)]
pub struct DevParport {
    file: File,
}

impl DevParport {
    /// Opens the device node read-write.
    pub fn open(path: &str) -> Result<DevParport, PortError> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|source| match source.kind() {
                std::io::ErrorKind::NotFound => PortError::NoDevice { path: path.into() },
                kind => PortError::Open {
                    path: path.into(),
                    hint: if kind == std::io::ErrorKind::PermissionDenied {
                        " (add the user to group lp, or install the udev rule KERNEL==\"parport[0-9]*\", GROUP=\"lp\", MODE=\"0660\")"
                    } else {
                        ""
                    },
                    source,
                },
            })?;
        Ok(DevParport { file })
    }
}

fn io(r: nix::Result<libc::c_int>) -> std::io::Result<()> {
    r.map(|_| ()).map_err(std::io::Error::from)
}

impl PpIoctl for DevParport {
    fn claim(&self) -> std::io::Result<()> {
        // SAFETY: PPCLAIM takes no argument; the fd is open.
        io(unsafe { sys::ppclaim(self.file.as_raw_fd()) })
    }
    fn release(&self) -> std::io::Result<()> {
        // SAFETY: PPRELEASE takes no argument; the fd is open.
        io(unsafe { sys::pprelease(self.file.as_raw_fd()) })
    }
    fn get_modes(&self) -> std::io::Result<u32> {
        let mut m: libc::c_uint = 0;
        // SAFETY: the kernel writes one unsigned int into `m`.
        io(unsafe { sys::ppgetmodes(self.file.as_raw_fd(), &mut m) })?;
        Ok(m)
    }
    fn read_data(&self) -> std::io::Result<u8> {
        let mut v = 0u8;
        // SAFETY: the kernel writes one byte into `v`.
        io(unsafe { sys::pprdata(self.file.as_raw_fd(), &mut v) })?;
        Ok(v)
    }
    fn write_data(&self, v: u8) -> std::io::Result<()> {
        // SAFETY: the kernel reads one byte from `v`.
        io(unsafe { sys::ppwdata(self.file.as_raw_fd(), &v) })
    }
    fn read_status(&self) -> std::io::Result<u8> {
        let mut v = 0u8;
        // SAFETY: the kernel writes one byte into `v`.
        io(unsafe { sys::pprstatus(self.file.as_raw_fd(), &mut v) })?;
        Ok(v)
    }
    fn read_control(&self) -> std::io::Result<u8> {
        let mut v = 0u8;
        // SAFETY: the kernel writes one byte into `v`.
        io(unsafe { sys::pprcontrol(self.file.as_raw_fd(), &mut v) })?;
        Ok(v)
    }
    fn write_control(&self, v: u8) -> std::io::Result<()> {
        // SAFETY: the kernel reads one byte from `v`.
        io(unsafe { sys::ppwcontrol(self.file.as_raw_fd(), &v) })
    }
    fn data_dir(&self, input: bool) -> std::io::Result<()> {
        let d: libc::c_int = input as libc::c_int;
        // SAFETY: the kernel reads one int from `d`.
        io(unsafe { sys::ppdatadir(self.file.as_raw_fd(), &d) })
    }
}

impl<T: PpIoctl + ?Sized> PpIoctl for std::sync::Arc<T> {
    fn claim(&self) -> std::io::Result<()> {
        (**self).claim()
    }
    fn release(&self) -> std::io::Result<()> {
        (**self).release()
    }
    fn get_modes(&self) -> std::io::Result<u32> {
        (**self).get_modes()
    }
    fn read_data(&self) -> std::io::Result<u8> {
        (**self).read_data()
    }
    fn write_data(&self, v: u8) -> std::io::Result<()> {
        (**self).write_data(v)
    }
    fn read_status(&self) -> std::io::Result<u8> {
        (**self).read_status()
    }
    fn read_control(&self) -> std::io::Result<u8> {
        (**self).read_control()
    }
    fn write_control(&self, v: u8) -> std::io::Result<()> {
        (**self).write_control(v)
    }
    fn data_dir(&self, input: bool) -> std::io::Result<()> {
        (**self).data_dir(input)
    }
}

/// A parallel port reached through ppdev.
#[derive(Debug)]
pub struct PpdevPort<I: PpIoctl = DevParport> {
    dev: I,
    path: String,
    base: Option<u16>,
    claimed: AtomicBool,
    modes: AtomicU64,
    dir_input: AtomicBool,
    errors: AtomicU64,
}

impl PpdevPort<DevParport> {
    /// Opens `path` (e.g. `/dev/parport0`); `base` is the I/O address from
    /// /proc, if known (for messages only). A missing node is
    /// [`PortError::NoDevice`].
    pub fn open(path: &str, base: Option<u16>) -> Result<Self, PortError> {
        Ok(PpdevPort::with_ioctl(DevParport::open(path)?, path, base))
    }
}

impl<I: PpIoctl> PpdevPort<I> {
    /// A port on an already-open ioctl target (a test's recorder).
    pub fn with_ioctl(dev: I, path: &str, base: Option<u16>) -> Self {
        PpdevPort {
            dev,
            path: path.to_string(),
            base,
            claimed: AtomicBool::new(false),
            modes: AtomicU64::new(0),
            dir_input: AtomicBool::new(false),
            errors: AtomicU64::new(0),
        }
    }

    /// The `PARPORT_MODE_*` bits `PPGETMODES` reported at claim.
    pub fn modes(&self) -> u32 {
        self.modes.load(Relaxed) as u32
    }

    /// The device node's path.
    pub fn path(&self) -> &str {
        &self.path
    }

    #[inline]
    fn byte(&self, r: std::io::Result<u8>) -> u8 {
        r.unwrap_or_else(|_| {
            self.errors.fetch_add(1, Relaxed);
            0xFF
        })
    }

    #[inline]
    fn done(&self, r: std::io::Result<()>) {
        if r.is_err() {
            self.errors.fetch_add(1, Relaxed);
        }
    }
}

impl<I: PpIoctl> PortIo for PpdevPort<I> {
    #[inline]
    fn read_data(&self) -> u8 {
        self.byte(self.dev.read_data())
    }
    #[inline]
    fn write_data(&self, v: u8) {
        self.done(self.dev.write_data(v))
    }
    #[inline]
    fn read_status(&self) -> u8 {
        self.byte(self.dev.read_status())
    }
    #[inline]
    fn read_control(&self) -> u8 {
        let v = self.byte(self.dev.read_control()) & regs::CONTROL_LINES;
        if self.dir_input.load(Relaxed) {
            v | regs::CONTROL_DIR_IN
        } else {
            v
        }
    }
    #[inline]
    fn write_control(&self, v: u8) {
        let input = v & regs::CONTROL_DIR_IN != 0;
        if input != self.dir_input.load(Relaxed) {
            self.done(self.dev.data_dir(input));
            self.dir_input.store(input, Relaxed);
        }
        self.done(self.dev.write_control(v & regs::CONTROL_LINES))
    }
    fn has_ecr(&self) -> bool {
        false
    }
    fn write_ecr(&self, _v: u8) -> Result<(), PortError> {
        Err(PortError::Unsupported(format!(
            "{}: ppdev cannot write the ECR (EPP mode needs raw port I/O)",
            self.path
        )))
    }
    fn claim(&self) -> Result<(), PortError> {
        if self.claimed.load(Relaxed) {
            return Ok(());
        }
        self.dev.claim().map_err(|source| PortError::Ioctl {
            op: "PPCLAIM",
            path: self.path.clone(),
            source,
        })?;
        self.claimed.store(true, Relaxed);
        match self.dev.get_modes() {
            Ok(m) => self.modes.store(m as u64, Relaxed),
            Err(source) => {
                self.release();
                return Err(PortError::Ioctl {
                    op: "PPGETMODES",
                    path: self.path.clone(),
                    source,
                });
            }
        }
        Ok(())
    }
    fn release(&self) {
        if self.claimed.swap(false, Relaxed) {
            let _ = self.dev.release();
        }
    }
    fn describe(&self) -> String {
        match self.base {
            Some(b) => format!("ppdev {} (base {b:#x})", self.path),
            None => format!("ppdev {}", self.path),
        }
    }
    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }
}

impl<I: PpIoctl> Drop for PpdevPort<I> {
    fn drop(&mut self) {
        self.release();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn claim_reads_modes_and_drop_releases() {
        let rec = Arc::new(RecordingIoctl::new(MODE_PCSPP | MODE_TRISTATE));
        let p = PpdevPort::with_ioctl(rec.clone(), "/dev/parport9", Some(0x378));
        p.claim().unwrap();
        p.claim().unwrap();
        assert_eq!(p.modes(), MODE_PCSPP | MODE_TRISTATE);
        assert_eq!(p.describe(), "ppdev /dev/parport9 (base 0x378)");
        drop(p);
        assert_eq!(
            rec.calls(),
            vec![Ioctl::Claim, Ioctl::GetModes, Ioctl::Release]
        );
    }

    #[test]
    fn direction_bit_goes_through_ppdatadir() {
        let rec = Arc::new(RecordingIoctl::new(MODE_PCSPP | MODE_TRISTATE));
        let p = PpdevPort::with_ioctl(rec.clone(), "/dev/parport0", None);
        p.claim().unwrap();
        rec.clear();
        p.write_control(0x2B);
        p.write_control(0x24);
        assert_eq!(p.read_control(), 0x24);
        p.write_control(0x04);
        assert_eq!(
            rec.calls(),
            vec![
                Ioctl::DataDir(true),
                Ioctl::WriteControl(0x0B),
                Ioctl::WriteControl(0x04),
                Ioctl::ReadControl,
                Ioctl::DataDir(false),
                Ioctl::WriteControl(0x04),
            ]
        );
    }

    #[test]
    fn failed_claim_is_a_clear_error() {
        let p = PpdevPort::with_ioctl(RecordingIoctl::unregistered(), "/dev/parport1", None);
        let e = p.claim().unwrap_err().to_string();
        assert!(e.contains("PPCLAIM on /dev/parport1 failed"), "{e}");
        assert!(p.write_ecr(0x94).is_err());
        assert!(!p.has_ecr());
    }

    #[test]
    fn the_fake_shares_one_port_between_handles_as_ppdev_does() {
        let first = RecordingIoctl::new(MODE_PCSPP);
        let second = first.open_again();
        // Registers need the claim.
        assert_eq!(
            second.read_status().unwrap_err().raw_os_error(),
            Some(libc::EINVAL)
        );
        first.claim().unwrap();
        assert_eq!(
            first.claim().unwrap_err().raw_os_error(),
            Some(libc::EINVAL),
            "already claimed by this handle"
        );
        first.write_data(0x5A).unwrap();
        // The second handle would block in PPCLAIM: the fake says so.
        assert_eq!(
            second.claim().unwrap_err().raw_os_error(),
            Some(libc::EDEADLK),
            "a claim that would block"
        );
        // Closing the first handle releases the port.
        drop(first);
        second.claim().unwrap();
        assert_eq!(
            second.read_data().unwrap(),
            0x5A,
            "the registers are shared"
        );
    }

    #[test]
    fn missing_node_is_named() {
        let e = DevParport::open("/dev/parport-does-not-exist").unwrap_err();
        assert!(e
            .to_string()
            .contains("/dev/parport-does-not-exist does not exist"));
    }
}
