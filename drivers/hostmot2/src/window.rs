//! The transport over a memory window ([`RegWindow`]): a PCI board's BAR
//! mapped by the shared driver layer ([`hal_driver::bus::MmapWindow`]), or
//! a simulated board ([`hal_driver::sim::SimBoard`] around an
//! [`Hm2Model`](crate::sim::Hm2Model)). The driver cannot tell them apart.
//!
//! Memory-mapped registers need no batching: queued reads are read as the
//! receive asks for them, queued writes are written at once (posted PCI
//! writes keep their order). A burst whose accesses the window counted as
//! failed (a vanished device reads all ones) is reported as a bus error.

use hal_driver::bus::RegWindow;

use crate::transport::{check_window, ReadQueue, TransferStats, Transport, TransportError};

/// A [`Transport`] over a [`RegWindow`].
pub struct WindowTransport<W> {
    win: W,
    reads: ReadQueue,
    stats: TransferStats,
    errors: u64,
}

impl<W: RegWindow> WindowTransport<W> {
    /// A transport over `win`.
    pub fn new(win: W) -> WindowTransport<W> {
        let errors = win.errors();
        WindowTransport {
            win,
            reads: ReadQueue::default(),
            stats: TransferStats::default(),
            errors,
        }
    }

    /// The window.
    pub fn window(&self) -> &W {
        &self.win
    }

    /// A bus error if the window counted failed accesses since the last
    /// check.
    #[inline]
    fn check(&mut self) -> Result<(), TransportError> {
        let now = self.win.errors();
        if now != self.errors {
            self.errors = now;
            return Err(TransportError::Bus { count: now });
        }
        Ok(())
    }
}

impl<W: RegWindow> Transport for WindowTransport<W> {
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError> {
        check_window(addr, buf.len())?;
        self.win.read_burst(addr as usize, buf);
        self.stats.words_read += buf.len() as u64;
        self.stats.read_bursts += 1;
        self.check()
    }

    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        check_window(addr, data.len())?;
        self.win.write_burst(addr as usize, data);
        self.stats.words_written += data.len() as u64;
        self.stats.write_bursts += 1;
        self.check()
    }

    fn reserve(&mut self, reads: usize, _read_words: usize, _writes: usize, _write_words: usize) {
        self.reads.reserve(reads);
    }

    fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
        self.reads.push(addr, words)
    }

    fn send_queued_reads(&mut self) -> Result<(), TransportError> {
        Ok(())
    }

    fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError> {
        let win = &self.win;
        self.reads.receive(out, &mut self.stats, |addr, dst| {
            win.read_burst(addr as usize, dst)
        })?;
        self.check()
    }

    fn send_queued_writes(&mut self) -> Result<(), TransportError> {
        self.check()
    }

    fn stats(&self) -> TransferStats {
        self.stats
    }

    fn describe(&self) -> String {
        self.win.describe()
    }
}
