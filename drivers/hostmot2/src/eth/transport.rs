//! The Ethernet transport: the hostmot2 core's [`Transport`] over LBP16
//! on a UDP socket `connect()`ed to one board (only its datagrams are
//! received), or on an in-process simulated board ([`super::link`]).
//!
//! # Each cycle
//!
//! `read-request` sends one datagram: every queued TRAM read, then the
//! bookkeeping of hostmot2-more.md 1.6 (the board's packet counter, a
//! new read tag written to space 4 0x10 and read back with the last write
//! tag). `read` waits for the one reply, at most the read timeout after
//! the request left (`packet-read-timeout`), so the realtime thread is
//! never held longer. `write` sends one datagram: every queued write and
//! a new write tag at space 4 0x14; it gets no reply.
//!
//! # Loss, lateness, duplicates
//!
//! A reply must have exactly the expected length and echo this cycle's
//! read tag; anything else (a late reply to an earlier cycle, a
//! duplicate, a short or long datagram) is discarded and the wait goes
//! on until the deadline. No good reply by then is a packet error
//! ([`PacketErrors`]): the cycle's inputs are skipped
//! ([`TransportError::Lost`]) and the next `write` rewrites the whole
//! configuration (in case the lost traffic carried some of it). A reply
//! whose write tag is not the last one sent reveals a lost write: its
//! data is used, and it counts as an error and rewrites the
//! configuration too. At `packet-error-limit` the transport reports
//! [`TransportError::PacketErrors`] and the board stops.
//!
//! Two deliberate differences from LinuxCNC: a stale reply is never
//! copied into the cycle's data (LinuxCNC copies it before checking the
//! tag), and a reply whose tag does not match is never accepted after
//! the deadline (LinuxCNC accepts it silently).
//!
//! # Outside the cycle
//!
//! Registration and tools read with [`Transport::read`]: one datagram
//! per read, tagged through the space-6 scratch word so a late answer to
//! an earlier read can never be taken for this one; up to four tries
//! of 250 ms each, then [`TransportError::NoReply`] naming the board's
//! address. Plain writes are one datagram each, without reply.

use std::io;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::{HalHost, Ours};

use super::errors::PacketErrors;
use super::link::{Link, SharedEthBoard, SimLink};
use crate::lbp16::{self, addr, space, Command, Request, Width};
use crate::transport::{ReadQueue, TransferStats, Transport, TransportError};

/// How long a read outside the cycle waits for its reply.
pub const SINGLE_TIMEOUT: Duration = Duration::from_millis(250);
/// Tries of a read outside the cycle.
pub const SINGLE_TRIES: u32 = 4;
/// How long the first cycle's reply may take while the board registers
/// (no thread runs yet, so nothing waits on it).
pub const REGISTRATION_TIMEOUT: Duration = Duration::from_secs(1);
/// Bytes of cycle bookkeeping in a read reply: the packet counter (2),
/// the read tag (4) and the write tag (4).
const BOOKKEEPING_REPLY: usize = 10;

/// What a datagram that came while a cycle waited for its reply is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    /// This cycle's reply; `lost_write` when its write tag shows that a
    /// write datagram never arrived.
    Ours {
        /// A write was lost.
        lost_write: bool,
    },
    /// Not this cycle's reply (late, duplicated, malformed or foreign):
    /// discarded.
    Foreign,
}

/// Bytes of the reply to a cycle's request of `words` words.
pub fn reply_len(words: usize) -> usize {
    4 * words + BOOKKEEPING_REPLY
}

/// Classifies `reply` for a cycle that read `words` words with
/// `read_tag`, after the write tagged `write_tag` (none before the
/// first write): only a datagram of exactly the expected length that
/// echoes this cycle's read tag is its reply.
pub fn classify(reply: &[u8], words: usize, read_tag: u32, write_tag: Option<u32>) -> Reply {
    let n = reply_len(words);
    if reply.len() != n || reply[n - 8..n - 4] != read_tag.to_le_bytes() {
        return Reply::Foreign;
    }
    Reply::Ours {
        lost_write: write_tag.is_some_and(|t| reply[n - 4..n] != t.to_le_bytes()),
    }
}

/// Copies the data words at the start of a reply into `out`.
#[inline]
pub fn copy_words(reply: &[u8], out: &mut [u32]) {
    for (w, b) in out.iter_mut().zip(reply.chunks_exact(4)) {
        *w = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    }
}

/// Datagrams and bytes moved, for benchmarks.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Datagrams sent.
    pub sent: u64,
    /// Bytes sent (UDP payload).
    pub bytes_sent: u64,
    /// Datagrams received (stale ones included).
    pub received: u64,
    /// Bytes received (UDP payload).
    pub bytes_received: u64,
}

/// A board reached over UDP (or a simulated one, [`Link`]).
pub struct EthTransport<H: HalHost = Ours> {
    link: Link,
    peer: SocketAddr,
    name: String,
    reads: ReadQueue,
    request: Request,
    writes: Request,
    single: Request,
    reply: Box<[u8; 2048]>,
    /// The cycle's request went out at this time.
    sent_at: Option<Instant>,
    read_tag: u32,
    write_tag: u32,
    has_written: bool,
    scratch_tag: u16,
    period_ns: i64,
    errors: PacketErrors<H>,
    resync: bool,
    stats: TransferStats,
    traffic: Traffic,
}

impl<H: HalHost> std::fmt::Debug for EthTransport<H> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EthTransport")
            .field("peer", &self.peer)
            .field("errors", &self.errors)
            .finish()
    }
}

fn socket_error(op: &'static str, peer: SocketAddr, e: io::Error) -> TransportError {
    TransportError::Socket {
        op,
        peer: peer.to_string(),
        reason: e.to_string(),
    }
}

impl EthTransport {
    /// A socket connected to the board at `peer`. Its packet-error
    /// objects are made in the host the board registers in
    /// ([`into_host`](Self::into_host) moves it there first).
    pub fn connect(peer: SocketAddr) -> Result<EthTransport, TransportError> {
        let link = Link::udp(peer).map_err(|(op, e)| socket_error(op, peer, e))?;
        Ok(EthTransport::over(link, peer))
    }

    /// A transport to a simulated board in this process: its datagrams
    /// go to the board's LBP16 handler instead of a socket. `place` is
    /// the address the configuration gave, for messages only.
    pub fn simulated(board: Arc<SharedEthBoard>, place: SocketAddr) -> EthTransport {
        EthTransport::over(Link::Sim(SimLink::new(board)), place)
    }

    fn over(link: Link, peer: SocketAddr) -> EthTransport {
        EthTransport {
            link,
            peer,
            name: peer.to_string(),
            reads: ReadQueue::default(),
            request: Request::new(),
            writes: Request::new(),
            single: Request::new(),
            reply: Box::new([0; 2048]),
            sent_at: None,
            read_tag: 0,
            write_tag: 0,
            has_written: false,
            scratch_tag: 0,
            period_ns: 0,
            errors: PacketErrors::default(),
            resync: false,
            stats: TransferStats::default(),
            traffic: Traffic::default(),
        }
    }
}

impl<H: HalHost> EthTransport<H> {
    /// This transport for host `H2`, before its packet-error objects
    /// were made: a board probed at load, then registered in the host
    /// the driver was loaded into.
    pub fn into_host<H2: HalHost>(self) -> EthTransport<H2> {
        EthTransport {
            link: self.link,
            peer: self.peer,
            name: self.name,
            reads: self.reads,
            request: self.request,
            writes: self.writes,
            single: self.single,
            reply: self.reply,
            sent_at: self.sent_at,
            read_tag: self.read_tag,
            write_tag: self.write_tag,
            has_written: self.has_written,
            scratch_tag: self.scratch_tag,
            period_ns: self.period_ns,
            errors: self.errors.into_host(),
            resync: self.resync,
            stats: self.stats,
            traffic: self.traffic,
        }
    }

    /// The board's address.
    pub fn peer(&self) -> SocketAddr {
        self.peer
    }

    /// Names the board in messages (`7I96S at 192.168.1.121:27181`,
    /// `7I93 simulated at 10.10.10.10:27181`).
    pub fn set_name(&mut self, name: &str) {
        let how = if self.link.sim_board().is_some() {
            " simulated"
        } else {
            ""
        };
        self.name = format!("{name}{how} at {}", self.peer);
    }

    /// The simulated board behind this transport, if it is one.
    pub fn sim_board(&self) -> Option<&Arc<SharedEthBoard>> {
        self.link.sim_board()
    }

    /// The packet-error counter and its HAL objects.
    pub fn errors(&mut self) -> &mut PacketErrors<H> {
        &mut self.errors
    }

    /// Datagrams and bytes so far.
    pub fn traffic(&self) -> Traffic {
        self.traffic
    }

    #[inline]
    fn send(&mut self, which: Which) -> io::Result<()> {
        let bytes = match which {
            Which::Request => self.request.bytes(),
            Which::Writes => self.writes.bytes(),
            Which::Single => self.single.bytes(),
        };
        let n = self.link.send(bytes)?;
        self.traffic.sent += 1;
        self.traffic.bytes_sent += n as u64;
        Ok(())
    }

    /// Receives one datagram into `reply`, waiting until `deadline` at most.
    fn receive_until(&mut self, deadline: Instant) -> io::Result<usize> {
        let n = self.link.receive_until(&mut self.reply[..], deadline)?;
        self.traffic.received += 1;
        self.traffic.bytes_received += n as u64;
        Ok(n)
    }

    /// Counts a packet error: the cycle is skipped, or at the limit the
    /// board stops.
    #[inline]
    fn packet_error(&mut self) -> TransportError {
        self.resync = true;
        if self.errors.error() {
            TransportError::PacketErrors {
                level: self.errors.level(),
                limit: self.errors.limit(),
            }
        } else {
            TransportError::Lost
        }
    }

    /// Sends `single` (a request whose reply ends with the scratch echo)
    /// and returns the reply's length, trying up to [`SINGLE_TRIES`] times.
    fn exchange_single(&mut self) -> Result<usize, TransportError> {
        let expected = self.single.reply_len();
        let tag = self.scratch_tag;
        for _ in 0..SINGLE_TRIES {
            self.send(Which::Single)
                .map_err(|e| socket_error("sending to", self.peer, e))?;
            let deadline = Instant::now() + SINGLE_TIMEOUT;
            loop {
                match self.receive_until(deadline) {
                    Ok(n) if n == expected && self.reply[n - 2..n] == tag.to_le_bytes() => {
                        return Ok(n)
                    }
                    // Someone else's (late) answer: keep waiting.
                    Ok(_) => continue,
                    Err(e) if e.kind() == io::ErrorKind::TimedOut => break,
                    // Nobody listens at that port (ICMP port unreachable).
                    Err(e) if e.kind() == io::ErrorKind::ConnectionRefused => {
                        std::thread::sleep(Duration::from_millis(20));
                        break;
                    }
                    Err(e) => return Err(socket_error("receiving from", self.peer, e)),
                }
            }
        }
        Err(TransportError::NoReply {
            peer: self.peer.to_string(),
            attempts: SINGLE_TRIES,
            timeout_ms: SINGLE_TIMEOUT.as_millis() as u64,
        })
    }

    /// Appends the scratch tag to `single` (write, then read back).
    fn tag_single(&mut self) -> Result<(), TransportError> {
        self.scratch_tag = self.scratch_tag.wrapping_add(1);
        let full = TransportError::QueueFull {
            what: "single read",
        };
        self.single
            .write16(space::COMM_CTRL, addr::CTRL_SCRATCH, &[self.scratch_tag])
            .map_err(|_| full.clone())?;
        self.single
            .read16(space::COMM_CTRL, addr::CTRL_SCRATCH, 1)
            .map_err(|_| full)
    }

    /// Reads `out.len()` 16-bit words of `space` (its info area if
    /// `info`) from byte address `at`, outside the cycle.
    pub fn read16(
        &mut self,
        space: u8,
        info: bool,
        at: u16,
        out: &mut [u16],
    ) -> Result<(), TransportError> {
        self.single.clear();
        let count = out.len().min(lbp16::MAX_COUNT);
        let cmd = Command {
            info,
            ..Command::read(space, Width::W16, count as u8)
        };
        self.single
            .push_read(cmd, at)
            .map_err(|_| TransportError::QueueFull {
                what: "single read",
            })?;
        self.tag_single()?;
        self.exchange_single()?;
        for (i, w) in out[..count].iter_mut().enumerate() {
            *w = u16::from_le_bytes([self.reply[2 * i], self.reply[2 * i + 1]]);
        }
        Ok(())
    }

    /// Sends one datagram of the commands `build` pushes (plus the
    /// scratch tag, so it always has a reply) and returns the data of its
    /// reads, outside the cycle.
    pub fn exchange(
        &mut self,
        build: impl FnOnce(&mut Request) -> Result<(), lbp16::Full>,
    ) -> Result<&[u8], TransportError> {
        self.single.clear();
        build(&mut self.single).map_err(|_| TransportError::QueueFull {
            what: "single read",
        })?;
        self.tag_single()?;
        let n = self.exchange_single()?;
        Ok(&self.reply[..n - 2])
    }

    /// Writes 16-bit words to `space` at `at` in one datagram (no reply).
    pub fn write16(&mut self, space: u8, at: u16, words: &[u16]) -> Result<(), TransportError> {
        self.single.clear();
        self.single
            .write16(space, at, words)
            .map_err(|_| TransportError::QueueFull {
                what: "single write",
            })?;
        self.send(Which::Single)
            .map_err(|e| socket_error("sending to", self.peer, e))
    }
}

#[derive(Clone, Copy)]
enum Which {
    Request,
    Writes,
    Single,
}

impl<H: HalHost> Transport for EthTransport<H> {
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError> {
        crate::transport::check_window(addr, buf.len())?;
        // Up to 300 words per datagram (1200 bytes of reply).
        for (k, chunk) in buf.chunks_mut(300).enumerate() {
            let at = addr + 1200 * k as u32;
            self.single.clear();
            self.single
                .hm2_read(at, chunk.len())
                .map_err(|_| TransportError::QueueFull {
                    what: "single read",
                })?;
            self.tag_single()?;
            self.exchange_single()?;
            for (i, w) in chunk.iter_mut().enumerate() {
                let b = &self.reply[4 * i..4 * i + 4];
                *w = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            }
            self.stats.words_read += chunk.len() as u64;
            self.stats.read_bursts += 1;
        }
        Ok(())
    }

    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        crate::transport::check_window(addr, data.len())?;
        for (k, chunk) in data.chunks(300).enumerate() {
            self.single.clear();
            self.single
                .hm2_write(addr + 1200 * k as u32, chunk)
                .map_err(|_| TransportError::QueueFull {
                    what: "single write",
                })?;
            if self.send(Which::Single).is_err() {
                return Err(self.packet_error());
            }
            self.stats.words_written += chunk.len() as u64;
            self.stats.write_bursts += 1;
        }
        Ok(())
    }

    fn reserve(&mut self, reads: usize, _read_words: usize, _writes: usize, _write_words: usize) {
        // The datagrams have a fixed size; only the region list grows.
        self.reads.reserve(reads);
    }

    fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
        crate::transport::check_window(addr, words)?;
        let mark = self.request.mark();
        // Room for the bookkeeping stays: 14 request bytes, 10 reply bytes.
        self.request
            .hm2_read(addr, words)
            .map_err(|_| TransportError::QueueFull { what: "reads" })?;
        if self.request.bytes().len() + 18 > lbp16::MAX_REQUEST
            || self.request.reply_len() + BOOKKEEPING_REPLY > lbp16::MAX_REPLY
        {
            self.request.truncate(mark);
            return Err(TransportError::QueueFull { what: "reads" });
        }
        if let Err(e) = self.reads.push(addr, words) {
            self.request.truncate(mark);
            return Err(e);
        }
        Ok(())
    }

    fn send_queued_reads(&mut self) -> Result<(), TransportError> {
        self.read_tag = self.read_tag.wrapping_add(1);
        let tag = self.read_tag;
        let full = |_| TransportError::QueueFull { what: "reads" };
        let counter = Command {
            increment: false,
            ..Command::read(space::COMM_CTRL, Width::W16, 1)
        };
        self.request
            .push_read(counter, addr::CTRL_RX_PACKETS)
            .map_err(full)?;
        self.request
            .write16(
                space::TIMER,
                addr::TIMER_READ_TAG,
                &[tag as u16, (tag >> 16) as u16],
            )
            .map_err(full)?;
        self.request
            .read16(space::TIMER, addr::TIMER_READ_TAG, 4)
            .map_err(full)?;
        self.sent_at = None;
        let sent = self.send(Which::Request);
        self.request.clear();
        match sent {
            Ok(()) => {
                self.sent_at = Some(Instant::now());
                Ok(())
            }
            Err(_) => {
                self.reads.clear();
                Err(self.packet_error())
            }
        }
    }

    fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError> {
        let words = self.reads.words();
        let regions = self.reads.items().len();
        self.reads.clear();
        let Some(sent_at) = self.sent_at.take() else {
            // The request never left (its queue went with it): its error
            // is already counted, and this cycle's data is lost.
            return Err(TransportError::Lost);
        };
        if out.len() != words {
            return Err(TransportError::QueueMismatch {
                queued: words,
                got: out.len(),
            });
        }
        let timeout = if self.period_ns > 0 {
            Duration::from_nanos(self.errors.timeout_ns(self.period_ns))
        } else {
            REGISTRATION_TIMEOUT
        };
        let deadline = sent_at + timeout;
        let write_tag = self.has_written.then_some(self.write_tag);
        loop {
            let n = match self.receive_until(deadline) {
                Ok(n) => n,
                Err(_) => return Err(self.packet_error()),
            };
            let reply = &self.reply[..n];
            // Late, duplicated or malformed datagrams are not this
            // cycle's reply: wait on.
            let Reply::Ours { lost_write } = classify(reply, words, self.read_tag, write_tag)
            else {
                continue;
            };
            copy_words(reply, out);
            self.stats.words_read += words as u64;
            self.stats.read_bursts += regions as u64;
            if lost_write {
                // A write datagram never arrived: the data is good, the
                // configuration must be written again.
                return match self.packet_error() {
                    TransportError::Lost => Ok(()),
                    stop => Err(stop),
                };
            }
            self.errors.clean();
            return Ok(());
        }
    }

    fn queue_write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        crate::transport::check_window(addr, data.len())?;
        let mark = self.writes.mark();
        self.writes
            .hm2_write(addr, data)
            .map_err(|_| TransportError::QueueFull { what: "writes" })?;
        // Room for the write tag stays.
        if self.writes.bytes().len() + 8 > lbp16::MAX_REQUEST {
            self.writes.truncate(mark);
            return Err(TransportError::QueueFull { what: "writes" });
        }
        self.stats.words_written += data.len() as u64;
        self.stats.write_bursts += 1;
        Ok(())
    }

    fn send_queued_writes(&mut self) -> Result<(), TransportError> {
        let tag = self.write_tag.wrapping_add(1);
        if self
            .writes
            .write16(
                space::TIMER,
                addr::TIMER_WRITE_TAG,
                &[tag as u16, (tag >> 16) as u16],
            )
            .is_err()
        {
            self.writes.clear();
            return Err(TransportError::QueueFull { what: "writes" });
        }
        let sent = self.send(Which::Writes);
        self.writes.clear();
        match sent {
            Ok(()) => {
                self.write_tag = tag;
                self.has_written = true;
                Ok(())
            }
            Err(_) => match self.packet_error() {
                TransportError::Lost => Ok(()),
                stop => Err(stop),
            },
        }
    }

    fn stats(&self) -> TransferStats {
        self.stats
    }

    fn split_read(&self) -> bool {
        true
    }

    fn threadsafe(&self) -> bool {
        false
    }

    fn describe(&self) -> String {
        self.name.clone()
    }

    fn set_cycle_period(&mut self, period_ns: i64) {
        if period_ns != self.period_ns {
            self.link.set_period(period_ns);
        }
        self.period_ns = period_ns;
    }

    fn take_resync(&mut self) -> bool {
        std::mem::take(&mut self.resync)
    }

    fn recover(&mut self) {
        self.errors.reset();
        self.resync = false;
    }
}
