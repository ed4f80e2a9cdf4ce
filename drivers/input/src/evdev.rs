//! The kernel backend: event nodes under `/dev/input`, opened for reading
//! and writing (LED events are written), non-blocking.

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsFd, AsRawFd, BorrowedFd};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

use crate::device::{human_order, Catalogue, Identity, InputDevice};
use crate::error::{InputError, Result};
use crate::regs::{self, AbsInfo, Event, InputId};

/// Where the kernel's event nodes are.
pub const INPUT_DIR: &str = "/dev/input";
/// The longest name or phys string read.
const STRING_MAX: usize = 1024;
/// Records read at once.
const READ_RECORDS: usize = 64;

/// The event nodes of `/dev/input`.
pub struct Nodes;

impl Catalogue for Nodes {
    fn describe(&self) -> String {
        INPUT_DIR.to_string()
    }

    fn exists(&self, path: &Path) -> bool {
        // A name too long for the kernel is simply not there.
        path.exists()
    }

    fn nodes(&self) -> Vec<PathBuf> {
        let Ok(dir) = std::fs::read_dir(INPUT_DIR) else {
            return Vec::new();
        };
        let mut v: Vec<PathBuf> = dir
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with("event"))
            .map(|e| e.path())
            .collect();
        v.sort_by(|a, b| human_order(a, b));
        v
    }

    fn open(&self, path: &Path) -> Result<Box<dyn InputDevice>> {
        Ok(Box::new(EventNode::open(path)?))
    }
}

/// An open event node.
pub struct EventNode {
    file: File,
    who: Identity,
    buf: Vec<u8>,
}

impl EventNode {
    /// Opens `path` and reads who the device is.
    pub fn open(path: &Path) -> Result<EventNode> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK | libc::O_CLOEXEC)
            .open(path)
            .map_err(|source| InputError::Device {
                op: "opening",
                path: path.to_path_buf(),
                source,
            })?;
        let mut node = EventNode {
            file,
            who: Identity {
                path: path.to_path_buf(),
                ..Identity::default()
            },
            buf: vec![0; READ_RECORDS * regs::EVENT_SIZE],
        };
        node.who.name = node.string(regs::eviocgname(STRING_MAX), "reading the name of")?;
        // Some devices have no phys (LinuxCNC skips it then too).
        node.who.phys = node.string(regs::eviocgphys(STRING_MAX), "").ok();
        let mut id = [0u8; regs::INPUT_ID_SIZE];
        node.ioctl_buf(regs::EVIOCGID, &mut id, "reading the id of")?;
        node.who.id = InputId::from_bytes(&id);
        Ok(node)
    }

    fn err(&self, op: &'static str, source: std::io::Error) -> InputError {
        InputError::Device {
            op,
            path: self.who.path.clone(),
            source,
        }
    }

    /// An ioctl that fills `buf` (its length is encoded in `req`).
    fn ioctl_buf(&self, req: u64, buf: &mut [u8], op: &'static str) -> Result<usize> {
        debug_assert_eq!(((req >> 16) & 0x3fff) as usize, buf.len());
        // SAFETY: every request passed here is a read ioctl whose size
        // field is buf's length (checked above in debug builds, and by
        // construction at each call), so the kernel writes at most
        // buf.len() bytes into buf.
        let r = unsafe { libc::ioctl(self.file.as_raw_fd(), req as _, buf.as_mut_ptr()) };
        if r < 0 {
            return Err(self.err(op, std::io::Error::last_os_error()));
        }
        Ok(usize::try_from(r).unwrap_or(0))
    }

    /// A string ioctl (name, phys): up to its NUL, invalid UTF-8 replaced.
    fn string(&self, req: u64, op: &'static str) -> Result<String> {
        let mut buf = vec![0u8; STRING_MAX];
        self.ioctl_buf(req, &mut buf, op)?;
        let end = buf.iter().position(|b| *b == 0).unwrap_or(buf.len());
        Ok(String::from_utf8_lossy(&buf[..end]).into_owned())
    }

    fn gone(&self, source: Option<std::io::Error>) -> InputError {
        InputError::Gone {
            path: self.who.path.clone(),
            name: self.who.name.clone(),
            source,
        }
    }
}

/// Whether an error means the device was unplugged.
fn is_gone(e: &std::io::Error) -> bool {
    matches!(e.raw_os_error(), Some(libc::ENODEV) | Some(libc::EIO))
}

impl InputDevice for EventNode {
    fn identity(&self) -> &Identity {
        &self.who
    }

    fn codes(&mut self, kind: u16, max: u16) -> Result<Vec<u16>> {
        let mut bits = vec![0u8; regs::bitmap_len(max)];
        self.ioctl_buf(
            regs::eviocgbit(kind, bits.len()),
            &mut bits,
            "reading the capabilities of",
        )?;
        Ok(regs::bits_set(&bits, max))
    }

    fn absinfo(&mut self, code: u16) -> Result<AbsInfo> {
        let mut b = [0u8; regs::ABSINFO_SIZE];
        self.ioctl_buf(regs::eviocgabs(code), &mut b, "reading an axis range of")?;
        Ok(AbsInfo::from_bytes(&b))
    }

    fn keys_held(&mut self) -> Result<Vec<u16>> {
        let mut bits = [0u8; regs::bitmap_len(regs::KEY_MAX)];
        self.ioctl_buf(
            regs::eviocgkey(bits.len()),
            &mut bits,
            "reading the keys held on",
        )?;
        Ok(regs::bits_set(&bits, regs::KEY_MAX))
    }

    fn grab(&mut self) -> Result<()> {
        // SAFETY: EVIOCGRAB takes its argument by value (an int), not
        // through a pointer.
        let r = unsafe {
            libc::ioctl(
                self.file.as_raw_fd(),
                regs::EVIOCGRAB as _,
                1 as libc::c_int,
            )
        };
        if r < 0 {
            return Err(self.err(
                "taking exclusive access to",
                std::io::Error::last_os_error(),
            ));
        }
        Ok(())
    }

    fn read_available(&mut self, out: &mut Vec<Event>) -> Result<()> {
        let mut decoded = Vec::new();
        loop {
            let n = match self.file.read(&mut self.buf) {
                Ok(0) => return Err(self.gone(None)),
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) if is_gone(&e) => return Err(self.gone(Some(e))),
                Err(e) => return Err(self.err("reading", e)),
            };
            regs::parse_events(&self.buf[..n], &mut decoded)?;
            out.append(&mut decoded);
            if n < self.buf.len() {
                return Ok(());
            }
        }
    }

    fn write(&mut self, event: Event) -> Result<()> {
        match self.file.write(&event.to_record()) {
            Ok(_) => Ok(()),
            Err(e) if is_gone(&e) => Err(self.gone(Some(e))),
            Err(e) => Err(self.err("writing an LED event to", e)),
        }
    }

    fn fd(&self) -> Option<BorrowedFd<'_>> {
        Some(self.file.as_fd())
    }
}
