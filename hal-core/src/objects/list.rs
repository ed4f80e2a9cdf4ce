//! Name-sorted singly linked lists of records in the segment.

use std::sync::atomic::{AtomicU64, Ordering::*};

use crate::error::{HalError, Result};
use crate::shm::*;

/// A record that sits on a name-sorted list.
pub(crate) trait Named: Record {
    fn name(&self) -> &Name;
    fn link(&self) -> &AtomicU64;
}

macro_rules! named {
    ($($t:ty),*) => {$(
        impl Named for $t {
            fn name(&self) -> &Name { &self.name }
            fn link(&self) -> &AtomicU64 { &self.next }
        }
    )*};
}
named!(CompRec, PinRec, ParamRec, SigRec, FunctRec, ThreadRec, RegionRec);

/// Iterates a list, stopping with an error on a bad link or a cycle.
pub(crate) fn iter<'a, T: Record + Named + 'a>(
    seg: &'a Segment,
    head: &AtomicU64,
) -> impl Iterator<Item = Result<(u64, &'a T)>> + 'a {
    let mut cur = head.load(Acquire);
    let mut budget = seg.size() / 64 + 1;
    std::iter::from_fn(move || {
        if cur == 0 {
            return None;
        }
        if budget == 0 {
            cur = 0;
            return Some(Err(HalError::BadSegment {
                instance: seg.instance().to_string(),
                reason: "object list does not terminate".into(),
            }));
        }
        budget -= 1;
        match seg.rec::<T>(cur) {
            Ok(r) => {
                let off = cur;
                cur = r.link().load(Acquire);
                Some(Ok((off, r)))
            }
            Err(e) => {
                cur = 0;
                Some(Err(e))
            }
        }
    })
}

/// Finds a record by name.
pub(crate) fn find<'a, T: Record + Named + 'a>(
    seg: &'a Segment,
    head: &AtomicU64,
    name: &str,
) -> Result<Option<(u64, &'a T)>> {
    let key = Name::encode(name);
    for item in iter::<T>(seg, head) {
        let (off, r) = item?;
        if r.name().eq_key(&key) {
            return Ok(Some((off, r)));
        }
    }
    Ok(None)
}

/// Inserts `rec` (at `off`) keeping the list sorted by name (byte order, as
/// LinuxCNC's strcmp).
pub(crate) fn insert_sorted<T: Record + Named>(
    tx: &mut Txn<'_>,
    head: &AtomicU64,
    off: u64,
    rec: &T,
) -> Result<()> {
    let mut key = [0u64; 32];
    for (k, w) in key.iter_mut().zip(rec.name().words()) {
        *k = w.load(Relaxed);
    }
    let seg = tx.seg();
    let mut prev: &AtomicU64 = head;
    for item in iter::<T>(seg, head) {
        let (_, r) = item?;
        if r.name().cmp_key(&key) == std::cmp::Ordering::Greater {
            break;
        }
        prev = r.link();
    }
    tx.set(rec.link(), prev.load(Relaxed))?;
    tx.set(prev, off)
}

/// Removes the record at `off` from a list.
pub(crate) fn remove<T: Record + Named>(
    tx: &mut Txn<'_>,
    head: &AtomicU64,
    off: u64,
) -> Result<()> {
    let seg = tx.seg();
    let mut prev: &AtomicU64 = head;
    for item in iter::<T>(seg, head) {
        let (o, r) = item?;
        if o == off {
            return tx.set(prev, r.link().load(Relaxed));
        }
        prev = r.link();
    }
    Err(HalError::BadSegment {
        instance: seg.instance().to_string(),
        reason: format!("record {off:#x} is not on its list"),
    })
}
