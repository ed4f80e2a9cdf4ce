//! Transactions: every structural change runs under the robust lock, and
//! every word it overwrites in reachable memory is first recorded in an undo
//! journal in the segment. A commit empties the journal; an error, a panic,
//! or the death of the holding process (seen by the next locker as
//! EOWNERDEAD) replays it backwards, so the structure is never half-changed.

use std::mem::size_of;
use std::sync::atomic::{AtomicU64, Ordering::*};

use super::alloc::BlockKind;
use super::layout::*;
use super::mutex::Acquired;
use super::segment::Segment;
use crate::error::{HalError, Result};

/// An open transaction; holds the structural lock.
pub(crate) struct Txn<'a> {
    seg: &'a Segment,
    /// Whether anything was written (to bump the generation on commit).
    dirty: bool,
}

impl Segment {
    /// Runs `f` as one transaction: committed if it returns `Ok`, rolled back
    /// if it returns `Err` or panics.
    pub(crate) fn transaction<T>(&self, f: impl FnOnce(&mut Txn<'_>) -> Result<T>) -> Result<T> {
        let h = self.header();
        match h.mutex.lock(self) {
            Ok(Acquired::Clean) => {
                // A holder that died after a previous EOWNERDEAD recovery
                // cannot leave entries behind, but be defensive anyway.
                if h.journal_len.load(Relaxed) != 0 {
                    rollback(self);
                }
            }
            Ok(Acquired::OwnerDied) => {
                rollback(self);
                if let Err(source) = h.mutex.make_consistent() {
                    h.mutex.unlock();
                    return Err(HalError::Os {
                        op: "recovering the HAL lock",
                        source,
                    });
                }
            }
            Err(source) => {
                return Err(HalError::Os {
                    op: "taking the HAL lock",
                    source,
                })
            }
        }
        struct Unlock<'s>(&'s Segment, bool);
        impl Drop for Unlock<'_> {
            fn drop(&mut self) {
                if !self.1 {
                    // Panic or error: undo everything first.
                    rollback(self.0);
                }
                self.0.header().mutex.unlock();
            }
        }
        let mut guard = Unlock(self, false);
        let mut tx = Txn {
            seg: self,
            dirty: false,
        };
        let result = f(&mut tx);
        if result.is_ok() {
            h.journal_len.store(0, Release);
            if tx.dirty {
                h.generation.fetch_add(1, Release);
            }
            guard.1 = true;
        }
        drop(guard);
        result
    }
}

/// Undoes a journal, newest entry first.
fn rollback(seg: &Segment) {
    let h = seg.header();
    let n = (h.journal_len.load(Acquire) as usize).min(JOURNAL_CAP);
    for i in (0..n).rev() {
        let (off, old) = seg.journal_entry(i);
        if let Ok(w) = seg.word(off.load(Relaxed)) {
            w.store(old.load(Relaxed), Release);
        }
    }
    h.journal_len.store(0, Release);
}

impl<'a> Txn<'a> {
    pub(crate) fn seg(&self) -> &'a Segment {
        self.seg
    }

    pub(crate) fn header(&self) -> &'a Header {
        self.seg.header()
    }

    pub(crate) fn rec<T: Record>(&self, off: u64) -> Result<&'a T> {
        self.seg.rec(off)
    }

    /// Writes `value` to a word of the segment, journaling the old value.
    pub(crate) fn set(&mut self, word: &AtomicU64, value: u64) -> Result<()> {
        let h = self.seg.header();
        let n = h.journal_len.load(Relaxed) as usize;
        if n >= JOURNAL_CAP {
            return Err(HalError::JournalFull { limit: JOURNAL_CAP });
        }
        let off = self.seg.offset_of(word);
        let (e_off, e_old) = self.seg.journal_entry(n);
        e_off.store(off, Relaxed);
        e_old.store(word.load(Relaxed), Relaxed);
        // The entry is complete before it counts, and counts before the write.
        h.journal_len.store(n as u64 + 1, Release);
        word.store(value, Release);
        self.dirty = true;
        Ok(())
    }

    /// Writes a name field, journaling every word that changes.
    pub(crate) fn set_name(&mut self, name: &Name, s: &str) -> Result<()> {
        for (w, v) in name.words().iter().zip(Name::encode(s)) {
            if w.load(Relaxed) != v {
                self.set(w, v)?;
            }
        }
        Ok(())
    }

    /// Allocates a zeroed record of type `T` from the free list of `kind`
    /// or the top of the segment, and tags it. The record is unreachable
    /// until the caller links it, so its contents need no journaling.
    pub(crate) fn alloc<T: Record>(&mut self, kind: BlockKind) -> Result<(u64, &'a T)> {
        let size = size_of::<T>() as u64;
        debug_assert_eq!(kind.size(), Some(size.next_multiple_of(64)));
        let off = self.alloc_block(kind, size)?;
        let words = self.seg.words(off, size / 8)?;
        for w in words.iter().skip(2) {
            w.store(0, Relaxed);
        }
        words[0].store(T::TAG, Release);
        Ok((off, self.seg.rec::<T>(off)?))
    }

    /// Allocates a blob with room for `len` bytes.
    pub(crate) fn alloc_blob(&mut self, len: u64) -> Result<(u64, &'a BlobRec)> {
        let hdr = size_of::<BlobRec>() as u64;
        let need = hdr + len.next_multiple_of(8);
        // First fit from the blob free list.
        let h = self.header();
        let mut prev: &AtomicU64 = &h.free[BlockKind::Blob as usize];
        let mut cur = prev.load(Relaxed);
        let mut budget = self.seg.size() / 64;
        while cur != 0 && budget > 0 {
            budget -= 1;
            let b: &BlobRec = self.rec(cur)?;
            if b.capacity.load(Relaxed).saturating_add(hdr) >= need {
                let next = b.next.load(Relaxed);
                self.set(prev, next)?;
                self.set(&b.next, 0)?;
                self.init_blob(cur, b.capacity.load(Relaxed))?;
                return Ok((cur, self.rec(cur)?));
            }
            prev = &b.next;
            cur = b.next.load(Relaxed);
        }
        let size = need.next_multiple_of(64);
        let off = self.bump(size)?;
        self.init_blob(off, size - hdr)?;
        Ok((off, self.rec(off)?))
    }

    fn init_blob(&mut self, off: u64, capacity: u64) -> Result<()> {
        let total = size_of::<BlobRec>() as u64 + capacity;
        let words = self.seg.words(off, total / 8)?;
        for w in words.iter().skip(2) {
            w.store(0, Relaxed);
        }
        words[2].store(capacity, Relaxed);
        words[0].store(BlobRec::TAG, Release);
        Ok(())
    }

    /// Data words of a blob.
    pub(crate) fn blob_words(&self, off: u64) -> Result<&'a [AtomicU64]> {
        blob_words(self.seg, off)
    }

    fn alloc_block(&mut self, kind: BlockKind, size: u64) -> Result<u64> {
        let head = &self.header().free[kind as usize];
        let off = head.load(Relaxed);
        if off != 0 {
            let next_word = self.seg.word(off.saturating_add(8))?;
            let next = next_word.load(Relaxed);
            self.set(head, next)?;
            self.set(next_word, 0)?;
            return Ok(off);
        }
        self.bump(size.next_multiple_of(64))
    }

    fn bump(&mut self, size: u64) -> Result<u64> {
        let top_word = &self.header().alloc_top;
        let top = top_word.load(Relaxed);
        let available = self.seg.size().saturating_sub(top);
        if size > available {
            return Err(HalError::OutOfMemory {
                requested: size,
                available,
            });
        }
        self.set(top_word, top + size)?;
        Ok(top)
    }

    /// A [`Pair`] holding `first` and `second`, from the pool's free list or
    /// carved from the current pair block (a new block when it is used up).
    pub(crate) fn alloc_pair(&mut self, pool: PairPool, first: u64, second: u64) -> Result<u64> {
        let h = self.header();
        let free = match pool {
            PairPool::Pin => &h.free_pin_pairs,
            PairPool::Param => &h.free_param_pairs,
        };
        let off = match free.load(Relaxed) {
            0 => {
                let (mut block, used) = (h.pair_block.load(Relaxed), h.pair_used.load(Relaxed));
                if block == 0 || used >= 4 {
                    block = self.alloc_block(BlockKind::Pairs, 64)?;
                    self.set(&h.pair_block, block)?;
                    self.set(&h.pair_used, 0)?;
                }
                let used = h.pair_used.load(Relaxed);
                self.set(&h.pair_used, used + 1)?;
                block + used * 16
            }
            off => {
                let next = self.seg.pair(off)?.first.load(Relaxed);
                self.set(free, next)?;
                off
            }
        };
        // Journaled: a reused pair's first word held the free list's link.
        let p = self.seg.pair(off)?;
        self.set(&p.second, second)?;
        self.set(&p.first, first)?;
        Ok(off)
    }

    /// Returns a pair to its pool's free list; its record is already gone
    /// from every list.
    pub(crate) fn free_pair(&mut self, pool: PairPool, off: u64) -> Result<()> {
        let h = self.header();
        let free = match pool {
            PairPool::Pin => &h.free_pin_pairs,
            PairPool::Param => &h.free_param_pairs,
        };
        let p = self.seg.pair(off)?;
        self.set(&p.first, free.load(Relaxed))?;
        self.set(free, off)
    }

    /// Returns a block to the free list of its kind. The caller has already
    /// unlinked it from every live list.
    pub(crate) fn free(&mut self, kind: BlockKind, off: u64) -> Result<()> {
        if off == 0 {
            return Ok(());
        }
        let head = &self.header().free[kind as usize];
        let next_word = self.seg.word(off.saturating_add(8))?;
        self.set(next_word, head.load(Relaxed))?;
        self.set(head, off)
    }
}

/// Data words of the blob at `off` (bounds-checked against its capacity).
pub(crate) fn blob_words(seg: &Segment, off: u64) -> Result<&[AtomicU64]> {
    let b: &BlobRec = seg.rec(off)?;
    let cap = b.capacity.load(Relaxed);
    seg.words(off + size_of::<BlobRec>() as u64, cap / 8)
}
