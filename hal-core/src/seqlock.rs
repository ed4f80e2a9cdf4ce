//! A seqlock snapshot in a named region: one writer publishes a group of
//! words, readers in any process get a consistent copy without blocking the
//! writer (the motion status channel).

use std::sync::atomic::{fence, Ordering::*};

use crate::error::{HalError, Result};
use crate::objects::{Component, Instance, Region};

const SEQ: usize = 0;
const LEN: usize = 1;
const DATA: usize = 2;

/// The writing end; there must be only one per snapshot.
pub struct SeqLockWriter {
    region: Region,
    len: usize,
}

/// A reading end; any number may exist.
pub struct SeqLockReader {
    region: Region,
    len: usize,
}

impl SeqLockWriter {
    /// Creates a snapshot of `len` words as a region owned by `comp`.
    pub fn create(comp: &Component, name: &str, len: usize) -> Result<SeqLockWriter> {
        let region = comp.region(name, (len + DATA) * 8)?;
        region.words()[LEN].store(len as u64, Release);
        Ok(SeqLockWriter { region, len })
    }

    /// Publishes `data` (its first `len` words; missing words are zero).
    #[inline]
    pub fn write(&mut self, data: &[u64]) {
        let w = self.region.words();
        let seq = w[SEQ].load(Relaxed);
        w[SEQ].store(seq.wrapping_add(1), Relaxed);
        fence(Release);
        for i in 0..self.len {
            w[DATA + i].store(data.get(i).copied().unwrap_or(0), Relaxed);
        }
        w[SEQ].store(seq.wrapping_add(2), Release);
    }
}

impl SeqLockReader {
    /// Opens a snapshot by name.
    pub fn open(inst: &Instance, name: &str) -> Result<SeqLockReader> {
        let region = inst.region(name)?;
        let len = region.words().get(LEN).map_or(0, |w| w.load(Acquire)) as usize;
        if region.words().len() < DATA || len > region.words().len() - DATA {
            return Err(HalError::BadValue {
                what: format!("snapshot '{name}'"),
                reason: format!(
                    "header says {len} words, region has {}",
                    region.words().len()
                ),
            });
        }
        Ok(SeqLockReader { region, len })
    }

    /// Words in the snapshot.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the snapshot has no words.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Copies a consistent snapshot into `out`. Retries while the writer is
    /// mid-update; false if it never finished within the retry budget (a
    /// writer that died mid-write).
    pub fn read(&self, out: &mut [u64]) -> bool {
        let w = self.region.words();
        for _ in 0..100_000 {
            let s1 = w[SEQ].load(Acquire);
            if s1 & 1 == 1 {
                std::hint::spin_loop();
                continue;
            }
            for (o, src) in out.iter_mut().zip(&w[DATA..DATA + self.len]) {
                *o = src.load(Relaxed);
            }
            fence(Acquire);
            if w[SEQ].load(Relaxed) == s1 {
                return true;
            }
        }
        false
    }
}
