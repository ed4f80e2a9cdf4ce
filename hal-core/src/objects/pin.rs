//! Pins: creation, linking to signals, and access by name.

use std::sync::atomic::Ordering::*;

use super::list;
use super::Instance;
use crate::error::{HalError, Result};
use crate::name::validate;
use crate::shm::*;
use crate::types::{HalType, PinDir, Value};

pub(crate) fn pin_type(tx_seg: &Segment, p: &PinRec) -> Result<HalType> {
    HalType::from_code(p.type_code.load(Relaxed) as u32).ok_or_else(|| HalError::BadSegment {
        instance: tx_seg.instance().to_string(),
        reason: format!("pin '{}' has an unknown type code", p.name.get()),
    })
}

pub(crate) fn pin_dir(seg: &Segment, p: &PinRec) -> Result<PinDir> {
    PinDir::from_code(p.dir.load(Relaxed) as u32).ok_or_else(|| HalError::BadSegment {
        instance: seg.instance().to_string(),
        reason: format!("pin '{}' has an unknown direction", p.name.get()),
    })
}

/// Finds a pin by its name or, as LinuxCNC does, by its name before aliasing.
pub(crate) fn find_pin<'a>(seg: &'a Segment, name: &str) -> Result<Option<(u64, &'a PinRec)>> {
    list::find_aliased(seg, &seg.header().pins, name)
}

pub(crate) fn require_pin<'a>(seg: &'a Segment, name: &str) -> Result<(u64, &'a PinRec)> {
    find_pin(seg, name)?.ok_or_else(|| HalError::NotFound {
        kind: "pin",
        name: name.to_string(),
    })
}

/// Disconnects a pin; it keeps the signal's last value in its own cell.
pub(crate) fn unlink_tx(tx: &mut Txn<'_>, pin_off: u64) -> Result<()> {
    let seg = tx.seg();
    let pin: &PinRec = tx.rec(pin_off)?;
    let sig_off = pin.signal.load(Relaxed);
    if sig_off == 0 {
        return Ok(());
    }
    let sig: &SigRec = tx.rec(sig_off)?;
    let cell: &CellRec = tx.rec(sig.cell.load(Relaxed))?;
    let dir = pin_dir(seg, pin)?;
    let counter = match dir {
        PinDir::In => &sig.readers,
        PinDir::Out => &sig.writers,
        PinDir::Io => &sig.bidirs,
    };
    tx.set(counter, counter.load(Relaxed).saturating_sub(1))?;
    let w = pin.words(seg)?;
    // A pin keeps its signal's value; a port pin leaves the buffer with
    // the signal, so that it stays between one writer and one reader.
    let kept = match pin_type(seg, pin)? {
        HalType::Port => 0,
        _ => cell.value.load(Relaxed),
    };
    tx.set(&w.second, kept)?;
    tx.set(&w.first, seg.offset_of(&w.second))?;
    tx.set(&pin.signal, 0)?;
    // Off the signal's list of pins.
    let (prev, next) = (pin.sig_prev.load(Relaxed), pin.sig_next.load(Relaxed));
    match prev {
        0 => tx.set(&sig.first_pin, next)?,
        p => tx.set(&tx.rec::<PinRec>(p)?.sig_next, next)?,
    }
    if next != 0 {
        tx.set(&tx.rec::<PinRec>(next)?.sig_prev, prev)?;
    }
    tx.set(&pin.sig_prev, 0)?;
    tx.set(&pin.sig_next, 0)
}

/// Puts a pin that was just linked to signal `s` on the signal's list.
fn join_signal(tx: &mut Txn<'_>, pin_off: u64, pin: &PinRec, s: &SigRec) -> Result<()> {
    let first = s.first_pin.load(Relaxed);
    tx.set(&pin.sig_prev, 0)?;
    tx.set(&pin.sig_next, first)?;
    if first != 0 {
        tx.set(&tx.rec::<PinRec>(first)?.sig_prev, pin_off)?;
    }
    tx.set(&s.first_pin, pin_off)
}

pub(crate) fn new_pin_tx(
    tx: &mut Txn<'_>,
    comp: u64,
    name: &str,
    t: HalType,
    dir: PinDir,
    init: u64,
) -> Result<u64> {
    validate("pin", name)?;
    let seg = tx.seg();
    let h = tx.header();
    if find_pin(seg, name)?.is_some() {
        return Err(HalError::Duplicate {
            kind: "pin",
            name: name.to_string(),
        });
    }
    let (off, rec) = tx.alloc::<PinRec>(BlockKind::Pin)?;
    rec.name.init(name);
    rec.type_code.store(t.code() as u64, Relaxed);
    rec.dir.store(dir.code() as u64, Relaxed);
    rec.owner.store(comp, Relaxed);
    let hot = tx.alloc_pair(PairPool::Pin, 0, init)?;
    rec.hot.store(hot, Relaxed);
    let w = rec.words(seg)?;
    tx.set(&w.first, seg.offset_of(&w.second))?;
    list::insert_sorted(tx, &h.pins, off, rec)?;
    super::component::adopt(tx, comp, |c| &c.own_pins, &rec.owner_next, off)?;
    Ok(off)
}

impl Instance {
    pub(crate) fn new_pin(
        &self,
        comp: u64,
        name: &str,
        t: HalType,
        dir: PinDir,
        init: u64,
    ) -> Result<u64> {
        self.tx(|tx| new_pin_tx(tx, comp, name, t, dir, init))
    }

    /// Connects pin `pin` to signal `signal` (halcmd `linkps`), with
    /// LinuxCNC's rules: types match, at most one output pin per signal, no
    /// output pin together with I/O pins. Linking a pin to the signal it is
    /// already on is not an error.
    pub fn link(&self, pin: &str, signal: &str) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, "link")?;
        self.tx(|tx| {
            let seg = tx.seg();
            let (pin_off, p) = require_pin(seg, pin)?;
            let (sig_off, s) = super::signal::require_signal(seg, signal)?;
            let cur = p.signal.load(Relaxed);
            if cur == sig_off {
                return Ok(());
            }
            if cur != 0 {
                let other: &SigRec = tx.rec(cur)?;
                return Err(HalError::PinAlreadyLinked {
                    pin: p.name.get(),
                    signal: other.name.get(),
                });
            }
            let pt = pin_type(seg, p)?;
            let st = super::signal::sig_type(seg, s)?;
            if pt != st {
                return Err(HalError::TypeMismatch {
                    pin: p.name.get(),
                    pin_type: pt,
                    signal: s.name.get(),
                    signal_type: st,
                });
            }
            let dir = pin_dir(seg, p)?;
            let writers = s.writers.load(Relaxed);
            let bidirs = s.bidirs.load(Relaxed);
            if dir == PinDir::Out && writers > 0 {
                let writer = super::signal::writer_of(seg, sig_off)?.unwrap_or_default();
                return Err(HalError::SignalHasWriter {
                    signal: s.name.get(),
                    writer,
                    pin: p.name.get(),
                });
            }
            if dir == PinDir::Out && bidirs > 0 {
                return Err(HalError::SignalHasIoPins {
                    signal: s.name.get(),
                    pin: p.name.get(),
                });
            }
            if dir == PinDir::Io && writers > 0 {
                return Err(HalError::SignalHasOutputForIo {
                    signal: s.name.get(),
                    pin: p.name.get(),
                });
            }
            let port = st == HalType::Port;
            if port && (dir == PinDir::Io || (dir == PinDir::In && s.readers.load(Relaxed) > 0)) {
                return Err(HalError::PortSignalFull {
                    signal: s.name.get(),
                    pin: p.name.get(),
                });
            }
            let cell: &CellRec = tx.rec(s.cell.load(Relaxed))?;
            // The first pin on a fresh signal (or an output joining readers
            // only) gives the signal its initial value, as LinuxCNC does;
            // a port signal keeps its buffer.
            if !port
                && (dir != PinDir::In || s.readers.load(Relaxed) == 0)
                && writers == 0
                && bidirs == 0
            {
                tx.set(&cell.value, p.words(seg)?.second.load(Relaxed))?;
            }
            let counter = match dir {
                PinDir::In => &s.readers,
                PinDir::Out => &s.writers,
                PinDir::Io => &s.bidirs,
            };
            tx.set(counter, counter.load(Relaxed).saturating_add(1))?;
            tx.set(&p.signal, sig_off)?;
            tx.set(&p.words(seg)?.first, seg.offset_of(&cell.value))?;
            join_signal(tx, pin_off, p, s)
        })
    }

    /// Disconnects a pin from its signal (halcmd `unlinkp`). A pin that is
    /// not linked is left alone.
    pub fn unlink(&self, pin: &str) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, "unlink")?;
        self.tx(|tx| {
            let (off, _) = require_pin(tx.seg(), pin)?;
            unlink_tx(tx, off)
        })
    }

    /// Reads a pin's current value (the signal's, if linked).
    pub fn pin_value(&self, pin: &str) -> Result<Value> {
        self.tx(|tx| {
            let seg = tx.seg();
            let (_, p) = require_pin(seg, pin)?;
            let t = pin_type(seg, p)?;
            let w = seg.word(p.words(seg)?.first.load(Relaxed))?;
            Ok(Value::from_bits(t, w.load(Relaxed)))
        })
    }

    /// Sets an unconnected input or I/O pin (halcmd `setp` on a pin). The
    /// value must have the pin's type.
    pub fn set_pin(&self, pin: &str, value: Value) -> Result<()> {
        self.tx(|tx| {
            let seg = tx.seg();
            let (_, p) = require_pin(seg, pin)?;
            let t = pin_type(seg, p)?;
            if t != value.hal_type() {
                return Err(HalError::WrongType {
                    kind: "pin",
                    name: pin.to_string(),
                    expected: value.hal_type(),
                    actual: t,
                });
            }
            if t == HalType::Port {
                return Err(HalError::PortPinSet { pin: p.name.get() });
            }
            if pin_dir(seg, p)? == PinDir::Out {
                return Err(HalError::PinIsOutput { name: p.name.get() });
            }
            let sig = p.signal.load(Relaxed);
            if sig != 0 {
                let s: &SigRec = tx.rec(sig)?;
                return Err(HalError::PinConnected {
                    pin: p.name.get(),
                    signal: s.name.get(),
                });
            }
            // A value write, not a structural change: no journal needed.
            p.words(seg)?.second.store(value.to_bits(), Relaxed);
            Ok(())
        })
    }
}
