//! The search trees over the segment's name-sorted object lists.
//!
//! Each indexed kind (components, pins, params, signals, functions,
//! regions) keeps, beside its sorted list, a treap: a binary search tree by
//! name whose nodes also form a max-heap by a priority drawn from the
//! record's offset. Finding, inserting and removing a record cost O(log n)
//! steps expected, and the tree hands the list its neighbour, so the list
//! (which every listing walks) stays sorted without being searched.
//!
//! Every word the tree changes goes through the transaction's journal, so
//! a holder that dies mid-change leaves the tree as it was, and a reader in
//! another process (who holds the same lock) always sees a whole tree.
//! Every descent is bounded, so a corrupted link ends in an error rather
//! than a loop.

use std::cmp::Ordering;
use std::sync::atomic::{AtomicU64, Ordering::*};

use crate::error::{HalError, Result};
use crate::shm::*;

/// The tree links and key of one record, as one tree sees them: pins and
/// params sit in two trees (by name, and by the name they had before an
/// alias), so the tree code is given a view rather than fixed fields.
pub(crate) struct Node<'r> {
    pub key: &'r Name,
    pub left: &'r AtomicU64,
    pub right: &'r AtomicU64,
}

/// How a tree sees its records.
pub(crate) type View<T> = for<'r> fn(&'r T) -> Node<'r>;

/// A node's heap priority: a mix of its offset (offsets are unique, so
/// ties cannot happen; the mix makes priorities independent of name order
/// even though records are allocated in the order they are named).
fn priority(off: u64) -> u64 {
    let mut z = off.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A name's words, for comparing other names against it.
pub(crate) fn key_of(name: &Name) -> [u64; 32] {
    let mut key = [0u64; 32];
    for (k, w) in key.iter_mut().zip(name.words()) {
        *k = w.load(Relaxed);
    }
    key
}

/// Bounds every walk: a tree cannot have more nodes than the segment has
/// 64-byte blocks.
fn budget(seg: &Segment) -> u64 {
    seg.size() / 64 + 1
}

/// Spends one step of a walk's budget; a walk that runs out is in a
/// broken (cyclic) tree, and `what` says which walk.
fn spend(steps: &mut u64, seg: &Segment, what: &str) -> Result<()> {
    *steps = steps.checked_sub(1).ok_or_else(|| broken(seg, what))?;
    Ok(())
}

fn broken(seg: &Segment, what: &str) -> HalError {
    HalError::BadSegment {
        instance: seg.instance().to_string(),
        reason: format!("object index: {what}"),
    }
}

/// Finds the record whose key equals `key`.
pub(crate) fn lookup<'a, T: Record>(
    seg: &'a Segment,
    root: &AtomicU64,
    view: View<T>,
    key: &[u64; 32],
) -> Result<Option<(u64, &'a T)>> {
    let mut cur = root.load(Acquire);
    let mut steps = budget(seg);
    while cur != 0 {
        spend(&mut steps, seg, "a search does not end")?;
        let r: &T = seg.rec(cur)?;
        let n = view(r);
        cur = match n.key.cmp_key(key) {
            Ordering::Equal => return Ok(Some((cur, r))),
            Ordering::Greater => n.left.load(Acquire),
            Ordering::Less => n.right.load(Acquire),
        };
    }
    Ok(None)
}

/// The link in `parent` (or the root) that leads to a path's next node.
fn link_to<'a, T: Record + 'a>(
    seg: &'a Segment,
    root: &'a AtomicU64,
    view: View<T>,
    parent: Option<&(u64, bool)>,
) -> Result<&'a AtomicU64> {
    Ok(match parent {
        None => root,
        Some(&(p, went_left)) => {
            let n = view(seg.rec::<T>(p)?);
            if went_left {
                n.left
            } else {
                n.right
            }
        }
    })
}

/// Inserts the record at `off`, whose key no other record in the tree has.
/// Returns the record just before it in name order, if any.
pub(crate) fn insert<T: Record>(
    tx: &mut Txn<'_>,
    root: &AtomicU64,
    view: View<T>,
    off: u64,
) -> Result<Option<u64>> {
    let seg = tx.seg();
    let rec: &T = seg.rec(off)?;
    let node = view(rec);
    let key = key_of(node.key);
    // Down to the leaf position, remembering the way and the last node
    // passed on its right (the new record's predecessor).
    let mut path: Vec<(u64, bool)> = Vec::new();
    let mut before = None;
    let mut cur = root.load(Relaxed);
    let mut steps = budget(seg);
    while cur != 0 {
        spend(&mut steps, seg, "an insertion does not end")?;
        let n = view(seg.rec::<T>(cur)?);
        match n.key.cmp_key(&key) {
            Ordering::Equal => return Err(broken(seg, "a name is already in the tree")),
            Ordering::Greater => {
                path.push((cur, true));
                cur = n.left.load(Relaxed);
            }
            Ordering::Less => {
                before = Some(cur);
                path.push((cur, false));
                cur = n.right.load(Relaxed);
            }
        }
    }
    for w in [node.left, node.right] {
        if w.load(Relaxed) != 0 {
            tx.set(w, 0)?;
        }
    }
    tx.set(link_to(seg, root, view, path.last())?, off)?;
    // Up again by rotations while the new node outranks its parent.
    let rank = priority(off);
    while let Some((parent, went_left)) = path.pop() {
        if priority(parent) >= rank {
            break;
        }
        let p = view(seg.rec::<T>(parent)?);
        if went_left {
            tx.set(p.left, node.right.load(Relaxed))?;
            tx.set(node.right, parent)?;
        } else {
            tx.set(p.right, node.left.load(Relaxed))?;
            tx.set(node.left, parent)?;
        }
        tx.set(link_to(seg, root, view, path.last())?, off)?;
    }
    Ok(before)
}

/// Removes the record at `off` from the tree. Returns the record just
/// before it in name order, if any.
pub(crate) fn remove<T: Record>(
    tx: &mut Txn<'_>,
    root: &AtomicU64,
    view: View<T>,
    off: u64,
) -> Result<Option<u64>> {
    let seg = tx.seg();
    let node = view(seg.rec::<T>(off)?);
    let key = key_of(node.key);
    let mut path: Vec<(u64, bool)> = Vec::new();
    let mut before = None;
    let mut cur = root.load(Relaxed);
    let mut steps = budget(seg);
    while cur != off {
        spend(&mut steps, seg, "a removal does not end")?;
        if cur == 0 {
            return Err(broken(seg, &format!("record {off:#x} is not in its tree")));
        }
        let n = view(seg.rec::<T>(cur)?);
        if n.key.cmp_key(&key) == Ordering::Greater {
            path.push((cur, true));
            cur = n.left.load(Relaxed);
        } else {
            before = Some(cur);
            path.push((cur, false));
            cur = n.right.load(Relaxed);
        }
    }
    // With a left subtree, the predecessor is its rightmost node.
    let mut cur = node.left.load(Relaxed);
    while cur != 0 {
        spend(&mut steps, seg, "a removal does not end")?;
        before = Some(cur);
        cur = view(seg.rec::<T>(cur)?).right.load(Relaxed);
    }
    // Down by rotations until the node has at most one child, which then
    // takes its place.
    loop {
        spend(&mut steps, seg, "a removal does not end")?;
        let (l, r) = (node.left.load(Relaxed), node.right.load(Relaxed));
        let link = link_to(seg, root, view, path.last())?;
        if l == 0 || r == 0 {
            tx.set(link, l | r)?;
            break;
        }
        if priority(l) > priority(r) {
            let child = view(seg.rec::<T>(l)?);
            tx.set(node.left, child.right.load(Relaxed))?;
            tx.set(child.right, off)?;
            tx.set(link, l)?;
            path.push((l, false));
        } else {
            let child = view(seg.rec::<T>(r)?);
            tx.set(node.right, child.left.load(Relaxed))?;
            tx.set(child.left, off)?;
            tx.set(link, r)?;
            path.push((r, true));
        }
    }
    tx.set(node.left, 0)?;
    tx.set(node.right, 0)?;
    Ok(before)
}

/// Checks a tree against its records: in name order, heap-ordered, and
/// holding exactly `expected` nodes. For tests.
#[cfg(test)]
pub(crate) fn check<T: Record>(
    seg: &Segment,
    root: &AtomicU64,
    view: View<T>,
    expected: &[u64],
) -> Result<()> {
    fn walk<T: Record>(
        seg: &Segment,
        view: View<T>,
        at: u64,
        out: &mut Vec<u64>,
        depth: usize,
        max: &mut usize,
    ) -> Result<()> {
        if at == 0 {
            return Ok(());
        }
        *max = (*max).max(depth);
        let n = view(seg.rec::<T>(at)?);
        for child in [n.left.load(Relaxed), n.right.load(Relaxed)] {
            assert!(child == 0 || priority(child) <= priority(at), "heap order");
        }
        walk(seg, view, n.left.load(Relaxed), out, depth + 1, max)?;
        out.push(at);
        walk(seg, view, n.right.load(Relaxed), out, depth + 1, max)
    }
    let mut order = Vec::new();
    let mut depth = 0;
    walk(seg, view, root.load(Relaxed), &mut order, 1, &mut depth)?;
    for pair in order.windows(2) {
        let a = view(seg.rec::<T>(pair[0])?);
        let b = view(seg.rec::<T>(pair[1])?);
        assert_eq!(a.key.cmp_key(&key_of(b.key)), Ordering::Less, "name order");
    }
    let mut got = order.clone();
    got.sort_unstable();
    let mut want = expected.to_vec();
    want.sort_unstable();
    assert_eq!(got, want, "the tree holds exactly the listed records");
    let bound = 4 * (usize::BITS - expected.len().leading_zeros()) as usize + 8;
    assert!(depth <= bound, "depth {depth} for {} nodes", expected.len());
    Ok(())
}
