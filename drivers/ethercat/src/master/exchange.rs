//! A single-writer, lock-free hand-off of a byte buffer between the
//! realtime side and the master's helper thread: a sequence lock over
//! 64-bit atomic words. The writer never waits; a reader that meets a
//! write in progress retries a bounded number of times and otherwise
//! reports "not now" (the realtime side then keeps last cycle's data and
//! counts it). No allocation after construction, no lock, no system call.

use std::sync::atomic::{fence, AtomicU64, Ordering::*};

/// Retries a reader makes before giving up for this cycle.
const READ_TRIES: usize = 4;

/// The hand-off.
#[derive(Debug)]
pub struct Exchange {
    seq: AtomicU64,
    tag: AtomicU64,
    words: Box<[AtomicU64]>,
    len: usize,
}

impl Exchange {
    /// A hand-off of `len` bytes.
    pub fn new(len: usize) -> Exchange {
        Exchange {
            seq: AtomicU64::new(0),
            tag: AtomicU64::new(0),
            words: (0..len.div_ceil(8)).map(|_| AtomicU64::new(0)).collect(),
            len,
        }
    }

    /// Bytes carried.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether it carries nothing.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// How many writes there have been.
    pub fn writes(&self) -> u64 {
        self.seq.load(Acquire) / 2
    }

    /// Publishes `bytes` (the first `len`) with `tag`. One writer only.
    pub fn write(&self, bytes: &[u8], tag: u64) {
        let s = self.seq.load(Relaxed);
        self.seq.store(s.wrapping_add(1), Relaxed);
        fence(Release);
        for (i, w) in self.words.iter().enumerate() {
            let mut b = [0u8; 8];
            let from = i * 8;
            let n = bytes.len().saturating_sub(from).min(8);
            b[..n].copy_from_slice(&bytes[from..from + n]);
            w.store(u64::from_le_bytes(b), Relaxed);
        }
        self.tag.store(tag, Relaxed);
        self.seq.store(s.wrapping_add(2), Release);
    }

    /// Copies the last complete write into `out`; its tag, or None if a
    /// write kept overlapping the read.
    pub fn read(&self, out: &mut [u8]) -> Option<u64> {
        for _ in 0..READ_TRIES {
            let s1 = self.seq.load(Acquire);
            if s1 % 2 == 1 {
                std::hint::spin_loop();
                continue;
            }
            for (i, w) in self.words.iter().enumerate() {
                let b = w.load(Relaxed).to_le_bytes();
                let from = i * 8;
                let n = out.len().saturating_sub(from).min(8);
                out[from..from + n].copy_from_slice(&b[..n]);
            }
            let tag = self.tag.load(Relaxed);
            fence(Acquire);
            if self.seq.load(Relaxed) == s1 {
                return Some(tag);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_see_whole_writes() {
        let x = Exchange::new(20);
        x.write(&[7; 20], 1);
        let mut out = [0u8; 20];
        assert_eq!(x.read(&mut out), Some(1));
        assert_eq!(out, [7; 20]);
        let x = std::sync::Arc::new(Exchange::new(64));
        let w = x.clone();
        let writer = std::thread::spawn(move || {
            for i in 0..20_000u64 {
                w.write(&[(i % 251) as u8; 64], i);
            }
        });
        let mut seen = 0;
        while !writer.is_finished() || seen == 0 {
            let mut out = [0u8; 64];
            if let Some(tag) = x.read(&mut out) {
                assert!(out.iter().all(|b| *b == out[0]), "torn read at tag {tag}");
                seen += 1;
            }
        }
        writer.join().unwrap();
    }
}
