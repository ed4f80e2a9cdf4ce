//! Finding the pendant (USB 10ce:eb70) among Linux's hidraw devices
//! through sysfs, reading its input reports and writing its display.

use std::fs::File;
use std::io::Read;
use std::os::fd::AsRawFd;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::error::{Result, UsbError};

/// The pendant's USB vendor id.
pub const VENDOR: u32 = 0x10ce;
/// The pendant's USB product id.
pub const PRODUCT: u32 = 0xeb70;
/// hidraw's class directory in sysfs.
pub const SYS_HIDRAW: &str = "/sys/class/hidraw";
/// The largest input report read at once.
pub const READ_MAX: usize = 32;

/// Whether a hidraw device's `uevent` text names the pendant: a line
/// `HID_ID=BUS:VENDOR:PRODUCT` in hex, bus 0003 (USB).
pub fn uevent_is_pendant(uevent: &str) -> bool {
    uevent.lines().any(|l| {
        let Some(id) = l.trim().strip_prefix("HID_ID=") else {
            return false;
        };
        let mut parts = id.split(':').map(|p| u32::from_str_radix(p, 16).ok());
        matches!(
            (parts.next(), parts.next(), parts.next(), parts.next()),
            (Some(Some(3)), Some(Some(VENDOR)), Some(Some(PRODUCT)), None)
        )
    })
}

/// The `/dev` nodes of every pendant under `sys` (a hidraw class
/// directory), in name order. A directory that cannot be read is none.
pub fn find(sys: &Path, dev: &Path) -> Vec<PathBuf> {
    let Ok(dir) = std::fs::read_dir(sys) else {
        return Vec::new();
    };
    let mut names: Vec<String> = dir
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("hidraw"))
        .collect();
    names.sort();
    names
        .into_iter()
        .filter(|n| {
            let uevent = sys.join(n).join("device/uevent");
            // A uevent file is a few hundred bytes; read at most 4 KiB.
            let mut text = String::new();
            File::open(uevent)
                .and_then(|f| f.take(4096).read_to_string(&mut text))
                .is_ok()
                && uevent_is_pendant(&text)
        })
        .map(|n| dev.join(n))
        .collect()
}

/// An open pendant.
pub struct Device {
    file: File,
    path: PathBuf,
}

/// HIDIOCSFEATURE(len): `_IOC(_IOC_READ|_IOC_WRITE, 'H', 0x06, len)`.
fn hidiocsfeature(len: usize) -> libc::c_ulong {
    (3 << 30) | ((len as libc::c_ulong) << 16) | (libc::c_ulong::from(b'H') << 8) | 0x06
}

impl Device {
    /// Opens a hidraw node for reading and writing.
    pub fn open(path: &Path) -> Result<Device> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK | libc::O_CLOEXEC)
            .open(path)
            .map_err(|source| UsbError::Device {
                op: "opening",
                path: path.to_path_buf(),
                source,
            })?;
        Ok(Device {
            file,
            path: path.to_path_buf(),
        })
    }

    /// The node's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn err(&self, op: &'static str, source: std::io::Error) -> UsbError {
        UsbError::Device {
            op,
            path: self.path.clone(),
            source,
        }
    }

    /// Waits up to `timeout` for an input report; its length in `buf`,
    /// or 0 when none came.
    pub fn read(&mut self, buf: &mut [u8; READ_MAX], timeout: Duration) -> Result<usize> {
        use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
        use std::os::fd::AsFd;
        let ms = u16::try_from(timeout.as_millis()).unwrap_or(u16::MAX);
        let mut fds = [PollFd::new(self.file.as_fd(), PollFlags::POLLIN)];
        let n = match poll(&mut fds, PollTimeout::from(ms)) {
            Ok(n) => n,
            Err(nix::errno::Errno::EINTR) => return Ok(0),
            Err(e) => return Err(self.err("waiting on", e.into())),
        };
        if n == 0 {
            return Ok(0);
        }
        let revents = fds[0].revents().unwrap_or(PollFlags::empty());
        if revents.intersects(PollFlags::POLLERR | PollFlags::POLLHUP | PollFlags::POLLNVAL) {
            return Err(self.err(
                "reading",
                std::io::Error::new(std::io::ErrorKind::BrokenPipe, "device went away"),
            ));
        }
        match self.file.read(buf) {
            Ok(n) => Ok(n),
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => Ok(0),
            Err(e) => Err(self.err("reading", e)),
        }
    }

    /// Sends one feature report (its id in byte 0).
    pub fn send_feature(&mut self, report: &[u8; super::report::DISPLAY_REPORT_LEN]) -> Result<()> {
        let mut buf = *report;
        // SAFETY: HIDIOCSFEATURE reads (and may write back) exactly the
        // buffer length encoded in the request, which is buf's length.
        let r = unsafe {
            libc::ioctl(
                self.file.as_raw_fd(),
                hidiocsfeature(buf.len()) as _,
                buf.as_mut_ptr(),
            )
        };
        if r < 0 {
            return Err(self.err("writing the display to", std::io::Error::last_os_error()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_the_pendant_uevent() {
        let u = "DRIVER=hid-generic\nHID_ID=0003:000010CE:0000EB70\nHID_NAME=KTURT.LTD\n";
        assert!(uevent_is_pendant(u));
        assert!(!uevent_is_pendant("HID_ID=0003:000010CE:0000EB71\n"));
        assert!(
            !uevent_is_pendant("HID_ID=0005:000010CE:0000EB70\n"),
            "bluetooth"
        );
        assert!(!uevent_is_pendant("HID_ID=0003:zz:0000EB70\n"));
        assert!(!uevent_is_pendant(""));
    }

    #[test]
    fn finds_pendants_in_a_sysfs_tree() {
        let root = std::env::temp_dir().join(format!("xhc-sys-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        for (n, id) in [
            ("hidraw1", "0003:000010CE:0000EB70"),
            ("hidraw0", "0003:0000046D:0000C52B"),
        ] {
            let d = root.join(n).join("device");
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(d.join("uevent"), format!("HID_ID={id}\n")).unwrap();
        }
        let found = find(&root, Path::new("/dev"));
        assert_eq!(found, vec![PathBuf::from("/dev/hidraw1")]);
        assert!(find(&root.join("none"), Path::new("/dev")).is_empty());
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn feature_request_code() {
        // HIDIOCSFEATURE(8) as Linux's headers compute it.
        assert_eq!(hidiocsfeature(8), 0xC008_4806);
    }
}
