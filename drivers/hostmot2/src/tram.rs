//! TRAM, the per-cycle batched register transfer (hardware.md 5.8a): the
//! modules register the regions they read every `read` and write every
//! `write` while the board registers; each cycle moves them all in one
//! queued burst per direction, in registration order.
//!
//! As in LinuxCNC this is a software list, not the firmware's translation
//! RAM. A module keeps the [`Slot`] of each region and finds its words in
//! the contiguous read and write buffers at that slot.

use crate::transport::{Transport, TransportError};

/// Where a region's words sit in a TRAM buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Slot {
    /// First word in the buffer.
    pub start: usize,
    /// Words.
    pub words: usize,
}

impl Slot {
    /// The region's words in `buf`.
    #[inline]
    pub fn of<'a>(&self, buf: &'a [u32]) -> &'a [u32] {
        &buf[self.start..self.start + self.words]
    }

    /// The region's words in `buf`, writable.
    #[inline]
    pub fn of_mut<'a>(&self, buf: &'a mut [u32]) -> &'a mut [u32] {
        &mut buf[self.start..self.start + self.words]
    }
}

#[derive(Debug, Clone, Copy)]
struct Region {
    addr: u32,
    slot: Slot,
}

/// The regions and their buffers.
#[derive(Debug, Default)]
pub struct Tram {
    reads: Vec<Region>,
    writes: Vec<Region>,
    /// Words read this cycle, in region order.
    pub read_buf: Vec<u32>,
    /// Words to write this cycle, in region order.
    pub write_buf: Vec<u32>,
}

impl Tram {
    /// Registers a region read every cycle.
    pub fn add_read(&mut self, addr: u32, words: usize) -> Slot {
        let slot = Slot {
            start: self.read_buf.len(),
            words,
        };
        self.read_buf.resize(slot.start + words, 0);
        self.reads.push(Region { addr, slot });
        slot
    }

    /// Registers a region written every cycle.
    pub fn add_write(&mut self, addr: u32, words: usize) -> Slot {
        let slot = Slot {
            start: self.write_buf.len(),
            words,
        };
        self.write_buf.resize(slot.start + words, 0);
        self.writes.push(Region { addr, slot });
        slot
    }

    /// Moves the read region starting at buffer word `start` to `addr`
    /// (raw mode reads the address its pin names).
    #[inline]
    pub fn retarget_read(&mut self, start: usize, addr: u32) {
        if let Some(r) = self.reads.iter_mut().find(|r| r.slot.start == start) {
            r.addr = addr;
        }
    }

    /// Regions and words of each direction: (reads, read words, writes,
    /// write words), for [`Transport::reserve`].
    pub fn sizes(&self) -> (usize, usize, usize, usize) {
        (
            self.reads.len(),
            self.read_buf.len(),
            self.writes.len(),
            self.write_buf.len(),
        )
    }

    /// Queues every read region and sends the request (the first half
    /// of a cycle's read; `read-request` on a network board).
    pub fn request_reads(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.queue_reads(t)?;
        t.send_queued_reads()
    }

    /// Queues every read region without sending (the board adds its
    /// PktUART links' reads to the same burst).
    pub fn queue_reads(&self, t: &mut dyn Transport) -> Result<(), TransportError> {
        for r in &self.reads {
            t.queue_read(r.addr, r.slot.words)?;
        }
        Ok(())
    }

    /// Receives the requested regions into `read_buf`.
    pub fn receive_reads(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        t.receive_queued_reads(&mut self.read_buf)
    }

    /// Queues every write region from `write_buf` (the caller queues its
    /// other writes after these and sends them).
    pub fn queue_writes(&self, t: &mut dyn Transport) -> Result<(), TransportError> {
        for r in &self.writes {
            t.queue_write(r.addr, r.slot.of(&self.write_buf))?;
        }
        Ok(())
    }
}
