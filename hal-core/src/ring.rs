//! A single-producer single-consumer ring of fixed-size records in a named
//! region, for realtime-to-user-space streams (sampler, streamer, scope).
//!
//! A ring of depth D holds at most D-1 records (one slot always stays
//! empty), as LinuxCNC's FIFOs do. Indices grow without wrapping; the slot
//! is the index modulo D. The producer owns the head, the consumer the tail;
//! neither ever blocks. Layout in the region, in words: head at 0, tail at 8
//! (own cache lines), depth at 16, record width at 17, records from 24.

use std::sync::atomic::{AtomicU64, Ordering::*};

use crate::error::{HalError, Result};
use crate::objects::{Component, Instance, Region};

const HEAD: usize = 0;
const TAIL: usize = 8;
const DEPTH: usize = 16;
const WIDTH: usize = 17;
const DATA: usize = 24;

struct Ring {
    region: Region,
    depth: u64,
    width: usize,
}

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
        Ok(Ring {
            region,
            depth: depth as u64,
            width,
        })
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
        Ok(Ring {
            region,
            depth,
            width: width as usize,
        })
    }

    fn word(&self, i: usize) -> &AtomicU64 {
        &self.region.words()[i]
    }

    fn slot(&self, index: u64) -> &[AtomicU64] {
        let start = DATA + (index % self.depth) as usize * self.width;
        &self.region.words()[start..start + self.width]
    }

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

            /// Opens a ring another component created.
            pub fn open(inst: &Instance, name: &str) -> Result<$t> {
                Ring::open(inst, name).map($t)
            }

            /// Records waiting in the ring.
            pub fn len(&self) -> usize {
                self.0.len()
            }

            /// Whether the ring holds no record.
            pub fn is_empty(&self) -> bool {
                self.len() == 0
            }

            /// Most records the ring can hold (depth - 1).
            pub fn capacity(&self) -> usize {
                self.0.depth as usize - 1
            }

            /// Words per record.
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
        let r = &self.0;
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
        let r = &self.0;
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
