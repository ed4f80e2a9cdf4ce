//! The low-level transport: how the bus-independent core reaches a
//! board's registers (LinuxCNC's "llio" read/write and queue hooks).
//!
//! The core calls [`Transport::read`] and [`Transport::write`] while it
//! registers a board (IDROM, descriptors, configuration) and, once per
//! cycle, the queued forms: `read` queues every TRAM read region with
//! [`Transport::queue_read`], then [`Transport::send_queued_reads`] and
//! [`Transport::receive_queued_reads`]; `write` queues every write with
//! [`Transport::queue_write`] and ends with
//! [`Transport::send_queued_writes`]. So each direction is one burst per
//! cycle, which is what a network transport (hm2_eth, one UDP datagram
//! each way) needs; a memory-mapped transport simply performs the
//! accesses as they come. Module code only ever sees this trait.
//!
//! Transports never allocate in the queued calls: their queues have a
//! fixed capacity, set when the board is registered ([`Transport::reserve`]).

use thiserror::Error;

/// Why a transfer failed.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum TransportError {
    /// The access does not fit in the 64 KiB register window.
    #[error("access of {words} words at 0x{addr:05X} leaves the 64 KiB register window")]
    OutOfWindow {
        /// First byte address.
        addr: u32,
        /// Words.
        words: usize,
    },
    /// The bus reported failed accesses (a vanished PCI device reads all
    /// ones and counts an error).
    #[error("{count} bus errors (board gone or not answering)")]
    Bus {
        /// Failed accesses so far.
        count: u64,
    },
    /// More queued transfers than reserved.
    #[error("transfer queue full ({what})")]
    QueueFull {
        /// Which queue.
        what: &'static str,
    },
    /// The receive buffer does not match what was queued.
    #[error("receive buffer of {got} words for {queued} queued words")]
    QueueMismatch {
        /// Words queued.
        queued: usize,
        /// Buffer size.
        got: usize,
    },
    /// A network transfer of this cycle was lost, late or malformed and
    /// counted as a packet error: the cycle's inputs are skipped, the
    /// board keeps running.
    #[error("packet lost, late or malformed (counted as a packet error)")]
    Lost,
    /// Packet errors reached `packet-error-limit`: the board stops.
    #[error("packet-error-limit reached ({level} of {limit})")]
    PacketErrors {
        /// The error counter.
        level: i32,
        /// The limit.
        limit: i32,
    },
    /// An EPP cycle timed out: the board did not answer.
    #[error("EPP timeout at 0x{addr:04X} on the parallel port at {port:#x}: the board did not answer (cable, power, or the port not in EPP mode)")]
    EppTimeout {
        /// The burst's first byte address.
        addr: u32,
        /// The port's base address.
        port: u16,
    },
    /// A burst past the 15 address bits EPP carries.
    #[error(
        "access of {words} words at 0x{addr:05X} leaves the EPP address range (0x0000..0x7FFF)"
    )]
    EppRange {
        /// First byte address.
        addr: u32,
        /// Words.
        words: usize,
    },
    /// A board on the network never answered.
    #[error("no reply from {peer} ({attempts} requests, {timeout_ms} ms each)")]
    NoReply {
        /// The board's address.
        peer: String,
        /// Requests sent.
        attempts: u32,
        /// How long each waited, ms.
        timeout_ms: u64,
    },
    /// A socket operation failed.
    #[error("{op} {peer}: {reason}")]
    Socket {
        /// What was done ("sending to").
        op: &'static str,
        /// The board's address.
        peer: String,
        /// The system's words.
        reason: String,
    },
}

/// Register transfers counted by a transport, for benchmarks and tests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TransferStats {
    /// Words read.
    pub words_read: u64,
    /// Words written.
    pub words_written: u64,
    /// Separate read bursts (one per contiguous region).
    pub read_bursts: u64,
    /// Separate write bursts.
    pub write_bursts: u64,
}

/// How the core reaches a board's registers.
pub trait Transport: Send {
    /// Reads `buf.len()` words from byte address `addr` now.
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError>;
    /// Writes `data` to byte address `addr` now.
    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError>;
    /// Makes room for `reads` queued read regions of `read_words` words in
    /// all and `writes` queued writes of `write_words` words per cycle.
    /// Called while registering, before the first cycle.
    fn reserve(&mut self, reads: usize, read_words: usize, writes: usize, write_words: usize);
    /// Queues a read of `words` words at `addr` for this cycle.
    fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError>;
    /// Sends the queued reads (a network transport sends its request).
    fn send_queued_reads(&mut self) -> Result<(), TransportError>;
    /// Fills `out` with the data of every queued read, in queue order,
    /// and empties the queue.
    fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError>;
    /// Queues a write for this cycle. By default the write goes to the
    /// board at once: right for transports whose writes reach the
    /// registers directly (PCI window, EPP, SPI), which then only check
    /// the bus in `send_queued_writes`.
    fn queue_write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        self.write(addr, data)
    }
    /// Sends the queued writes and empties the queue.
    fn send_queued_writes(&mut self) -> Result<(), TransportError>;
    /// Transfers so far.
    fn stats(&self) -> TransferStats;
    /// Whether the read of a cycle is split into a request and a receive
    /// (LinuxCNC exports `read-request` for such boards).
    fn split_read(&self) -> bool {
        false
    }
    /// Whether transfers may come from more than one thread (LinuxCNC
    /// exports `read_gpio`/`write_gpio` only then).
    fn threadsafe(&self) -> bool {
        true
    }
    /// What the transport talks to, for messages (a PCI address, "simulated 5i25").
    fn describe(&self) -> String;
    /// The period of the thread that runs the cycle (the network
    /// transport's read timeout is a share of it). Called every `write`.
    fn set_cycle_period(&mut self, _period_ns: i64) {}
    /// Whether the board lost a write or a reply since the last call and
    /// its whole configuration should be written again (LinuxCNC's
    /// soft reset after a packet error).
    fn take_resync(&mut self) -> bool {
        false
    }
    /// The user cleared `io_error`: the transport forgets its failures.
    fn recover(&mut self) {}
}

/// Calls a [`CountingTransport`] saw, shared with whoever watches it.
#[derive(Debug, Default)]
pub struct CallCounts {
    /// Immediate reads ([`Transport::read`]): one round trip each on a
    /// network board.
    pub reads: std::sync::atomic::AtomicU64,
    /// Immediate writes ([`Transport::write`]).
    pub writes: std::sync::atomic::AtomicU64,
    /// Read bursts sent ([`Transport::send_queued_reads`]).
    pub read_bursts: std::sync::atomic::AtomicU64,
    /// Write bursts sent ([`Transport::send_queued_writes`]).
    pub write_bursts: std::sync::atomic::AtomicU64,
}

impl CallCounts {
    /// Immediate accesses so far (reads and writes).
    pub fn immediate(&self) -> u64 {
        use std::sync::atomic::Ordering::Relaxed;
        self.reads.load(Relaxed) + self.writes.load(Relaxed)
    }

    /// Bursts sent so far (read and write).
    pub fn bursts(&self) -> u64 {
        use std::sync::atomic::Ordering::Relaxed;
        self.read_bursts.load(Relaxed) + self.write_bursts.load(Relaxed)
    }
}

/// A transport that counts the calls made through it into a shared
/// [`CallCounts`] and otherwise passes everything on: tests and benches
/// use it to show that realtime code makes no immediate accesses.
pub struct CountingTransport<T> {
    inner: T,
    counts: std::sync::Arc<CallCounts>,
}

impl<T: Transport> CountingTransport<T> {
    /// Counts the calls to `inner`.
    pub fn new(inner: T) -> CountingTransport<T> {
        CountingTransport {
            inner,
            counts: Default::default(),
        }
    }

    /// The counters, to watch while the transport is in use.
    pub fn counts(&self) -> std::sync::Arc<CallCounts> {
        self.counts.clone()
    }
}

impl<T: Transport> Transport for CountingTransport<T> {
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError> {
        self.counts
            .reads
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.read(addr, buf)
    }
    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        self.counts
            .writes
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.write(addr, data)
    }
    fn reserve(&mut self, reads: usize, read_words: usize, writes: usize, write_words: usize) {
        self.inner.reserve(reads, read_words, writes, write_words);
    }
    fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
        self.inner.queue_read(addr, words)
    }
    fn send_queued_reads(&mut self) -> Result<(), TransportError> {
        self.counts
            .read_bursts
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.send_queued_reads()
    }
    fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError> {
        self.inner.receive_queued_reads(out)
    }
    fn queue_write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        self.inner.queue_write(addr, data)
    }
    fn send_queued_writes(&mut self) -> Result<(), TransportError> {
        self.counts
            .write_bursts
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.send_queued_writes()
    }
    fn stats(&self) -> TransferStats {
        self.inner.stats()
    }
    fn split_read(&self) -> bool {
        self.inner.split_read()
    }
    fn threadsafe(&self) -> bool {
        self.inner.threadsafe()
    }
    fn describe(&self) -> String {
        self.inner.describe()
    }
    fn set_cycle_period(&mut self, period_ns: i64) {
        self.inner.set_cycle_period(period_ns);
    }
    fn take_resync(&mut self) -> bool {
        self.inner.take_resync()
    }
    fn recover(&mut self) {
        self.inner.recover();
    }
}

/// Checks that `words` words at `addr` stay inside the register window.
#[inline]
pub fn check_window(addr: u32, words: usize) -> Result<(), TransportError> {
    let end = addr as u64 + 4 * words as u64;
    if addr % 4 != 0 || end > crate::regs::WINDOW_BYTES as u64 {
        return Err(TransportError::OutOfWindow { addr, words });
    }
    Ok(())
}

/// A fixed-capacity list of queued reads: (address, words).
#[derive(Debug, Default, Clone)]
pub struct ReadQueue {
    items: Vec<(u32, usize)>,
    words: usize,
}

impl ReadQueue {
    /// Makes room for `n` entries.
    pub fn reserve(&mut self, n: usize) {
        self.items.reserve(n.saturating_sub(self.items.len()));
    }

    /// Adds an entry without allocating.
    #[inline]
    pub fn push(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
        check_window(addr, words)?;
        if self.items.len() == self.items.capacity() {
            return Err(TransportError::QueueFull { what: "reads" });
        }
        self.items.push((addr, words));
        self.words += words;
        Ok(())
    }

    /// Words queued.
    #[inline]
    pub fn words(&self) -> usize {
        self.words
    }

    /// The entries, in order.
    #[inline]
    pub fn items(&self) -> &[(u32, usize)] {
        &self.items
    }

    /// Empties the queue, keeping its capacity.
    #[inline]
    pub fn clear(&mut self) {
        self.items.clear();
        self.words = 0;
    }

    /// Fills `out` with every queued read in order, each done by `read`
    /// (address, destination), counts them in `stats` and empties the
    /// queue; `out` must hold exactly the words queued.
    pub fn receive(
        &mut self,
        out: &mut [u32],
        stats: &mut TransferStats,
        mut read: impl FnMut(u32, &mut [u32]),
    ) -> Result<(), TransportError> {
        let queued = self.words;
        if out.len() != queued {
            self.clear();
            return Err(TransportError::QueueMismatch {
                queued,
                got: out.len(),
            });
        }
        let mut at = 0;
        for &(addr, n) in &self.items {
            read(addr, &mut out[at..at + n]);
            at += n;
        }
        stats.words_read += at as u64;
        stats.read_bursts += self.items.len() as u64;
        self.clear();
        Ok(())
    }
}

/// A fixed-capacity list of queued writes with their data.
#[derive(Debug, Default, Clone)]
pub struct WriteQueue {
    items: Vec<(u32, usize, usize)>,
    data: Vec<u32>,
}

impl WriteQueue {
    /// Makes room for `n` entries of `words` words in all.
    pub fn reserve(&mut self, n: usize, words: usize) {
        self.items.reserve(n.saturating_sub(self.items.len()));
        self.data.reserve(words.saturating_sub(self.data.len()));
    }

    /// Adds a write without allocating.
    #[inline]
    pub fn push(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        check_window(addr, data.len())?;
        if self.items.len() == self.items.capacity()
            || self.data.capacity() - self.data.len() < data.len()
        {
            return Err(TransportError::QueueFull { what: "writes" });
        }
        self.items.push((addr, self.data.len(), data.len()));
        self.data.extend_from_slice(data);
        Ok(())
    }

    /// The queued writes: (address, data), in order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &[u32])> {
        self.items
            .iter()
            .map(|&(a, start, n)| (a, &self.data[start..start + n]))
    }

    /// Empties the queue, keeping its capacity.
    #[inline]
    pub fn clear(&mut self) {
        self.items.clear();
        self.data.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queues_refuse_to_grow_in_realtime() {
        let mut r = ReadQueue::default();
        r.reserve(2);
        let cap = r.items.capacity();
        for i in 0..cap {
            r.push(0x1000 + 4 * i as u32, 1).unwrap();
        }
        assert_eq!(
            r.push(0x2000, 1),
            Err(TransportError::QueueFull { what: "reads" })
        );
        assert_eq!(r.words(), cap);
        r.clear();
        assert_eq!(r.words(), 0);

        let mut w = WriteQueue::default();
        w.reserve(1, 2);
        w.push(0x10, &[1, 2]).unwrap();
        assert!(w.push(0x20, &[1; 64]).is_err());
        assert_eq!(w.iter().collect::<Vec<_>>(), vec![(0x10, &[1u32, 2][..])]);
    }

    #[test]
    fn the_window_is_64_kib() {
        assert!(check_window(0xFFFC, 1).is_ok());
        assert!(check_window(0xFFFC, 2).is_err());
        assert!(check_window(0x0102, 1).is_err(), "unaligned");
        assert!(check_window(0x1_0000, 0).is_ok());
    }
}
