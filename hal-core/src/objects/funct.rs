//! Function and thread metadata in the segment. The code behind a function
//! lives in the host's private table; the segment only holds its id there,
//! so nothing written into the segment can make the host jump anywhere.

use std::sync::atomic::{AtomicU64, Ordering::*};

use super::component::{new_component_tx, remove_component_tx, ComponentKind};
use super::list;
use super::param::new_param_tx;
use super::pin::new_pin_tx;
use crate::error::{HalError, Result};
use crate::name::validate;
use crate::shm::*;
use crate::types::{HalType, ParamDir, PinDir};

/// Creates a function record with its `.time` pin and `.tmax`,
/// `.tmax-increased` params, owned by component `comp`.
pub(crate) fn new_funct_tx(
    tx: &mut Txn<'_>,
    comp: u64,
    name: &str,
    code_id: u64,
    uses_fp: bool,
    reentrant: bool,
) -> Result<u64> {
    validate("function", name)?;
    let seg = tx.seg();
    let h = tx.header();
    if list::find::<FunctRec>(seg, &h.functs, name)?.is_some() {
        return Err(HalError::Duplicate {
            kind: "function",
            name: name.to_string(),
        });
    }
    let time = new_pin_tx(
        tx,
        comp,
        &format!("{name}.time"),
        HalType::S32,
        PinDir::Out,
        0,
    )?;
    let tmax = new_param_tx(
        tx,
        comp,
        &format!("{name}.tmax"),
        HalType::S32,
        ParamDir::Rw,
        0,
    )?;
    let inc = new_param_tx(
        tx,
        comp,
        &format!("{name}.tmax-increased"),
        HalType::Bit,
        ParamDir::Ro,
        0,
    )?;
    let (off, rec) = tx.alloc::<FunctRec>(BlockKind::Funct)?;
    rec.name.init(name);
    rec.owner.store(comp, Relaxed);
    rec.code_id.store(code_id, Relaxed);
    rec.uses_fp.store(uses_fp as u64, Relaxed);
    rec.reentrant.store(reentrant as u64, Relaxed);
    rec.time_pin.store(time, Relaxed);
    rec.tmax_param.store(tmax, Relaxed);
    rec.tmax_inc_param.store(inc, Relaxed);
    list::insert_sorted(tx, &h.functs, off, rec)?;
    super::component::adopt(tx, comp, |c| &c.own_functs, &rec.owner_next, off)?;
    Ok(off)
}

/// Removes a function that no thread lists any more: its component took
/// all of its functions out of the threads first
/// ([`remove_owned_entries_tx`]). Its timing pin and params belong to the
/// component, which removes them with its other pins and params (this is
/// only called while removing the component).
pub(crate) fn remove_funct_tx(tx: &mut Txn<'_>, off: u64) -> Result<()> {
    let h = tx.header();
    let f: &FunctRec = tx.rec(off)?;
    if f.users.load(Relaxed) != 0 {
        // A thread entry not found by the owner's pass: the segment's
        // lists and counts disagree; the transaction is rolled back.
        return Err(HalError::BadSegment {
            instance: tx.seg().instance().to_string(),
            reason: format!(
                "function '{}' is still in a thread after its component left them",
                f.name.get()
            ),
        });
    }
    list::remove::<FunctRec>(tx, &h.functs, off)?;
    tx.free(BlockKind::Funct, off)
}

/// Function record offsets in a thread's list, in execution order.
pub(crate) fn entries(seg: &Segment, thread: &ThreadRec) -> Result<Vec<u64>> {
    list_entries(seg, &thread.functs)
}

/// Function record offsets in a thread's init list.
pub(crate) fn init_entries(seg: &Segment, thread: &ThreadRec) -> Result<Vec<u64>> {
    list_entries(seg, &thread.init_functs)
}

fn list_entries(seg: &Segment, head: &AtomicU64) -> Result<Vec<u64>> {
    let mut out = Vec::new();
    let mut cur = head.load(Acquire);
    let mut budget = seg.size() / 64;
    while cur != 0 {
        if budget == 0 {
            return Err(HalError::BadSegment {
                instance: seg.instance().to_string(),
                reason: "thread function list does not terminate".into(),
            });
        }
        budget -= 1;
        let e: &EntryRec = seg.rec(cur)?;
        out.push(e.funct.load(Relaxed));
        cur = e.next.load(Acquire);
    }
    Ok(out)
}

/// Converts halcmd's `addf` position into a list index: 1 is first, 2
/// second, ...; -1 is last, -2 one before last, ...; 0 or beyond the list is
/// `None`.
pub(crate) fn position_to_index(position: i32, len: usize) -> Option<usize> {
    let mag = position.unsigned_abs() as usize;
    match position {
        p if p > 0 && mag <= len + 1 => Some(mag - 1),
        p if p < 0 && mag <= len + 1 => Some(len + 1 - mag),
        _ => None,
    }
}

/// Inserts function `funct` into `thread`'s list at `index` (checked by the
/// caller against the list length; `append` when it is the length) and
/// counts the new user. Appending takes one step, whatever the length.
pub(crate) fn add_entry_tx(
    tx: &mut Txn<'_>,
    thread: u64,
    funct: u64,
    index: usize,
    append: bool,
) -> Result<()> {
    let t: &ThreadRec = tx.rec(thread)?;
    let last = t.functs_last.load(Relaxed);
    let at_end = match last {
        0 => None,
        l => tx
            .rec::<EntryRec>(l)
            .ok()
            .filter(|e| e.next.load(Relaxed) == 0),
    };
    let off = match (append, at_end) {
        (true, Some(e)) => insert_entry_tx(tx, &e.next, funct, 0)?,
        _ => insert_entry_tx(tx, &t.functs, funct, index)?,
    };
    let e: &EntryRec = tx.rec(off)?;
    if e.next.load(Relaxed) == 0 {
        tx.set(&t.functs_last, off)?;
    }
    Ok(())
}

/// Appends `funct` to `thread`'s init list.
pub(crate) fn add_init_entry_tx(tx: &mut Txn<'_>, thread: u64, funct: u64) -> Result<()> {
    let t: &ThreadRec = tx.rec(thread)?;
    let n = init_entries(tx.seg(), t)?.len();
    insert_entry_tx(tx, &t.init_functs, funct, n).map(|_| ())
}

/// Inserts an entry for `funct` `index` links after `head`; returns its
/// offset.
fn insert_entry_tx(tx: &mut Txn<'_>, head: &AtomicU64, funct: u64, index: usize) -> Result<u64> {
    let f: &FunctRec = tx.rec(funct)?;
    let (off, e) = tx.alloc::<EntryRec>(BlockKind::Entry)?;
    e.funct.store(funct, Relaxed);
    let mut link = head;
    for _ in 0..index {
        let cur = link.load(Relaxed);
        if cur == 0 {
            break;
        }
        let rec: &EntryRec = tx.rec(cur)?;
        link = &rec.next;
    }
    tx.set(&e.next, link.load(Relaxed))?;
    tx.set(link, off)?;
    tx.set(&f.users, f.users.load(Relaxed).saturating_add(1))?;
    Ok(off)
}

/// Removes the first occurrence of `funct` from `thread`; false if absent.
pub(crate) fn remove_entry_tx(tx: &mut Txn<'_>, thread: u64, funct: u64) -> Result<bool> {
    let t: &ThreadRec = tx.rec(thread)?;
    if remove_from_list_tx(tx, &t.init_functs, None, funct)? {
        return Ok(true);
    }
    remove_from_list_tx(tx, &t.functs, Some(&t.functs_last), funct)
}

/// Removes the first entry for `funct` after `head`, keeping `last` (the
/// list's last entry) up to date.
fn remove_from_list_tx(
    tx: &mut Txn<'_>,
    head: &AtomicU64,
    last: Option<&AtomicU64>,
    funct: u64,
) -> Result<bool> {
    let mut link = head;
    let mut prev = 0;
    let mut budget = tx.seg().size() / 64;
    while link.load(Relaxed) != 0 && budget > 0 {
        budget -= 1;
        let off = link.load(Relaxed);
        let e: &EntryRec = tx.rec(off)?;
        if e.funct.load(Relaxed) == funct {
            let next = e.next.load(Relaxed);
            tx.set(link, next)?;
            if let (Some(last), 0) = (last, next) {
                tx.set(last, prev)?;
            }
            tx.free(BlockKind::Entry, off)?;
            let f: &FunctRec = tx.rec(funct)?;
            tx.set(&f.users, f.users.load(Relaxed).saturating_sub(1))?;
            return Ok(true);
        }
        prev = off;
        link = &e.next;
    }
    Ok(false)
}

/// Takes every entry of a function owned by component `comp` out of every
/// thread's lists, in one pass over each list: removing a component with
/// N functions in a thread then costs one walk of that thread, where one
/// search per function made teardown grow with N².
pub(crate) fn remove_owned_entries_tx(tx: &mut Txn<'_>, comp: u64) -> Result<()> {
    let seg = tx.seg();
    let h = tx.header();
    let threads: Vec<u64> = list::iter::<ThreadRec>(seg, &h.threads)
        .map(|r| r.map(|(o, _)| o))
        .collect::<Result<_>>()?;
    for thread in threads {
        let t: &ThreadRec = tx.rec(thread)?;
        remove_entries_where_tx(tx, &t.init_functs, None, comp)?;
        remove_entries_where_tx(tx, &t.functs, Some(&t.functs_last), comp)?;
    }
    Ok(())
}

/// Removes, in one walk from `head`, every entry whose function is owned by
/// `comp`, keeping `last` (the list's last entry) up to date.
fn remove_entries_where_tx(
    tx: &mut Txn<'_>,
    head: &AtomicU64,
    last: Option<&AtomicU64>,
    comp: u64,
) -> Result<()> {
    let mut link = head;
    let mut prev = 0;
    let mut budget = tx.seg().size() / 64;
    while link.load(Relaxed) != 0 {
        if budget == 0 {
            return Err(HalError::BadSegment {
                instance: tx.seg().instance().to_string(),
                reason: "thread function list does not terminate".into(),
            });
        }
        budget -= 1;
        let off = link.load(Relaxed);
        let e: &EntryRec = tx.rec(off)?;
        let funct = e.funct.load(Relaxed);
        let f: &FunctRec = tx.rec(funct)?;
        if f.owner.load(Relaxed) != comp {
            prev = off;
            link = &e.next;
            continue;
        }
        // Unlink and free the entry; `link` now leads to its successor.
        tx.set(link, e.next.load(Relaxed))?;
        tx.free(BlockKind::Entry, off)?;
        tx.set(&f.users, f.users.load(Relaxed).saturating_sub(1))?;
    }
    if let Some(last) = last {
        tx.set(last, prev)?;
    }
    Ok(())
}

/// Thread creation parameters checked against LinuxCNC's rules.
pub(crate) struct NewThread<'a> {
    pub name: &'a str,
    pub period: i64,
    pub uses_fp: bool,
    pub cpu: Option<usize>,
}

/// Creates a thread record with its pseudo-component `__<name>`, the pins
/// `<name>.time` and `<name>.threadbeat` and the param `<name>.tmax`.
/// Returns the record and the (possibly rounded) period.
pub(crate) fn new_thread_tx(tx: &mut Txn<'_>, spec: &NewThread<'_>) -> Result<(u64, i64)> {
    let name = spec.name;
    validate("thread", name)?;
    let seg = tx.seg();
    let h = tx.header();
    if list::find_linear::<ThreadRec>(seg, &h.threads, name)?.is_some() {
        return Err(HalError::Duplicate {
            kind: "thread",
            name: name.to_string(),
        });
    }
    if spec.period <= 0 {
        return Err(HalError::ZeroPeriod {
            name: name.to_string(),
        });
    }
    let stored = h.base_period.load(Relaxed);
    let period = if stored == 0 || stored > i64::MAX as u64 {
        tx.set(&h.base_period, spec.period as u64)?;
        spec.period
    } else {
        let base = stored as i64;
        if spec.period < base {
            return Err(HalError::PeriodBelowBase {
                name: name.to_string(),
                period: spec.period,
                base,
            });
        }
        spec.period
            .checked_add(base / 2)
            .map(|p| p / base)
            .and_then(|n| n.checked_mul(base))
            .filter(|&p| p > 0)
            .ok_or_else(|| HalError::ZeroPeriod {
                name: name.to_string(),
            })?
    };
    let mut lowest_priority = u64::MAX;
    for item in list::iter::<ThreadRec>(seg, &h.threads) {
        let (_, t) = item?;
        let p = t.period.load(Relaxed) as i64;
        if period < p {
            return Err(HalError::ThreadOrder {
                name: name.to_string(),
                period,
                previous: p,
                previous_name: t.name.get(),
            });
        }
        lowest_priority = lowest_priority.min(t.priority.load(Relaxed));
    }
    let priority = if lowest_priority == u64::MAX {
        crate::exec::TOP_PRIORITY as u64
    } else {
        lowest_priority.saturating_sub(1).max(1)
    };
    let (comp, _) = new_component_tx(tx, &format!("__{name}"), ComponentKind::Other)?;
    let time = new_pin_tx(
        tx,
        comp,
        &format!("{name}.time"),
        HalType::S32,
        PinDir::Out,
        0,
    )?;
    let beat = new_pin_tx(
        tx,
        comp,
        &format!("{name}.threadbeat"),
        HalType::S64,
        PinDir::Out,
        0,
    )?;
    let tmax = new_param_tx(
        tx,
        comp,
        &format!("{name}.tmax"),
        HalType::S32,
        ParamDir::Rw,
        0,
    )?;
    let comp_rec: &CompRec = tx.rec(comp)?;
    tx.set(&comp_rec.ready, 1)?;
    let (off, t) = tx.alloc::<ThreadRec>(BlockKind::Thread)?;
    t.name.init(name);
    t.owner.store(comp, Relaxed);
    t.period.store(period as u64, Relaxed);
    t.priority.store(priority, Relaxed);
    t.uses_fp.store(spec.uses_fp as u64, Relaxed);
    t.cpu.store(spec.cpu.map_or(0, |c| c as u64 + 1), Relaxed);
    t.time_pin.store(time, Relaxed);
    t.tmax_param.store(tmax, Relaxed);
    t.beat_pin.store(beat, Relaxed);
    t.seen_epoch.store(u64::MAX, Relaxed);
    t.lat_min_ns.store(u64::MAX, Relaxed);
    // Newest (slowest) first, as LinuxCNC lists them.
    tx.set(&t.next, h.threads.load(Relaxed))?;
    tx.set(&h.threads, off)?;
    Ok((off, period))
}

/// Deletes a thread: empties its list, removes its pseudo-component.
pub(crate) fn delete_thread_tx(tx: &mut Txn<'_>, off: u64) -> Result<()> {
    let seg = tx.seg();
    let h = tx.header();
    let t: &ThreadRec = tx.rec(off)?;
    for f in entries(seg, t)?.into_iter().chain(init_entries(seg, t)?) {
        remove_entry_tx(tx, off, f)?;
    }
    let comp = t.owner.load(Relaxed);
    // Unlink from the (not name-sorted) thread list.
    let mut link = &h.threads;
    let mut budget = seg.size() / 64;
    while link.load(Relaxed) != 0 && budget > 0 {
        budget -= 1;
        let cur = link.load(Relaxed);
        let r: &ThreadRec = tx.rec(cur)?;
        if cur == off {
            tx.set(link, r.next.load(Relaxed))?;
            break;
        }
        link = &r.next;
    }
    if comp != 0 {
        remove_component_tx(tx, comp)?;
    }
    tx.free(BlockKind::Thread, off)
}
