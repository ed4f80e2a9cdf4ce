//! [`MmapWindow`]: a [`RegWindow`] over a memory-mapped file, normally the
//! sysfs `resourceN` file of a PCI memory BAR (what
//! [`PciDevice::map_bar`](crate::pci::PciDevice::map_bar) returns), or a
//! plain file standing in for one (the fake sysfs tree of the tests, the
//! VM rig's ivshmem backing file seen from the host).
//!
//! The mapping is shared and every access is one volatile 32-bit load or
//! store, so each register access reaches the device exactly once and in
//! program order, as the hardware needs.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use memmap2::{MmapOptions, MmapRaw};

use super::{RegWindow, ALL_ONES};
use crate::error::{classify, DriverError, Result};

/// A shared read/write mapping of `len` bytes of a file.
pub struct MmapWindow {
    map: MmapRaw,
    len: usize,
    path: PathBuf,
    errors: AtomicU64,
}

impl std::fmt::Debug for MmapWindow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MmapWindow")
            .field("path", &self.path)
            .field("len", &format_args!("{:#x}", self.len))
            .finish()
    }
}

fn open_rw(path: &Path) -> Result<File> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .map_err(|e| classify("opening", path, e))
}

impl MmapWindow {
    /// Maps the whole file at `path`.
    pub fn open(path: &Path) -> Result<MmapWindow> {
        let file = open_rw(path)?;
        let size = file_size(&file, path)?;
        let len = usize::try_from(size).map_err(|_| DriverError::BadSysfs {
            path: path.to_path_buf(),
            reason: format!("{size:#x} bytes do not fit the address space"),
        })?;
        Self::map_file(&file, path, len)
    }

    /// Maps the first `len` bytes of the file at `path`; the file must be
    /// at least that long (touching a mapping past the end of a file
    /// would kill the process with SIGBUS).
    pub fn open_len(path: &Path, len: usize) -> Result<MmapWindow> {
        let file = open_rw(path)?;
        let size = file_size(&file, path)?;
        if size < len as u64 {
            return Err(DriverError::BadSysfs {
                path: path.to_path_buf(),
                reason: format!("the file is {size:#x} bytes, {len:#x} are needed"),
            });
        }
        Self::map_file(&file, path, len)
    }

    fn map_file(file: &File, path: &Path, len: usize) -> Result<MmapWindow> {
        if len < 4 {
            return Err(DriverError::BadSysfs {
                path: path.to_path_buf(),
                reason: format!("{len} bytes: too small for one 32-bit register"),
            });
        }
        let map = MmapOptions::new()
            .len(len)
            .map_raw(file)
            .map_err(|e| classify("mapping", path, e))?;
        Ok(MmapWindow {
            map,
            len,
            path: path.to_path_buf(),
            errors: AtomicU64::new(0),
        })
    }

    /// The mapped file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether `words` registers from `offset` are inside the window and
    /// aligned; counts an error if not.
    #[inline]
    fn check(&self, offset: usize, words: usize) -> bool {
        let ok = offset % 4 == 0
            && words
                .checked_mul(4)
                .and_then(|b| b.checked_add(offset))
                .is_some_and(|end| end <= self.len);
        if !ok {
            self.errors.fetch_add(1, Relaxed);
        }
        ok
    }

    #[inline]
    fn word_ptr(&self, offset: usize) -> *mut u32 {
        self.map.as_mut_ptr().wrapping_add(offset).cast::<u32>()
    }
}

fn file_size(file: &File, path: &Path) -> Result<u64> {
    file.metadata()
        .map(|m| m.len())
        .map_err(|e| DriverError::Io {
            path: path.to_path_buf(),
            op: "reading the size of",
            source: e,
        })
}

impl RegWindow for MmapWindow {
    fn len(&self) -> usize {
        self.len
    }

    #[inline]
    fn read32(&self, offset: usize) -> u32 {
        if !self.check(offset, 1) {
            return ALL_ONES;
        }
        // SAFETY: `check` put the 4 bytes at `offset` inside the live
        // mapping, and `offset` is 4-aligned from a page-aligned base.
        // Volatile: the device (or the peer process) changes the memory.
        unsafe { self.word_ptr(offset).read_volatile() }
    }

    #[inline]
    fn write32(&self, offset: usize, value: u32) {
        if self.check(offset, 1) {
            // SAFETY: as in `read32`; the mapping is writable and shared.
            unsafe { self.word_ptr(offset).write_volatile(value) }
        }
    }

    fn read_burst(&self, offset: usize, out: &mut [u32]) {
        if !self.check(offset, out.len()) {
            out.fill(ALL_ONES);
            return;
        }
        for (i, v) in out.iter_mut().enumerate() {
            // SAFETY: the whole burst was checked to lie in the mapping.
            *v = unsafe { self.word_ptr(offset + 4 * i).read_volatile() };
        }
    }

    fn write_burst(&self, offset: usize, data: &[u32]) {
        if !self.check(offset, data.len()) {
            return;
        }
        for (i, v) in data.iter().enumerate() {
            // SAFETY: the whole burst was checked to lie in the mapping.
            unsafe { self.word_ptr(offset + 4 * i).write_volatile(*v) }
        }
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        format!("{} ({:#x} bytes mapped)", self.path.display(), self.len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_file(tag: &str, bytes: usize) -> PathBuf {
        let p = std::env::temp_dir().join(format!("hal-driver-mmap-{tag}-{}", std::process::id()));
        std::fs::write(&p, vec![0u8; bytes]).unwrap();
        p
    }

    #[test]
    fn words_reach_the_file_and_bad_offsets_are_counted() {
        let p = temp_file("rw", 64);
        let w = MmapWindow::open(&p).unwrap();
        assert_eq!(w.len(), 64);
        w.write32(8, 0xDEAD_BEEF);
        w.write_burst(16, &[1, 2, 3]);
        let mut b = [0u32; 4];
        w.read_burst(12, &mut b);
        assert_eq!(b, [0, 1, 2, 3]);
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[8..12], &0xDEAD_BEEFu32.to_le_bytes());
        assert_eq!(w.errors(), 0);
        assert_eq!(w.read32(62), ALL_ONES, "misaligned");
        assert_eq!(w.read32(64), ALL_ONES, "past the end");
        assert_eq!(w.read32(usize::MAX - 3), ALL_ONES, "overflowing offset");
        w.write32(3, 7);
        w.read_burst(60, &mut b);
        assert_eq!(b, [ALL_ONES; 4]);
        assert_eq!(w.errors(), 5);
        assert_eq!(&std::fs::read(&p).unwrap()[..8], &[0; 8]);
        let _ = std::fs::remove_file(&p);
    }

    #[test]
    fn a_short_file_is_refused_before_mapping() {
        let p = temp_file("short", 16);
        let e = MmapWindow::open_len(&p, 64).unwrap_err().to_string();
        assert!(e.contains("0x10 bytes, 0x40 are needed"), "{e}");
        let _ = std::fs::remove_file(&p);
        let e = MmapWindow::open(&p).unwrap_err();
        assert!(matches!(e, DriverError::Io { .. }), "{e}");
    }
}
