//! Name-sorted singly linked lists of records in the segment, each with a
//! search tree by name over it (see [`super::index`]): listings walk the
//! list, lookups and changes go through the tree.

use std::sync::atomic::{AtomicU64, Ordering::*};

use super::index::{self, Node};
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

/// A record kept on a sorted list with a search tree by name over it.
pub(crate) trait Indexed: Named {
    /// How the name tree sees the record.
    fn by_name(&self) -> Node<'_>;
}

macro_rules! indexed {
    ($($t:ty),*) => {$(
        impl Indexed for $t {
            fn by_name(&self) -> Node<'_> {
                Node { key: &self.name, left: &self.left, right: &self.right }
            }
        }
    )*};
}
indexed!(CompRec, PinRec, ParamRec, SigRec, FunctRec, RegionRec);

/// A record that may carry an alias (pins and params): while it does, it
/// also sits in a second tree, by the name it had before.
pub(crate) trait Aliased: Indexed {
    /// The root of the kind's alias tree.
    fn alias_root(h: &Header) -> &AtomicU64;
    /// The name before the alias; empty while there is none.
    fn orig(&self) -> &Name;
    /// How the alias tree sees the record.
    fn by_orig(&self) -> Node<'_>;
}

macro_rules! aliased {
    ($($t:ty => $root:ident),*) => {$(
        impl Aliased for $t {
            fn alias_root(h: &Header) -> &AtomicU64 {
                &h.$root
            }
            fn orig(&self) -> &Name {
                &self.orig_name
            }
            fn by_orig(&self) -> Node<'_> {
                Node { key: &self.orig_name, left: &self.alias_left, right: &self.alias_right }
            }
        }
    )*};
}
aliased!(PinRec => pin_aliases, ParamRec => param_aliases);

/// Finds a record by name.
pub(crate) fn find<'a, T: Indexed + 'a>(
    seg: &'a Segment,
    head: &ObjList,
    name: &str,
) -> Result<Option<(u64, &'a T)>> {
    index::lookup(seg, &head.root, T::by_name, &Name::encode(name))
}

/// Finds a pin or param by its name or, as LinuxCNC does, by its name
/// before an alias.
pub(crate) fn find_aliased<'a, T: Aliased + 'a>(
    seg: &'a Segment,
    head: &ObjList,
    name: &str,
) -> Result<Option<(u64, &'a T)>> {
    let key = Name::encode(name);
    if let Some(found) = index::lookup(seg, &head.root, T::by_name, &key)? {
        return Ok(Some(found));
    }
    index::lookup(seg, T::alias_root(seg.header()), T::by_orig, &key)
}

/// Finds a record on an unindexed list (threads) by walking it.
pub(crate) fn find_linear<'a, T: Record + Named + 'a>(
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

/// Inserts `rec` (at `off`) into the kind's tree and, after the neighbour
/// the tree names, into its list, which stays sorted by name (byte order,
/// as LinuxCNC's strcmp).
pub(crate) fn insert_sorted<T: Indexed>(
    tx: &mut Txn<'_>,
    head: &ObjList,
    off: u64,
    rec: &T,
) -> Result<()> {
    let before = index::insert(tx, &head.root, T::by_name, off)?;
    let prev: &AtomicU64 = match before {
        Some(p) => tx.rec::<T>(p)?.link(),
        None => &head.first,
    };
    tx.set(rec.link(), prev.load(Relaxed))?;
    tx.set(prev, off)
}

/// Removes the record at `off` from its list and tree (a pin or param with
/// an alias leaves its alias tree first: [`forget_alias`]).
pub(crate) fn remove<T: Indexed>(tx: &mut Txn<'_>, head: &ObjList, off: u64) -> Result<()> {
    let seg = tx.seg();
    let rec: &T = tx.rec(off)?;
    let before = index::remove(tx, &head.root, T::by_name, off)?;
    let prev: &AtomicU64 = match before {
        Some(p) => tx.rec::<T>(p)?.link(),
        None => &head.first,
    };
    if prev.load(Relaxed) != off {
        return Err(HalError::BadSegment {
            instance: seg.instance().to_string(),
            reason: format!("record {off:#x} is not where its tree puts it on its list"),
        });
    }
    tx.set(prev, rec.link().load(Relaxed))
}

/// Removes an aliased pin or param from its alias tree (before its alias
/// goes, or before the record does).
pub(crate) fn forget_alias<T: Aliased>(tx: &mut Txn<'_>, off: u64) -> Result<()> {
    let rec: &T = tx.rec(off)?;
    if rec.orig().is_empty() {
        return Ok(());
    }
    index::remove(tx, T::alias_root(tx.header()), T::by_orig, off).map(|_| ())
}

/// Adds a pin or param whose `orig_name` was just set to its alias tree.
pub(crate) fn remember_alias<T: Aliased>(tx: &mut Txn<'_>, off: u64) -> Result<()> {
    index::insert(tx, T::alias_root(tx.header()), T::by_orig, off).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AliasKind, ComponentKind, HalType, Host, HostConfig, In};

    /// Checks every index against its list: same records, in name order,
    /// and shallow.
    fn check_all(seg: &Segment) {
        fn on_list<T: Indexed>(seg: &Segment, head: &ObjList) -> Vec<u64> {
            iter::<T>(seg, head).map(|r| r.unwrap().0).collect()
        }
        let h = seg.header();
        index::check(
            seg,
            &h.pins.root,
            PinRec::by_name,
            &on_list::<PinRec>(seg, &h.pins),
        )
        .unwrap();
        index::check(
            seg,
            &h.params.root,
            ParamRec::by_name,
            &on_list::<ParamRec>(seg, &h.params),
        )
        .unwrap();
        index::check(
            seg,
            &h.signals.root,
            SigRec::by_name,
            &on_list::<SigRec>(seg, &h.signals),
        )
        .unwrap();
        index::check(
            seg,
            &h.comps.root,
            CompRec::by_name,
            &on_list::<CompRec>(seg, &h.comps),
        )
        .unwrap();
        let aliased: Vec<u64> = iter::<PinRec>(seg, &h.pins)
            .map(|r| r.unwrap())
            .filter(|(_, p)| !p.orig_name.is_empty())
            .map(|(o, _)| o)
            .collect();
        index::check(seg, &h.pin_aliases, PinRec::by_orig, &aliased).unwrap();
        let names: Vec<String> = iter::<PinRec>(seg, &h.pins)
            .map(|r| r.unwrap().1.name.get())
            .collect();
        let mut sorted = names.clone();
        sorted.sort();
        assert_eq!(names, sorted, "the pin list is in name order");
    }

    #[test]
    fn indexes_follow_creation_aliases_and_removal() {
        let host = Host::create(HostConfig::for_tests("index")).unwrap();
        let inst = host.instance();
        let seg = &inst.seg;
        // Names in an order unlike their sorted one, some sharing prefixes.
        let mut comps = Vec::new();
        for i in 0..40u32 {
            let name = format!("c{}", (i * 17) % 40);
            let c = inst.new_component(&name, ComponentKind::User).unwrap();
            for j in 0..5u32 {
                let _: crate::Pin<f64, In> = c.pin(&format!("{name}.p{}", (j * 3) % 5)).unwrap();
            }
            let _: crate::Param<u32, crate::Rw> = c.param(&format!("{name}.k"), 0).unwrap();
            comps.push(c);
        }
        for i in 0..30 {
            inst.newsig(&format!("s{}", (i * 7) % 30), HalType::Float)
                .unwrap();
        }
        check_all(seg);
        // Found by name; missing names are not found.
        assert!(find::<SigRec>(seg, &seg.header().signals, "s13")
            .unwrap()
            .is_some());
        assert!(find::<SigRec>(seg, &seg.header().signals, "s130")
            .unwrap()
            .is_none());
        assert!(find::<SigRec>(seg, &seg.header().signals, "s")
            .unwrap()
            .is_none());
        // Aliases: found by either name, moved in the list, restored.
        inst.alias(AliasKind::Pin, "c3.p1", "zz.alias").unwrap();
        inst.alias(AliasKind::Pin, "c4.p2", "aa.alias").unwrap();
        inst.alias(AliasKind::Pin, "aa.alias", "mm.alias").unwrap();
        check_all(seg);
        for name in ["c3.p1", "zz.alias", "c4.p2", "mm.alias"] {
            assert!(inst.pin(name).unwrap().is_some(), "{name}");
        }
        assert!(inst.pin("aa.alias").unwrap().is_none());
        inst.unalias(AliasKind::Pin, "zz.alias").unwrap();
        check_all(seg);
        assert!(inst.pin("zz.alias").unwrap().is_none());
        // Removal, aliased pins among them, and a failed change rolled back.
        for i in (0..30).step_by(3) {
            inst.delsig(&format!("s{i}")).unwrap();
        }
        comps.retain(|c| !["c4", "c9", "c0", "c39"].contains(&c.name()));
        check_all(seg);
        assert!(inst.pin("mm.alias").unwrap().is_none());
        assert!(inst.pin("c4.p2").unwrap().is_none());
        assert!(inst.newsig("s1", HalType::Bit).is_err());
        check_all(seg);
        drop(comps);
        check_all(seg);
        assert!(iter::<PinRec>(seg, &seg.header().pins).next().is_none());
    }

    #[test]
    fn a_thousand_names_make_a_shallow_tree() {
        let host = Host::create(HostConfig::for_tests("index-depth")).unwrap();
        let inst = host.instance();
        for i in 0..1000 {
            inst.newsig(&format!("sig.{i:04}"), HalType::S32).unwrap();
        }
        // check() bounds the depth by 4 log2(n) + 8.
        check_all(&inst.seg);
    }

    /// The pair offsets of a component's pins, or of its params.
    fn pairs_of(seg: &Segment, comp: &str, pins: bool) -> Vec<u64> {
        let (_, c) = find::<CompRec>(seg, &seg.header().comps, comp)
            .unwrap()
            .unwrap();
        let mut out = Vec::new();
        let mut cur = if pins {
            c.own_pins.load(Relaxed)
        } else {
            c.own_params.load(Relaxed)
        };
        while cur != 0 {
            if pins {
                let p: &PinRec = seg.rec(cur).unwrap();
                out.push(p.hot.load(Relaxed));
                cur = p.owner_next.load(Relaxed);
            } else {
                let p: &ParamRec = seg.rec(cur).unwrap();
                out.push(p.hot.load(Relaxed));
                cur = p.owner_next.load(Relaxed);
            }
        }
        out.sort_unstable();
        out
    }

    #[test]
    fn pin_and_param_words_are_packed_and_reused_by_their_own_kind() {
        let host = Host::create(HostConfig::for_tests("pairs")).unwrap();
        let inst = host.instance();
        let seg = &inst.seg;
        let a = inst.new_component("a", ComponentKind::User).unwrap();
        for n in ["a.x", "a.y", "a.z"] {
            let _: crate::Pin<f64, In> = a.pin_init(n, 1.5).unwrap();
        }
        let k: crate::Param<u32, crate::Rw> = a.param("a.k", 7).unwrap();
        let _: crate::Param<u32, crate::Rw> = a.param("a.m", 8).unwrap();
        assert_eq!(k.get(), 7);
        let (pins, params) = (pairs_of(seg, "a", true), pairs_of(seg, "a", false));
        // Five pairs made in a row take two cache lines, not five.
        let lines: std::collections::BTreeSet<u64> =
            pins.iter().chain(&params).map(|p| p / 64).collect();
        assert!(lines.len() <= 2, "{pins:?} {params:?}");
        drop(k);
        drop(a);
        // A failed creation (a duplicate) changes nothing.
        let b = inst.new_component("b", ComponentKind::User).unwrap();
        let _: crate::Pin<f64, In> = b.pin_init("b.x", 2.5).unwrap();
        assert!(b.pin::<f64, In>("b.x").is_err());
        for n in ["b.y", "b.z"] {
            let _: crate::Pin<f64, In> = b.pin_init(n, 2.5).unwrap();
        }
        let q: crate::Param<u32, crate::Rw> = b.param("b.q", 9).unwrap();
        // Pins took the pins' freed pairs, the param a param's.
        assert_eq!(pairs_of(seg, "b", true), pins);
        assert!(params.contains(&pairs_of(seg, "b", false)[0]));
        assert_eq!(q.get(), 9);
        for n in ["b.x", "b.y", "b.z"] {
            assert_eq!(inst.pin_value(n).unwrap(), crate::Value::Float(2.5));
        }
        inst.newsig("b.s", HalType::Float).unwrap();
        inst.link("b.y", "b.s").unwrap();
        inst.set_signal("b.s", crate::Value::Float(4.0)).unwrap();
        assert_eq!(inst.pin_value("b.y").unwrap(), crate::Value::Float(4.0));
        inst.unlink("b.y").unwrap();
        assert_eq!(inst.pin_value("b.y").unwrap(), crate::Value::Float(4.0));
        check_all(seg);
    }
}
