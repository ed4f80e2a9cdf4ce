//! Components: creation, readiness, and removal with everything they own.

use std::sync::atomic::{AtomicU64, Ordering::*};

use super::list;
use super::Instance;
use crate::error::{HalError, Result};
use crate::handles::{Direction, Param, ParamAccess, Pin, RawParam, RawPin};
use crate::name::validate;
use crate::shm::*;
use crate::types::PinValue;

/// What kind of component this is, as `show comp` reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ComponentKind {
    /// A user-space component in some process other than the host.
    User,
    /// A realtime component living in the host.
    Realtime,
    /// A pseudo-component made by the core (one per thread).
    Other,
}

impl ComponentKind {
    pub(crate) fn code(self) -> u64 {
        match self {
            ComponentKind::User => 0,
            ComponentKind::Realtime => 1,
            ComponentKind::Other => 2,
        }
    }

    pub(crate) fn from_code(c: u64) -> ComponentKind {
        match c {
            0 => ComponentKind::User,
            1 => ComponentKind::Realtime,
            _ => ComponentKind::Other,
        }
    }
}

/// A component in the instance. Pins, params and regions are created
/// through it; dropping it removes the component and everything it owns,
/// so a component whose set-up failed half way leaves nothing behind.
pub struct Component {
    inst: Instance,
    off: u64,
    id: i32,
    name: String,
    kind: ComponentKind,
}

impl Instance {
    /// Creates a component owned by this process. It is not ready until
    /// [`Component::ready`] is called.
    pub fn new_component(&self, name: &str, kind: ComponentKind) -> Result<Component> {
        self.check_unlocked(super::lock_bits::LOAD, "hal_init")?;
        let (off, id) = self.tx(|tx| new_component_tx(tx, name, kind))?;
        Ok(Component {
            inst: self.clone(),
            off,
            id,
            name: name.to_string(),
            kind,
        })
    }

    /// Sets the id the next component will get. LinuxCNC numbers components
    /// together with its own process pieces; a front end that reproduces its
    /// numbering uses this. Ids never go backwards.
    pub fn advance_component_ids(&self, next: i32) -> Result<()> {
        self.tx(|tx| {
            let h = tx.header();
            if (next as u64) > h.next_comp_id.load(Relaxed) {
                tx.set(&h.next_comp_id, next as u64)?;
            }
            Ok(())
        })
    }

    /// The id the next component will get.
    pub fn next_component_id(&self) -> i32 {
        self.seg.header().next_comp_id.load(Relaxed) as i32
    }

    /// Removes the component at `off` and every pin, param, function and
    /// region it owns. Functions still in a thread are taken out of it.
    pub(crate) fn remove_component(&self, off: u64) -> Result<()> {
        self.tx(|tx| remove_component_tx(tx, off))
    }
}

pub(crate) fn new_component_tx(
    tx: &mut Txn<'_>,
    name: &str,
    kind: ComponentKind,
) -> Result<(u64, i32)> {
    validate("component", name)?;
    let h = tx.header();
    if list::find::<CompRec>(tx.seg(), &h.comps, name)?.is_some() {
        return Err(HalError::Duplicate {
            kind: "component",
            name: name.to_string(),
        });
    }
    let id = h.next_comp_id.load(Relaxed);
    if id > i32::MAX as u64 {
        return Err(HalError::TooMany {
            kind: "component",
            limit: i32::MAX as usize,
        });
    }
    tx.set(&h.next_comp_id, id + 1)?;
    let (off, rec) = tx.alloc::<CompRec>(BlockKind::Comp)?;
    rec.name.init(name);
    rec.id.store(id, Relaxed);
    rec.kind.store(kind.code(), Relaxed);
    rec.pid.store(std::process::id() as u64, Relaxed);
    list::insert_sorted(tx, &h.comps, off, rec)?;
    if kind == ComponentKind::User {
        super::owner::claim(tx.seg(), off)?;
    }
    Ok((off, id as i32))
}

/// Puts a new object (at `off`, its next-link word `next`) at the head of
/// one of its owner's lists.
pub(crate) fn adopt(
    tx: &mut Txn<'_>,
    comp: u64,
    list: fn(&CompRec) -> &AtomicU64,
    next: &AtomicU64,
    off: u64,
) -> Result<()> {
    let head = list(tx.rec::<CompRec>(comp)?);
    tx.set(next, head.load(Relaxed))?;
    tx.set(head, off)
}

/// The objects on one of a component's lists.
fn owned<T: Record>(
    seg: &Segment,
    head: &AtomicU64,
    next: fn(&T) -> &AtomicU64,
) -> Result<Vec<u64>> {
    let mut out = Vec::new();
    let mut cur = head.load(Relaxed);
    while cur != 0 {
        if out.len() as u64 > seg.size() / 64 {
            return Err(HalError::BadSegment {
                instance: seg.instance().to_string(),
                reason: "a component's list of objects does not end".into(),
            });
        }
        out.push(cur);
        cur = next(seg.rec::<T>(cur)?).load(Relaxed);
    }
    Ok(out)
}

pub(crate) fn remove_component_tx(tx: &mut Txn<'_>, off: u64) -> Result<()> {
    let seg = tx.seg();
    let h = tx.header();
    let comp: &CompRec = tx.rec(off)?;
    // Functions: out of every thread (one pass over each thread's list),
    // then gone (their timing pins and params are on the component's
    // lists too).
    crate::objects::funct::remove_owned_entries_tx(tx, off)?;
    for f in owned::<FunctRec>(seg, &comp.own_functs, |f| &f.owner_next)? {
        crate::objects::funct::remove_funct_tx(tx, f)?;
    }
    for p in owned::<PinRec>(seg, &comp.own_pins, |p| &p.owner_next)? {
        super::pin::unlink_tx(tx, p)?;
        list::forget_alias::<PinRec>(tx, p)?;
        list::remove::<PinRec>(tx, &h.pins, p)?;
        tx.free_pair(PairPool::Pin, tx.rec::<PinRec>(p)?.hot.load(Relaxed))?;
        tx.free(BlockKind::Pin, p)?;
    }
    for p in owned::<ParamRec>(seg, &comp.own_params, |p| &p.owner_next)? {
        list::forget_alias::<ParamRec>(tx, p)?;
        list::remove::<ParamRec>(tx, &h.params, p)?;
        tx.free_pair(PairPool::Param, tx.rec::<ParamRec>(p)?.hot.load(Relaxed))?;
        tx.free(BlockKind::Param, p)?;
    }
    for r in owned::<RegionRec>(seg, &comp.own_regions, |r| &r.owner_next)? {
        let rec: &RegionRec = tx.rec(r)?;
        let blob = rec.blob.load(Relaxed);
        list::remove::<RegionRec>(tx, &h.regions, r)?;
        tx.free(BlockKind::Blob, blob)?;
        tx.free(BlockKind::Region, r)?;
    }
    tx.free(BlockKind::Blob, comp.args.load(Relaxed))?;
    let kind = ComponentKind::from_code(comp.kind.load(Relaxed));
    list::remove::<CompRec>(tx, &h.comps, off)?;
    tx.free(BlockKind::Comp, off)?;
    if kind == ComponentKind::User {
        super::owner::release(seg, off);
    }
    Ok(())
}

impl Component {
    /// The component's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The component's id (the `Owner` column of `show`).
    pub fn id(&self) -> i32 {
        self.id
    }

    /// The component's kind.
    pub fn kind(&self) -> ComponentKind {
        self.kind
    }

    /// The instance the component lives in.
    pub fn instance(&self) -> &Instance {
        &self.inst
    }

    pub(crate) fn offset(&self) -> u64 {
        self.off
    }

    /// Creates a pin with value zero (FALSE, 0, 0.0).
    pub fn pin<T: PinValue, D: Direction>(&self, name: &str) -> Result<Pin<T, D>> {
        self.pin_init(name, T::from_bits(0))
    }

    /// Creates a pin with an initial value.
    pub fn pin_init<T: PinValue, D: Direction>(&self, name: &str, init: T) -> Result<Pin<T, D>> {
        let off = self
            .inst
            .new_pin(self.off, name, T::HAL_TYPE, D::DIR, init.to_bits())?;
        Pin::new(&self.inst.seg, off)
    }

    /// Creates an input pin of type `port`: the reading end of a byte
    /// stream ([`crate::PortIn`]).
    pub fn port_in(&self, name: &str) -> Result<crate::PortIn> {
        let t = crate::types::HalType::Port;
        let off = self.inst.new_pin(self.off, name, t, crate::PinDir::In, 0)?;
        crate::PortIn::new(&self.inst.seg, off)
    }

    /// Creates an output pin of type `port`: the writing end of a byte
    /// stream ([`crate::PortOut`]).
    pub fn port_out(&self, name: &str) -> Result<crate::PortOut> {
        let t = crate::types::HalType::Port;
        let off = self
            .inst
            .new_pin(self.off, name, t, crate::PinDir::Out, 0)?;
        crate::PortOut::new(&self.inst.seg, off)
    }

    /// Creates a pin whose type is chosen at run time, initially zero.
    pub fn pin_raw<D: Direction>(&self, name: &str, t: crate::types::HalType) -> Result<RawPin<D>> {
        if t == crate::types::HalType::Port {
            return Err(crate::HalError::NotAPortMaker {
                name: name.to_string(),
            });
        }
        let off = self.inst.new_pin(self.off, name, t, D::DIR, 0)?;
        RawPin::new(&self.inst.seg, off, t)
    }

    /// Creates a parameter with an initial value.
    pub fn param<T: PinValue, A: ParamAccess>(&self, name: &str, init: T) -> Result<Param<T, A>> {
        let off = self
            .inst
            .new_param(self.off, name, T::HAL_TYPE, A::DIR, init.to_bits())?;
        Param::new(&self.inst.seg, off)
    }

    /// Creates a parameter whose type and access are chosen at run time,
    /// initially zero.
    pub fn param_raw(
        &self,
        name: &str,
        t: crate::types::HalType,
        dir: crate::types::ParamDir,
    ) -> Result<RawParam> {
        let off = self.inst.new_param(self.off, name, t, dir, 0)?;
        RawParam::new(&self.inst.seg, off, t)
    }

    /// Records the `loadrt` arguments the component was loaded with, for
    /// `save`.
    pub fn set_loadrt_args(&self, args: &str) -> Result<()> {
        let comp_off = self.off;
        self.inst.tx(|tx| {
            let comp: &CompRec = tx.rec(comp_off)?;
            let old = comp.args.load(Relaxed);
            let (blob, rec) = tx.alloc_blob(args.len() as u64)?;
            let words = tx.blob_words(blob)?;
            for (i, chunk) in args.as_bytes().chunks(8).enumerate() {
                let mut w = [0u8; 8];
                w[..chunk.len()].copy_from_slice(chunk);
                words[i].store(u64::from_le_bytes(w), Relaxed);
            }
            rec.len.store(args.len() as u64, Relaxed);
            tx.set(&comp.args, blob)?;
            tx.free(BlockKind::Blob, old)
        })
    }

    /// Marks the component ready: `loadusr -W` and `waitusr` wait for this.
    pub fn ready(&self) -> Result<()> {
        self.set_ready(true)
    }

    /// Marks the component not ready again.
    pub fn unready(&self) -> Result<()> {
        self.set_ready(false)
    }

    fn set_ready(&self, ready: bool) -> Result<()> {
        let off = self.off;
        self.inst.tx(|tx| {
            let comp: &CompRec = tx.rec(off)?;
            tx.set(&comp.ready, ready as u64)
        })
    }
}

impl Drop for Component {
    fn drop(&mut self) {
        // Nothing useful can be done with an error here: the segment is
        // either gone (host exited) or corrupt.
        let _ = self.inst.remove_component(self.off);
    }
}

impl std::fmt::Debug for Component {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Component")
            .field("name", &self.name)
            .field("id", &self.id)
            .field("kind", &self.kind)
            .finish()
    }
}
