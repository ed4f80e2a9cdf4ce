//! Signals and their value cells.
//!
//! A signal's value lives in a cell of its own. When a signal is deleted its
//! cell is not reused at once: a function in a running thread may have read
//! the cell's offset from a pin an instant before the pin was unlinked and
//! still write to it. Retired cells wait in limbo, tagged with the grace
//! epoch, until every running thread has passed a cycle boundary since.

use std::sync::atomic::Ordering::*;

use super::list;
use super::pin::pin_dir;
use super::Instance;
use crate::error::{HalError, Result};
use crate::name::validate;
use crate::shm::*;
use crate::types::{HalType, PinDir, Value};

pub(crate) fn sig_type(seg: &Segment, s: &SigRec) -> Result<HalType> {
    HalType::from_code(s.type_code.load(Relaxed) as u32).ok_or_else(|| HalError::BadSegment {
        instance: seg.instance().to_string(),
        reason: format!("signal '{}' has an unknown type code", s.name.get()),
    })
}

pub(crate) fn require_signal<'a>(seg: &'a Segment, name: &str) -> Result<(u64, &'a SigRec)> {
    list::find::<SigRec>(seg, &seg.header().signals, name)?.ok_or_else(|| HalError::NotFound {
        kind: "signal",
        name: name.to_string(),
    })
}

/// The pins on signal `sig_off`'s list, in the list's order.
fn linked_pins(seg: &Segment, sig_off: u64) -> Result<Vec<(u64, &PinRec)>> {
    let s: &SigRec = seg.rec(sig_off)?;
    let mut out = Vec::new();
    let mut cur = s.first_pin.load(Relaxed);
    while cur != 0 {
        let p: &PinRec = seg.rec(cur)?;
        if p.signal.load(Relaxed) != sig_off || out.len() as u64 > seg.size() / 64 {
            return Err(HalError::BadSegment {
                instance: seg.instance().to_string(),
                reason: format!("the pin list of signal '{}' is broken", s.name.get()),
            });
        }
        out.push((cur, p));
        cur = p.sig_next.load(Relaxed);
    }
    Ok(out)
}

/// Name of the output pin driving a signal, if any.
pub(crate) fn writer_of(seg: &Segment, sig_off: u64) -> Result<Option<String>> {
    for (_, p) in linked_pins(seg, sig_off)? {
        if pin_dir(seg, p)? == PinDir::Out {
            return Ok(Some(p.name.get()));
        }
    }
    Ok(None)
}

/// The smallest grace epoch any running thread has acknowledged.
pub(crate) fn min_seen_epoch(seg: &Segment) -> Result<u64> {
    let mut min = u64::MAX;
    for item in list::iter::<ThreadRec>(seg, &seg.header().threads) {
        let (_, t) = item?;
        min = min.min(t.seen_epoch.load(Acquire));
    }
    Ok(min)
}

/// Allocates a value cell, preferring retired cells whose grace has passed.
fn alloc_cell<'a>(tx: &mut Txn<'a>) -> Result<(u64, &'a CellRec)> {
    let seg = tx.seg();
    let h = tx.header();
    let safe = min_seen_epoch(seg)?;
    let mut prev = &h.limbo;
    let mut cur = prev.load(Relaxed);
    let mut budget = seg.size() / 64;
    while cur != 0 && budget > 0 {
        budget -= 1;
        let c: &CellRec = tx.rec(cur)?;
        let next = c.next.load(Relaxed);
        if c.epoch.load(Relaxed) <= safe {
            tx.set(prev, next)?;
            tx.set(&c.next, 0)?;
            return Ok((cur, c));
        }
        prev = &c.next;
        cur = next;
    }
    tx.alloc::<CellRec>(BlockKind::Cell)
}

/// Puts a cell in limbo with a fresh grace epoch.
fn retire_cell(tx: &mut Txn<'_>, cell_off: u64) -> Result<()> {
    let h = tx.header();
    let c: &CellRec = tx.rec(cell_off)?;
    let epoch = h.grace_epoch.load(Relaxed) + 1;
    tx.set(&h.grace_epoch, epoch)?;
    tx.set(&c.epoch, epoch)?;
    tx.set(&c.next, h.limbo.load(Relaxed))?;
    tx.set(&h.limbo, cell_off)
}

impl Instance {
    /// Creates a signal (halcmd `newsig`) with value zero.
    pub fn newsig(&self, name: &str, t: HalType) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, "signal_new")?;
        validate("signal", name)?;
        self.tx(|tx| {
            let seg = tx.seg();
            let h = tx.header();
            if list::find::<SigRec>(seg, &h.signals, name)?.is_some() {
                return Err(HalError::Duplicate {
                    kind: "signal",
                    name: name.to_string(),
                });
            }
            let (cell_off, cell) = alloc_cell(tx)?;
            tx.set(&cell.value, 0)?;
            let (off, rec) = tx.alloc::<SigRec>(BlockKind::Signal)?;
            rec.name.init(name);
            rec.type_code.store(t.code() as u64, Relaxed);
            rec.cell.store(cell_off, Relaxed);
            list::insert_sorted(tx, &h.signals, off, rec)
        })
    }

    /// Deletes a signal (halcmd `delsig`), unlinking every pin on it.
    pub fn delsig(&self, name: &str) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, "signal_delete")?;
        self.tx(|tx| {
            let (off, _) = require_signal(tx.seg(), name)?;
            delsig_tx(tx, off)
        })
    }

    /// Deletes every signal (halcmd `delsig all`).
    pub fn delsig_all(&self) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, "signal_delete")?;
        self.tx(|tx| {
            let seg = tx.seg();
            let all: Vec<u64> = list::iter::<SigRec>(seg, &seg.header().signals)
                .map(|r| r.map(|(o, _)| o))
                .collect::<Result<_>>()?;
            for off in all {
                delsig_tx(tx, off)?;
            }
            Ok(())
        })
    }

    /// Reads a signal's value (halcmd `gets`).
    pub fn signal_value(&self, name: &str) -> Result<Value> {
        self.tx(|tx| {
            let seg = tx.seg();
            let (_, s) = require_signal(seg, name)?;
            let cell: &CellRec = seg.rec(s.cell.load(Relaxed))?;
            Ok(Value::from_bits(
                sig_type(seg, s)?,
                cell.value.load(Relaxed),
            ))
        })
    }

    /// The type of a signal (halcmd `stype`).
    pub fn signal_type(&self, name: &str) -> Result<HalType> {
        self.tx(|tx| {
            let seg = tx.seg();
            sig_type(seg, require_signal(seg, name)?.1)
        })
    }

    /// Sets a signal that has no output pin (halcmd `sets`); a port
    /// signal is sized whether or not its writer is linked.
    pub fn set_signal(&self, name: &str, value: Value) -> Result<()> {
        self.tx(|tx| {
            let seg = tx.seg();
            let (off, s) = require_signal(seg, name)?;
            let t = sig_type(seg, s)?;
            if t != value.hal_type() {
                return Err(HalError::WrongType {
                    kind: "signal",
                    name: name.to_string(),
                    expected: value.hal_type(),
                    actual: t,
                });
            }
            // A port's value is its buffer, which no writer drives: as in
            // LinuxCNC, `sets` sizes it with the writer linked.
            if s.writers.load(Relaxed) > 0 && t != HalType::Port {
                return Err(HalError::SignalDriven {
                    signal: name.to_string(),
                    writer: writer_of(seg, off)?.unwrap_or_default(),
                });
            }
            let cell: &CellRec = seg.rec(s.cell.load(Relaxed))?;
            if let Value::Port(size) = value {
                return size_port(tx, cell, name, size);
            }
            cell.value.store(value.to_bits(), Relaxed);
            Ok(())
        })
    }
}

/// `sets` on a port signal: makes its buffer of `size` bytes, once.
fn size_port(tx: &mut Txn<'_>, cell: &CellRec, name: &str, size: u32) -> Result<()> {
    let current = Value::from_bits(HalType::Port, cell.value.load(Relaxed));
    if let Value::Port(have @ 1..) = current {
        return Err(HalError::PortAllocated {
            signal: name.to_string(),
            size: have,
        });
    }
    // LinuxCNC takes a size of 0 and makes no buffer.
    if size == 0 {
        return Ok(());
    }
    if size > crate::port::MAX_PORT_SIZE {
        return Err(HalError::BadPortSize {
            size,
            max: crate::port::MAX_PORT_SIZE,
        });
    }
    let bits = crate::port::alloc(tx, size)?;
    tx.set(&cell.value, bits)
}

fn delsig_tx(tx: &mut Txn<'_>, off: u64) -> Result<()> {
    let seg = tx.seg();
    let h = tx.header();
    let linked: Vec<u64> = linked_pins(seg, off)?.into_iter().map(|(o, _)| o).collect();
    for p in linked {
        super::pin::unlink_tx(tx, p)?;
    }
    let s: &SigRec = tx.rec(off)?;
    let cell = s.cell.load(Relaxed);
    list::remove::<SigRec>(tx, &h.signals, off)?;
    retire_cell(tx, cell)?;
    tx.free(BlockKind::Signal, off)
}

/// Pins linked to signal `off`, with their directions, in pin-name order.
pub(crate) fn pins_of(seg: &Segment, off: u64) -> Result<Vec<(String, PinDir)>> {
    let mut out = linked_pins(seg, off)?
        .into_iter()
        .map(|(_, p)| Ok((p.name.get(), pin_dir(seg, p)?)))
        .collect::<Result<Vec<_>>>()?;
    out.sort_unstable_by(|a, b| a.0.as_bytes().cmp(b.0.as_bytes()));
    Ok(out)
}
