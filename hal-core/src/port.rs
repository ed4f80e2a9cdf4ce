//! HAL ports: pins of type `port`, a one-way byte stream from one output
//! pin to one input pin through a signal, as LinuxCNC 2.9 has them.
//!
//! A port signal holds no value but a buffer, made by `sets SIGNAL SIZE`
//! (once: a buffer's size never changes; allowed with the writer linked;
//! SIZE - 1 bytes fit, as in LinuxCNC) and kept for the instance's
//! life, as LinuxCNC keeps it. The signal's cell says where it is: the
//! size in bytes in its low 32 bits, the buffer's first word / 8 in the
//! high 32 bits (0 and 0 while no buffer is made). So `show` and `gets`
//! read the size as the value, and a pin finds the buffer through the
//! same slot and cell as any pin's value, following relinks.
//!
//! The buffer is two position words and the bytes: the reader's position
//! (how many bytes were ever taken) and the writer's (how many were ever
//! put), each written by one side only, so neither side waits for the
//! other or takes a lock. The writer fills bytes, then publishes its
//! position with release ordering; the reader reads the writer's position
//! with acquire ordering before the bytes it covers.

use std::sync::atomic::{AtomicU64, Ordering::*};
use std::sync::Arc;

use crate::error::{HalError, Result};
use crate::handles::{Direction, In, Out, Pin};
use crate::shm::{BlobRec, Segment, Txn};

/// The largest buffer `sets` makes (bytes): a port's bytes come out of
/// the instance's segment, which is a few MiB.
pub const MAX_PORT_SIZE: u32 = 1 << 20;

/// Words before the bytes: the reader's and the writer's positions.
const CTL_WORDS: u64 = 2;

/// The cell value of a port with `size` bytes whose buffer starts at
/// segment offset `off` (8-aligned).
pub(crate) fn encode(size: u32, off: u64) -> u64 {
    u64::from(size) | (off / 8) << 32
}

/// The size and buffer offset a port cell holds.
fn decode(bits: u64) -> (u64, u64) {
    (bits & 0xFFFF_FFFF, (bits >> 32) * 8)
}

/// Makes a buffer of `size` bytes in `tx`, its positions zero; the cell
/// value that names it.
pub(crate) fn alloc(tx: &mut Txn<'_>, size: u32) -> Result<u64> {
    let bytes = CTL_WORDS * 8 + u64::from(size).next_multiple_of(8);
    let (blob, _) = tx.alloc_blob(bytes)?;
    let data = blob + std::mem::size_of::<BlobRec>() as u64;
    for w in tx.seg().words(data, CTL_WORDS)? {
        tx.set(w, 0)?;
    }
    if data / 8 > u64::from(u32::MAX) {
        return Err(HalError::BadSegment {
            instance: tx.seg().instance().to_string(),
            reason: "a port buffer lies past what a port cell can name".into(),
        });
    }
    Ok(encode(size, data))
}

/// A port's buffer as one process sees it.
struct Buffer<'a> {
    read_pos: &'a AtomicU64,
    write_pos: &'a AtomicU64,
    bytes: &'a [AtomicU64],
    size: u64,
}

impl Buffer<'_> {
    /// Byte `i` (0..size) of the ring.
    fn byte(&self, i: u64) -> u8 {
        let w = self
            .bytes
            .get((i / 8) as usize)
            .map_or(0, |w| w.load(Relaxed));
        (w >> (8 * (i % 8))) as u8
    }

    /// Puts byte `b` at `i` (0..size). Only the writer stores into the
    /// bytes, so reading the word and storing it back changes nothing
    /// the reader has not yet taken but the byte itself.
    fn put(&self, i: u64, b: u8) {
        if let Some(w) = self.bytes.get((i / 8) as usize) {
            let shift = 8 * (i % 8);
            let v = w.load(Relaxed) & !(0xFF << shift) | u64::from(b) << shift;
            w.store(v, Relaxed);
        }
    }

    /// Bytes written and not yet read (the reader's view).
    fn readable(&self) -> u64 {
        let w = self.write_pos.load(Acquire);
        w.wrapping_sub(self.read_pos.load(Relaxed)).min(self.size)
    }

    /// Copies the `out.len()` oldest unread bytes, if there are that many.
    fn peek(&self, out: &mut [u8]) -> bool {
        let n = out.len() as u64;
        if n > self.readable() {
            return false;
        }
        let r = self.read_pos.load(Relaxed);
        for (k, b) in out.iter_mut().enumerate() {
            *b = self.byte(r.wrapping_add(k as u64) % self.size);
        }
        true
    }

    /// Drops the `n` oldest unread bytes, if there are that many.
    fn commit(&self, n: u64) -> bool {
        if n > self.readable() {
            return false;
        }
        let r = self.read_pos.load(Relaxed);
        self.read_pos.store(r.wrapping_add(n), Release);
        true
    }

    /// Room for bytes (the writer's view). A buffer of `size` bytes holds
    /// at most `size - 1`, as LinuxCNC's does (its ring keeps one byte
    /// free to tell full from empty): `sets p 9` gives 8 writable bytes.
    fn writable(&self) -> u64 {
        let r = self.read_pos.load(Acquire);
        let used = self.write_pos.load(Relaxed).wrapping_sub(r).min(self.size);
        (self.size - 1).saturating_sub(used)
    }

    /// Appends all of `src`, if there is room for all of it.
    fn write(&self, src: &[u8]) -> bool {
        let n = src.len() as u64;
        if n > self.writable() {
            return false;
        }
        let w = self.write_pos.load(Relaxed);
        for (k, b) in src.iter().enumerate() {
            self.put(w.wrapping_add(k as u64) % self.size, *b);
        }
        self.write_pos.store(w.wrapping_add(n), Release);
        true
    }
}

/// What both port handles hold: the pin, whose cell (its signal's, once
/// linked) names the buffer.
struct PortPin<D: Direction>(Pin<u64, D>);

impl<D: Direction> PortPin<D> {
    fn new(seg: &Arc<Segment>, off: u64) -> Result<PortPin<D>> {
        Pin::new(seg, off).map(PortPin)
    }

    /// The buffer of the signal the pin is on now; None while it has
    /// none (an unlinked pin, a signal not yet sized) or where the cell
    /// names no buffer inside the segment (only a corrupted one does).
    fn buffer(&self) -> Option<Buffer<'_>> {
        let seg = self.0.segment();
        let (size, off) = decode(self.0.get());
        // A buffer lies in the heap, past the header and the journal.
        if size == 0 || off < seg.cell_floor() {
            return None;
        }
        let words = seg.words(off, CTL_WORDS + size.div_ceil(8)).ok()?;
        let (ctl, bytes) = words.split_at(CTL_WORDS as usize);
        Some(Buffer {
            read_pos: &ctl[0],
            write_pos: &ctl[1],
            bytes,
            size,
        })
    }

    fn size(&self) -> u32 {
        self.buffer().map_or(0, |b| b.size as u32)
    }
}

/// The reading end of a port: an input pin of type `port`.
pub struct PortIn(PortPin<In>);

impl PortIn {
    pub(crate) fn new(seg: &Arc<Segment>, off: u64) -> Result<PortIn> {
        PortPin::new(seg, off).map(PortIn)
    }

    /// Bytes waiting to be read.
    pub fn readable(&self) -> u32 {
        self.0.buffer().map_or(0, |b| b.readable() as u32)
    }

    /// Takes exactly `out.len()` bytes, or nothing (false) when fewer wait.
    pub fn read(&self, out: &mut [u8]) -> bool {
        self.0
            .buffer()
            .is_some_and(|b| b.peek(out) && b.commit(out.len() as u64))
    }

    /// Copies exactly `out.len()` bytes without taking them, or nothing
    /// (false) when fewer wait.
    pub fn peek(&self, out: &mut [u8]) -> bool {
        self.0.buffer().is_some_and(|b| b.peek(out))
    }

    /// Takes `n` bytes already looked at with [`PortIn::peek`]; false
    /// (nothing taken) when fewer wait.
    pub fn peek_commit(&self, n: u32) -> bool {
        self.0.buffer().is_some_and(|b| b.commit(u64::from(n)))
    }

    /// Drops every waiting byte.
    pub fn clear(&self) {
        if let Some(b) = self.0.buffer() {
            b.commit(b.readable());
        }
    }

    /// The size of the buffer (0 while the pin's signal has none).
    pub fn buffer_size(&self) -> u32 {
        self.0.size()
    }
}

/// The writing end of a port: an output pin of type `port`.
pub struct PortOut(PortPin<Out>);

impl PortOut {
    pub(crate) fn new(seg: &Arc<Segment>, off: u64) -> Result<PortOut> {
        PortPin::new(seg, off).map(PortOut)
    }

    /// Room for bytes.
    pub fn writable(&self) -> u32 {
        self.0.buffer().map_or(0, |b| b.writable() as u32)
    }

    /// Appends all of `src`, or nothing (false) when there is not room
    /// for all of it.
    pub fn write(&self, src: &[u8]) -> bool {
        self.0.buffer().is_some_and(|b| b.write(src))
    }

    /// The size of the buffer (0 while the pin's signal has none).
    pub fn buffer_size(&self) -> u32 {
        self.0.size()
    }
}
