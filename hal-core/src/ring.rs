//! A single-producer single-consumer ring of fixed-size records in a named
//! region, for realtime-to-user-space streams (sampler, streamer, scope).
//!
//! A ring of depth D holds at most D-1 records (one slot always stays
//! empty), as LinuxCNC's FIFOs do. Indices grow without wrapping; the slot
//! is the index modulo D. The producer owns the head, the consumer the tail;
//! neither ever blocks. Layout in the region, in words: head at 0, tail at 8
//! (own cache lines), depth at 16, record width at 17, column count at 18
//! and column types at 19 (see below), records from 24.
//!
//! A *typed* ring (a HAL stream, as sampler and streamer use) records the
//! [`HalType`] of each column, so that a process attaching by name knows how
//! to read it: each record is a sample number followed by one word per
//! column. The column count is 0 for an untyped ring; the types are packed
//! three bits each, first column lowest.

use std::ptr::NonNull;
use std::sync::atomic::{AtomicU64, Ordering::*};

use crate::error::{HalError, Result};
use crate::objects::{Component, Instance, Region};
use crate::types::HalType;

const HEAD: usize = 0;
const TAIL: usize = 8;
const DEPTH: usize = 16;
const WIDTH: usize = 17;
const COLUMNS: usize = 18;
const TYPES: usize = 19;
const DATA: usize = 24;

/// Most columns a typed ring can describe (three bits each in one word).
pub const MAX_TYPED_COLUMNS: usize = 21;

struct Ring {
    /// Keeps the mapping `words` points into alive.
    region: Region,
    /// The region's first word: at least `DATA + depth * width` words
    /// (checked when the ring is made or opened), so that the realtime
    /// path reaches a word without building and checking a slice.
    words: NonNull<AtomicU64>,
    depth: u64,
    width: usize,
    /// The index this end expects to use next and the record position it
    /// stands for (index modulo depth), carried from one call to the next
    /// so that a call needs no division; recomputed when the index is not
    /// the expected one (another handle on the same end moved it).
    cursor: (u64, u64),
}

// SAFETY: `words` points into the shared mapping that `region` keeps alive,
// and every access through it is atomic; the ring is as shareable as the
// region (a `Send + Sync` handle on the segment).
unsafe impl Send for Ring {}
// SAFETY: as above; the cursor is only changed through `&mut`.
unsafe impl Sync for Ring {}

impl Ring {
    fn create(comp: &Component, name: &str, depth: usize, width: usize) -> Result<Ring> {
        if depth < 2 || width == 0 {
            return Err(HalError::BadValue {
                what: format!("ring '{name}'"),
                reason: format!("depth {depth} and record width {width}: depth must be at least 2 and width at least 1"),
            });
        }
        let words = depth
            .checked_mul(width)
            .and_then(|n| n.checked_add(DATA))
            .ok_or_else(|| HalError::BadValue {
                what: format!("ring '{name}'"),
                reason: "too large".into(),
            })?;
        let region = comp.region(name, words * 8)?;
        let w = region.words();
        w[DEPTH].store(depth as u64, Relaxed);
        w[WIDTH].store(width as u64, Release);
        Ok(Ring::over(region, depth as u64, width))
    }

    /// A ring over `region`, whose words (checked by the caller) hold
    /// the header and `depth` records of `width` words.
    fn over(region: Region, depth: u64, width: usize) -> Ring {
        let words = NonNull::from(region.words()).cast::<AtomicU64>();
        Ring {
            region,
            words,
            depth,
            width,
            cursor: (0, 0),
        }
    }

    fn open(inst: &Instance, name: &str) -> Result<Ring> {
        let region = inst.region(name)?;
        let w = region.words();
        let bad = |reason: String| HalError::BadValue {
            what: format!("ring '{name}'"),
            reason,
        };
        if w.len() < DATA {
            return Err(bad("region too small".into()));
        }
        let depth = w[DEPTH].load(Relaxed);
        let width = w[WIDTH].load(Acquire);
        let fits = depth
            .checked_mul(width)
            .and_then(|n| n.checked_add(DATA as u64))
            .is_some_and(|n| n <= w.len() as u64);
        if depth < 2 || width == 0 || !fits {
            return Err(bad(format!(
                "header says depth {depth}, width {width}, which does not fit its {} words",
                w.len()
            )));
        }
        Ok(Ring::over(region, depth, width as usize))
    }

    fn create_typed(comp: &Component, name: &str, depth: usize, types: &[HalType]) -> Result<Ring> {
        if types.is_empty() || types.len() > MAX_TYPED_COLUMNS {
            return Err(HalError::BadValue {
                what: format!("ring '{name}'"),
                reason: format!(
                    "{} columns: a typed ring has 1 to {MAX_TYPED_COLUMNS}",
                    types.len()
                ),
            });
        }
        let ring = Ring::create(comp, name, depth, types.len() + 1)?;
        let packed = types
            .iter()
            .enumerate()
            .fold(0u64, |acc, (i, t)| acc | (t.code() as u64) << (3 * i));
        let w = ring.region.words();
        w[TYPES].store(packed, Relaxed);
        w[COLUMNS].store(types.len() as u64, Release);
        Ok(ring)
    }

    fn column_types(&self) -> Option<Vec<HalType>> {
        let n = self.word(COLUMNS).load(Acquire) as usize;
        if n == 0 || n > MAX_TYPED_COLUMNS || n + 1 != self.width {
            return None;
        }
        let packed = self.word(TYPES).load(Relaxed);
        (0..n)
            .map(|i| HalType::from_code(((packed >> (3 * i)) & 7) as u32))
            .collect()
    }

    /// Header word `i` (one of the constants above).
    #[inline(always)]
    fn word(&self, i: usize) -> &AtomicU64 {
        debug_assert!(i < DATA);
        // SAFETY: the region holds at least DATA words (see `words`), and
        // the mapping lives as long as `self.region`.
        unsafe { &*self.words.as_ptr().add(i) }
    }

    /// The words of the record at `index`.
    #[inline(always)]
    fn slot(&mut self, index: u64) -> &[AtomicU64] {
        let pos = if index == self.cursor.0 {
            self.cursor.1
        } else {
            index % self.depth
        };
        let next = pos + 1;
        self.cursor = (
            index.wrapping_add(1),
            if next == self.depth { 0 } else { next },
        );
        // SAFETY: pos < depth, so the record's words lie within the
        // DATA + depth * width words of the region (see `words`).
        unsafe {
            std::slice::from_raw_parts(
                self.words.as_ptr().add(DATA + pos as usize * self.width),
                self.width,
            )
        }
    }

    #[inline(always)]
    fn len(&self) -> usize {
        let h = self.word(HEAD).load(Acquire);
        let t = self.word(TAIL).load(Acquire);
        h.wrapping_sub(t).min(self.depth - 1) as usize
    }
}

/// The producing end of a ring.
pub struct RingWriter(Ring);
/// The consuming end of a ring.
pub struct RingReader(Ring);

macro_rules! ring_end {
    ($t:ident) => {
        impl $t {
            /// Creates the ring as a region owned by `comp`.
            pub fn create(comp: &Component, name: &str, depth: usize, width: usize) -> Result<$t> {
                Ring::create(comp, name, depth, width).map($t)
            }

            /// Creates a typed ring (a HAL stream) as a region owned by
            /// `comp`: records are a sample number and one word per column.
            pub fn create_typed(
                comp: &Component,
                name: &str,
                depth: usize,
                types: &[HalType],
            ) -> Result<$t> {
                Ring::create_typed(comp, name, depth, types).map($t)
            }

            /// Opens a ring another component created.
            pub fn open(inst: &Instance, name: &str) -> Result<$t> {
                Ring::open(inst, name).map($t)
            }

            /// The column types of a typed ring; `None` for an untyped one
            /// (or one whose header does not describe its width).
            pub fn column_types(&self) -> Option<Vec<HalType>> {
                self.0.column_types()
            }

            /// The depth the ring was created with (one more than its
            /// capacity).
            #[inline]
            pub fn depth(&self) -> usize {
                self.0.depth as usize
            }

            /// Records waiting in the ring.
            #[inline]
            pub fn len(&self) -> usize {
                self.0.len()
            }

            /// Whether the ring holds no record.
            #[inline]
            pub fn is_empty(&self) -> bool {
                self.len() == 0
            }

            /// Most records the ring can hold (depth - 1).
            #[inline]
            pub fn capacity(&self) -> usize {
                self.0.depth as usize - 1
            }

            /// Words per record.
            #[inline]
            pub fn width(&self) -> usize {
                self.0.width
            }
        }
    };
}
ring_end!(RingWriter);
ring_end!(RingReader);

impl RingWriter {
    /// Appends a record of [`width`](Self::width) words; false if full.
    /// Extra words are ignored and missing ones written as zero.
    #[inline]
    pub fn push(&mut self, record: &[u64]) -> bool {
        let r = &mut self.0;
        let head = r.word(HEAD).load(Relaxed);
        let tail = r.word(TAIL).load(Acquire);
        if head.wrapping_sub(tail) >= r.depth - 1 {
            return false;
        }
        for (i, w) in r.slot(head).iter().enumerate() {
            w.store(record.get(i).copied().unwrap_or(0), Relaxed);
        }
        r.word(HEAD).store(head.wrapping_add(1), Release);
        true
    }
}

impl RingReader {
    /// Takes the oldest record into `out`; false if empty.
    #[inline]
    pub fn pop(&mut self, out: &mut [u64]) -> bool {
        let r = &mut self.0;
        let tail = r.word(TAIL).load(Relaxed);
        let head = r.word(HEAD).load(Acquire);
        if head == tail {
            return false;
        }
        for (o, w) in out.iter_mut().zip(r.slot(tail)) {
            *o = w.load(Relaxed);
        }
        r.word(TAIL).store(tail.wrapping_add(1), Release);
        true
    }
}
