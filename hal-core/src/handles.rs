//! Typed pin and parameter handles for realtime code.
//!
//! A pin handle points at the pin's slot in the segment. The slot holds the
//! offset of the value cell in use (the pin's own, or its signal's once
//! linked), so `get` and `set` are one load of the slot plus one access to
//! the cell: no allocation, lock or system call. An offset that is not a
//! cell's stands for the first cell, so even a corrupted slot cannot make
//! the process touch memory outside the segment's cells.

use std::marker::PhantomData;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use crate::error::Result;
use crate::shm::{ParamRec, PinRec, Segment};
use crate::types::{ParamDir, PinDir, PinValue};

/// Marker for a pin direction.
pub trait Direction: Send + Sync + 'static {
    /// The direction this marker stands for.
    const DIR: PinDir;
}
/// Marker for directions the owning component writes.
pub trait Writable: Direction {}

/// Input pin marker.
pub struct In;
/// Output pin marker.
pub struct Out;
/// Bidirectional pin marker.
pub struct Io;
impl Direction for In {
    const DIR: PinDir = PinDir::In;
}
impl Direction for Out {
    const DIR: PinDir = PinDir::Out;
}
impl Direction for Io {
    const DIR: PinDir = PinDir::Io;
}
impl Writable for Out {}
impl Writable for Io {}

/// Marker for parameter access.
pub trait ParamAccess: Send + Sync + 'static {
    /// The access this marker stands for.
    const DIR: ParamDir;
}
/// Read-only parameter marker (only the component writes it).
pub struct Ro;
/// Read-write parameter marker.
pub struct Rw;
impl ParamAccess for Ro {
    const DIR: ParamDir = ParamDir::Ro;
}
impl ParamAccess for Rw {
    const DIR: ParamDir = ParamDir::Rw;
}

/// Where one process finds value cells: the mapping's address and the
/// range of offsets a cell may have. Whoever holds one keeps the mapping
/// alive.
#[derive(Clone, Copy)]
pub(crate) struct Cells {
    base: *const u8,
    /// The first offset a cell may have (8-aligned).
    floor: u64,
    /// How far past `floor` the last cell may start, in words.
    span_words: u64,
}

impl Cells {
    /// No cells: a placeholder while a mapping is being checked.
    pub(crate) const EMPTY: Cells = Cells {
        base: std::ptr::null(),
        floor: 0,
        span_words: 0,
    };

    pub(crate) fn new(seg: &Segment) -> Cells {
        // A segment too small for any cell past its journal (only a
        // malformed one can be) still keeps every access inside it.
        let limit = seg.cell_limit();
        let floor = seg.cell_floor().next_multiple_of(8).min(limit);
        Cells {
            base: seg.base(),
            floor,
            span_words: (limit - floor) / 8,
        }
    }

    /// The cell `slot` names; a slot naming anything but a cell (only a
    /// corrupted segment has one) names the first cell instead.
    #[inline(always)]
    pub(crate) fn cell(&self, slot: &AtomicU64) -> &AtomicU64 {
        let off = slot.load(Relaxed);
        // One compare checks range and alignment: rotated right by three,
        // a distance from the floor that is not a multiple of 8 keeps a
        // low bit at the top and so exceeds any span. The fallback is a
        // plain move, not a call, so the common path keeps its registers
        // and the cell's load issues right behind the slot's.
        let off = if off.wrapping_sub(self.floor).rotate_right(3) <= self.span_words {
            off
        } else {
            self.floor
        };
        // SAFETY: `off` lies in [floor, floor + 8 * span_words], is
        // 8-aligned, and floor + 8 * span_words <= size - 8, so the word
        // lies inside the mapping (kept alive by the holder), past the
        // header and journal; any bits are a valid AtomicU64.
        unsafe { &*(self.base.add(off as usize) as *const AtomicU64) }
    }
}

/// A pin of value type `T` and direction `D`: 16 bytes, the slot's
/// address and the mapping (whose [`Cells`] bounds every access), so that
/// a function's handles take few cache lines.
pub struct Pin<T: PinValue, D: Direction> {
    slot: *const AtomicU64,
    seg: Arc<Segment>,
    _marker: PhantomData<fn() -> (T, D)>,
}

// SAFETY: the handle only performs atomic accesses to shared memory that the
// Arc keeps mapped; sharing or sending it between threads is sound.
unsafe impl<T: PinValue, D: Direction> Send for Pin<T, D> {}
// SAFETY: as above.
unsafe impl<T: PinValue, D: Direction> Sync for Pin<T, D> {}

impl<T: PinValue, D: Direction> Pin<T, D> {
    pub(crate) fn new(seg: &Arc<Segment>, off: u64) -> Result<Self> {
        let rec: &PinRec = seg.rec(off)?;
        Ok(Pin {
            slot: &rec.words(seg)?.first,
            seg: seg.clone(),
            _marker: PhantomData,
        })
    }

    #[inline(always)]
    fn cell(&self) -> &AtomicU64 {
        // SAFETY: `slot` points into the mapping, which `seg` keeps alive.
        self.seg.cells().cell(unsafe { &*self.slot })
    }

    /// The mapping the pin lives in (for handles built on a pin, as the
    /// port handles are).
    pub(crate) fn segment(&self) -> &Segment {
        &self.seg
    }

    /// The pin's slot (for the executor's timing outputs).
    pub(crate) fn slot(&self) -> &AtomicU64 {
        // SAFETY: as in `cell`.
        unsafe { &*self.slot }
    }

    /// The pin's current value (its signal's, if linked).
    #[inline(always)]
    pub fn get(&self) -> T {
        T::from_bits(self.cell().load(Relaxed))
    }

    /// Writes the pin whatever its direction (its signal, if linked).
    #[inline(always)]
    pub(crate) fn store_any(&self, v: T) {
        self.cell().store(v.to_bits(), Relaxed)
    }
}

impl<T: PinValue, D: Writable> Pin<T, D> {
    /// Writes the pin (its signal, if linked).
    #[inline(always)]
    pub fn set(&self, v: T) {
        self.cell().store(v.to_bits(), Relaxed)
    }
}

impl<T: PinValue> Pin<T, In> {
    /// Writes an input pin. A few LinuxCNC components correct their own
    /// inputs (a limited frequency, a zero scale); this is for them.
    #[inline(always)]
    pub fn overwrite(&self, v: T) {
        self.cell().store(v.to_bits(), Relaxed)
    }

    /// Writes the pin's own cell, the value it reads while it is not
    /// linked to a signal, whether or not it is linked now. A linked pin
    /// keeps reading its signal. This is for components that supply an
    /// input's value only when nothing is connected (pid estimates
    /// `command-deriv` and `feedback-deriv` this way).
    #[inline(always)]
    pub fn set_unlinked(&self, v: T) {
        // SAFETY: a pin's own cell is the word after its slot in their
        // `Pair`, inside the mapping that `seg` keeps alive.
        unsafe { &*self.slot.add(1) }.store(v.to_bits(), Relaxed)
    }
}

/// A parameter of value type `T`. The owning component may always write it;
/// `A` says whether `setp` may.
pub struct Param<T: PinValue, A: ParamAccess> {
    value: *const AtomicU64,
    _seg: Arc<Segment>,
    _marker: PhantomData<fn() -> (T, A)>,
}

// SAFETY: as for Pin: atomic accesses to memory the Arc keeps mapped.
unsafe impl<T: PinValue, A: ParamAccess> Send for Param<T, A> {}
// SAFETY: as above.
unsafe impl<T: PinValue, A: ParamAccess> Sync for Param<T, A> {}

impl<T: PinValue, A: ParamAccess> Param<T, A> {
    pub(crate) fn new(seg: &Arc<Segment>, off: u64) -> Result<Self> {
        let rec: &ParamRec = seg.rec(off)?;
        Ok(Param {
            value: &rec.words(seg)?.first,
            _seg: seg.clone(),
            _marker: PhantomData,
        })
    }

    /// The parameter's value word (for the executor's timing outputs).
    pub(crate) fn word(&self) -> &AtomicU64 {
        // SAFETY: points into the mapping kept alive by `_seg`.
        unsafe { &*self.value }
    }

    /// The parameter's value.
    #[inline(always)]
    pub fn get(&self) -> T {
        // SAFETY: points into the mapping kept alive by `_seg`.
        T::from_bits(unsafe { &*self.value }.load(Relaxed))
    }

    /// Sets the parameter.
    #[inline(always)]
    pub fn set(&self, v: T) {
        // SAFETY: as in `get`.
        unsafe { &*self.value }.store(v.to_bits(), Relaxed)
    }
}

impl<T: PinValue + std::fmt::Debug, D: Direction> std::fmt::Debug for Pin<T, D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pin")
            .field("dir", &D::DIR)
            .field("value", &self.get())
            .finish()
    }
}

impl<T: PinValue + std::fmt::Debug, A: ParamAccess> std::fmt::Debug for Param<T, A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Param")
            .field("dir", &A::DIR)
            .field("value", &self.get())
            .finish()
    }
}

/// A pin whose type is chosen at run time (sampler and streamer columns):
/// it reads and writes the 64-bit cell encoding of [`crate::Value`].
pub struct RawPin<D: Direction> {
    inner: Pin<u64, D>,
    hal_type: crate::types::HalType,
}

/// The reading side shared by [`RawPin`] and [`RawParam`]: a typed handle
/// on a value cell, read as its cell encoding.
macro_rules! raw_reads {
    ($what:literal) => {
        #[doc = concat!("The ", $what, "'s type.")]
        pub fn hal_type(&self) -> crate::types::HalType {
            self.hal_type
        }

        /// The cell encoding of the current value.
        #[inline(always)]
        pub fn get_bits(&self) -> u64 {
            self.inner.get()
        }

        /// The current value.
        pub fn value(&self) -> crate::types::Value {
            crate::types::Value::from_bits(self.hal_type, self.get_bits())
        }
    };
}

impl<D: Direction> RawPin<D> {
    pub(crate) fn new(
        seg: &Arc<Segment>,
        off: u64,
        hal_type: crate::types::HalType,
    ) -> Result<Self> {
        Ok(RawPin {
            inner: Pin::new(seg, off)?,
            hal_type,
        })
    }

    raw_reads!("pin");
}

impl<D: Writable> RawPin<D> {
    /// Writes a cell encoding; it must be one of this pin's type (see
    /// [`crate::Value::to_bits`]).
    #[inline(always)]
    pub fn set_bits(&self, bits: u64) {
        self.inner.set(bits)
    }
}

impl RawPin<In> {
    /// Writes an input pin's cell encoding (its signal's, if linked), as
    /// [`Pin::overwrite`] does. LinuxCNC's Python components may write
    /// their own input pins; this is for them.
    #[inline(always)]
    pub fn overwrite_bits(&self, bits: u64) {
        self.inner.overwrite(bits)
    }
}

/// A parameter whose type and access are chosen at run time: it reads and
/// writes the 64-bit cell encoding of [`crate::Value`]. The owning
/// component may always write it.
pub struct RawParam {
    inner: Param<u64, Rw>,
    hal_type: crate::types::HalType,
}

impl RawParam {
    pub(crate) fn new(
        seg: &Arc<Segment>,
        off: u64,
        hal_type: crate::types::HalType,
    ) -> Result<Self> {
        Ok(RawParam {
            inner: Param::new(seg, off)?,
            hal_type,
        })
    }

    raw_reads!("parameter");

    /// Writes a cell encoding; it must be one of this parameter's type.
    #[inline(always)]
    pub fn set_bits(&self, bits: u64) {
        self.inner.set(bits)
    }
}

impl<T: PinValue, D: Direction> Clone for Pin<T, D> {
    /// Another handle on the same pin (every access is atomic, so handles
    /// may be shared by functions in different threads).
    fn clone(&self) -> Self {
        Pin {
            slot: self.slot,
            seg: self.seg.clone(),
            _marker: PhantomData,
        }
    }
}

impl<T: PinValue, A: ParamAccess> Clone for Param<T, A> {
    /// Another handle on the same parameter.
    fn clone(&self) -> Self {
        Param {
            value: self.value,
            _seg: self._seg.clone(),
            _marker: PhantomData,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ComponentKind, Host, HostConfig};

    #[test]
    fn a_corrupted_slot_stays_inside_the_segments_cells() {
        let host = Host::create(HostConfig::for_tests("handles-clamp")).unwrap();
        let c = host
            .instance()
            .new_component("clamp", ComponentKind::User)
            .unwrap();
        let pin: Pin<u32, Out> = c.pin("clamp.out").unwrap();
        pin.set(7);
        assert_eq!(pin.get(), 7);
        let cells = *pin.seg.cells();
        let first = cells.floor;
        let last = cells.floor + 8 * cells.span_words;
        let at = |p: &Pin<u32, Out>| p.cell() as *const AtomicU64 as usize - cells.base as usize;
        // SAFETY: the slot is in the mapping the handle keeps alive; the
        // test stands in for a process that scribbled over it.
        let slot = unsafe { &*pin.slot };
        let good = slot.load(Relaxed);
        for (bad, lands) in [
            (0, first),
            (3, first),
            (first + 3, first),
            (u64::MAX, first),
            (last + 8, first),
            (last + 3, first),
        ] {
            slot.store(bad, Relaxed);
            assert_eq!(at(&pin) as u64, lands, "slot {bad:#x}");
        }
        slot.store(last, Relaxed);
        assert_eq!(at(&pin) as u64, last, "the last cell is a cell");
        slot.store(good, Relaxed);
        assert_eq!(pin.get(), 7);
    }
}

/// Reads value cells whose offsets are held in shared words rather than
/// in a pin's slot: a probe that a tool in another process points at pins
/// and signals at run time (halscope's `scope_rt`). An offset that is not
/// a cell's reads the first cell, as a corrupted slot does, so garbage
/// offsets written by another process never reach outside the segment's
/// cells.
#[derive(Clone)]
pub struct CellReader {
    cells: Cells,
    _seg: Arc<Segment>,
}

// SAFETY: the reader only performs atomic loads of shared memory that the
// Arc keeps mapped; sharing or sending it between threads is sound.
unsafe impl Send for CellReader {}
// SAFETY: as above.
unsafe impl Sync for CellReader {}

impl CellReader {
    pub(crate) fn new(seg: &Arc<Segment>) -> CellReader {
        CellReader {
            cells: Cells::new(seg),
            _seg: seg.clone(),
        }
    }

    /// The cell encoding held by the cell at segment offset `off` (the
    /// first cell's when `off` names no cell). No allocation, lock or
    /// system call: callable from a realtime function.
    #[inline]
    pub fn read(&self, off: u64) -> u64 {
        let slot = AtomicU64::new(off);
        self.cells.cell(&slot).load(Relaxed)
    }
}
