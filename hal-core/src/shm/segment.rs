//! Creating, attaching and addressing the segment.

use std::fs::{File, OpenOptions};
use std::mem::size_of;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::*};

use memmap2::{MmapOptions, MmapRaw};

use super::layout::*;
use crate::error::{HalError, Result};
use crate::handles::Cells;
use crate::paths;

/// A mapped segment. Shared between threads of one process; each process
/// maps it at its own address, so nothing in it is a pointer.
pub(crate) struct Segment {
    map: MmapRaw,
    /// The open segment file. Kept for the mapping's whole life: the
    /// byte-range locks that mark a live user-space component's owner
    /// (see `objects::owner`) belong to this open file description.
    file: File,
    size: u64,
    /// Journal offset, checked once and never reread from the segment.
    journal_off: u64,
    /// Where value cells may lie, for every handle on this mapping.
    cells: Cells,
    instance: String,
    path: PathBuf,
}

// SAFETY: the mapping is shared memory that every process and thread accesses
// only through atomic words (see layout.rs) and the robust mutex.
unsafe impl Send for Segment {}
// SAFETY: as above.
unsafe impl Sync for Segment {}

const HEADER_SIZE: u64 = (size_of::<Header>() as u64 + 63) & !63;

impl Segment {
    /// Creates and initialises a fresh segment of `size` bytes, all pages
    /// allocated up front. Fails if the file exists.
    pub(crate) fn create(instance: &str, size: u64) -> Result<Segment> {
        let path = paths::segment(instance);
        let min = HEADER_SIZE + (JOURNAL_CAP as u64) * 16 + 64 * 1024;
        if size < min {
            return Err(HalError::BadValue {
                what: "segment size".into(),
                reason: format!("{size} bytes is below the minimum of {min}"),
            });
        }
        // Exclusive and without following links: a file planted at the
        // name (by a squatter) makes this fail instead of being used.
        let file = paths::create_new(&path)
            .map_err(|e| HalError::io("creating shared memory segment", &path, e))?;
        let seg = paths::share_fd(&file, &paths::HalGroup::lookup(), &path)
            .and_then(|()| Self::init_file(instance, &path, file, size));
        if seg.is_err() {
            let _ = std::fs::remove_file(&path);
        }
        seg
    }

    fn init_file(instance: &str, path: &Path, file: File, size: u64) -> Result<Segment> {
        nix::fcntl::posix_fallocate(&file, 0, size as i64).map_err(|e| {
            HalError::io(
                "allocating shared memory (is /dev/shm full?)",
                path,
                e.into(),
            )
        })?;
        let map = MmapOptions::new()
            .len(size as usize)
            .map_raw(&file)
            .map_err(|e| HalError::io("mapping shared memory segment", path, e))?;
        let mut seg = Segment {
            map,
            file,
            size,
            journal_off: HEADER_SIZE,
            cells: Cells::EMPTY,
            instance: instance.to_string(),
            path: path.to_path_buf(),
        };
        seg.cells = Cells::new(&seg);
        let h = seg.header();
        h.version.store(LAYOUT_VERSION, Relaxed);
        h.size.store(size, Relaxed);
        h.host_pid.store(std::process::id() as u64, Relaxed);
        h.mutex.init().map_err(|source| HalError::Os {
            op: "initialising the HAL lock",
            source,
        })?;
        h.journal_off.store(HEADER_SIZE, Relaxed);
        h.alloc_top
            .store(HEADER_SIZE + JOURNAL_CAP as u64 * 16, Relaxed);
        h.next_comp_id.store(1, Relaxed);
        h.next_funct_id.store(1, Relaxed);
        h.magic.store(MAGIC, Release);
        Ok(seg)
    }

    /// Maps an existing segment and checks its header.
    pub(crate) fn attach(instance: &str) -> Result<Segment> {
        let path = paths::segment(instance);
        let not_running = || HalError::NotRunning {
            instance: instance.to_string(),
        };
        let file = match OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NOFOLLOW)
            .open(&path)
        {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(not_running()),
            Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
                return Err(paths::denied("opening shared memory segment", &path))
            }
            Err(e) => return Err(paths::open_error("opening shared memory segment", &path, e)),
        };
        let len = file
            .metadata()
            .map_err(|e| HalError::io("reading shared memory segment size", &path, e))?
            .len();
        let bad = |reason: String| HalError::BadSegment {
            instance: instance.to_string(),
            reason,
        };
        if len < HEADER_SIZE {
            return Err(bad(format!("file is only {len} bytes")));
        }
        let map = MmapOptions::new()
            .len(len as usize)
            .map_raw(&file)
            .map_err(|e| HalError::io("mapping shared memory segment", &path, e))?;
        let mut seg = Segment {
            map,
            file,
            size: len,
            journal_off: 0,
            cells: Cells::EMPTY,
            instance: instance.to_string(),
            path,
        };
        let h = seg.header();
        match h.magic.load(Acquire) {
            0 => return Err(not_running()),
            MAGIC => {}
            m => return Err(bad(format!("wrong magic number {m:#x}"))),
        }
        let version = h.version.load(Relaxed);
        if version != LAYOUT_VERSION {
            return Err(bad(format!(
                "layout version {version}, this program understands {LAYOUT_VERSION}"
            )));
        }
        if h.size.load(Relaxed) != len {
            return Err(bad(format!(
                "header says {} bytes, file has {len}",
                h.size.load(Relaxed)
            )));
        }
        let jo = h.journal_off.load(Relaxed);
        if jo < HEADER_SIZE
            || jo % 8 != 0
            || jo
                .checked_add(JOURNAL_CAP as u64 * 16)
                .is_none_or(|end| end > len)
        {
            return Err(bad(format!("journal offset {jo:#x} out of range")));
        }
        seg.journal_off = jo;
        seg.cells = Cells::new(&seg);
        Ok(seg)
    }

    /// Size of the mapping in bytes.
    pub(crate) fn size(&self) -> u64 {
        self.size
    }

    pub(crate) fn instance(&self) -> &str {
        &self.instance
    }

    pub(crate) fn base(&self) -> *mut u8 {
        self.map.as_mut_ptr()
    }

    pub(crate) fn header(&self) -> &Header {
        // SAFETY: the mapping is at least HEADER_SIZE bytes (checked at create
        // and attach), page aligned, and Header consists of atomics and the
        // pthread mutex, for which any bit pattern is a valid Rust value.
        unsafe { &*(self.base() as *const Header) }
    }

    fn check_range(&self, off: u64, len: u64) -> Result<()> {
        if off == 0 || off % 8 != 0 || off.checked_add(len).is_none_or(|end| end > self.size) {
            return Err(HalError::BadOffset {
                offset: off,
                size: self.size,
            });
        }
        Ok(())
    }

    /// The record of type `T` at `off`, after checking bounds, alignment and tag.
    pub(crate) fn rec<T: Record>(&self, off: u64) -> Result<&T> {
        self.check_range(off, size_of::<T>() as u64)?;
        // SAFETY: the range lies inside the mapping and is 8-byte aligned;
        // every record type is repr(C) and made only of AtomicU64 words (or
        // arrays of them), for which every bit pattern is valid.
        let r = unsafe { &*(self.base().add(off as usize) as *const T) };
        // The tag is the first word of every record.
        // SAFETY: same range as above; the first word is an AtomicU64.
        let tag = unsafe { &*(self.base().add(off as usize) as *const AtomicU64) }.load(Acquire);
        if tag != T::TAG {
            return Err(HalError::BadSegment {
                instance: self.instance.clone(),
                reason: format!(
                    "record at {off:#x} has tag {tag:#x}, expected {:#x}",
                    T::TAG
                ),
            });
        }
        Ok(r)
    }

    /// The [`Pair`] at `off`, after checking bounds and alignment.
    pub(crate) fn pair(&self, off: u64) -> Result<&Pair> {
        self.check_range(off, 16)?;
        if off % 16 != 0 {
            return Err(HalError::BadOffset {
                offset: off,
                size: self.size,
            });
        }
        // SAFETY: inside the mapping and aligned; a Pair is two atomic
        // words, for which any bits are valid.
        Ok(unsafe { &*(self.base().add(off as usize) as *const Pair) })
    }

    /// A run of `count` words at `off`, after a bounds check.
    pub(crate) fn words(&self, off: u64, count: u64) -> Result<&[AtomicU64]> {
        self.check_range(off, count.saturating_mul(8))?;
        // SAFETY: bounds and alignment checked; AtomicU64 accepts any bits.
        Ok(unsafe {
            std::slice::from_raw_parts(
                self.base().add(off as usize) as *const AtomicU64,
                count as usize,
            )
        })
    }

    /// The word at `off` (bounds-checked).
    pub(crate) fn word(&self, off: u64) -> Result<&AtomicU64> {
        Ok(&self.words(off, 1)?[0])
    }

    /// Offset of a reference into this segment.
    pub(crate) fn offset_of<T>(&self, r: &T) -> u64 {
        (r as *const T as usize - self.base() as usize) as u64
    }

    /// Where value cells may lie in this mapping.
    #[inline(always)]
    pub(crate) fn cells(&self) -> &Cells {
        &self.cells
    }

    /// Largest offset a value cell may start at; used to clamp offsets on
    /// the realtime path instead of branching.
    pub(crate) fn cell_limit(&self) -> u64 {
        (self.size - 8) & !7
    }

    /// Smallest offset a value cell may start at: past the header and the
    /// journal, so a corrupted slot can never aim a pin write at the lock.
    pub(crate) fn cell_floor(&self) -> u64 {
        self.journal_off + JOURNAL_CAP as u64 * 16
    }

    /// Journal entry `i` as (offset word, old value word).
    pub(crate) fn journal_entry(&self, i: usize) -> (&AtomicU64, &AtomicU64) {
        let i = i.min(JOURNAL_CAP - 1) as u64;
        let base = self.journal_off + i * 16;
        // SAFETY: journal_off was checked at create/attach so that all
        // JOURNAL_CAP entries lie inside the mapping, and i is clamped.
        unsafe {
            let p = self.base().add(base as usize) as *const AtomicU64;
            (&*p, &*p.add(1))
        }
    }

    /// The open segment file.
    pub(crate) fn file(&self) -> &File {
        &self.file
    }

    /// Where the segment file lives.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Removes the segment file (the host does this on exit).
    pub(crate) fn unlink(&self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
