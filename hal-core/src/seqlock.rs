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
    /// mid-update: first spinning, then sleeping between attempts, because
    /// a writer without realtime priority can be preempted mid-write for
    /// milliseconds. False if no consistent copy was seen for about a
    /// second (a writer that died mid-write). Readers are user-space code;
    /// they may sleep.
    pub fn read(&self, out: &mut [u64]) -> bool {
        const SPINS: u32 = 1000;
        const SLEEPS: u32 = 10_000;
        for attempt in 0..SPINS + SLEEPS {
            if self.try_read(out) {
                return true;
            }
            if attempt < SPINS {
                std::hint::spin_loop();
            } else {
                std::thread::sleep(std::time::Duration::from_micros(100));
            }
        }
        false
    }

    /// One attempt: true if the copy in `out` is consistent.
    fn try_read(&self, out: &mut [u64]) -> bool {
        let w = self.region.words();
        let s1 = w[SEQ].load(Acquire);
        if s1 & 1 == 1 {
            return false;
        }
        for (o, src) in out.iter_mut().zip(&w[DATA..DATA + self.len]) {
            *o = src.load(Relaxed);
        }
        fence(Acquire);
        w[SEQ].load(Relaxed) == s1
    }
}
