//! One PktUART reached only through its board's per-cycle bursts, for
//! realtime users (`hm2_modbus`): the board's `read` carries the link's
//! reads in its one read burst and hands their words over; its `write`
//! carries the writes the user staged since. The user never touches the
//! transport, so no period costs a round trip of its own (on hm2_eth
//! every immediate access is one).
//!
//! Per read burst the link adds, after the board's TRAM regions:
//!
//! 1. the transmitter's and the receiver's mode/status words;
//! 2. the receive-count pop, when the user asked for the next frame in
//!    the period before;
//! 3. or up to [`CHUNK_WORDS`] pops of that frame's data, once its count
//!    word (and so its size) came in the burst before; a longer frame
//!    drains over several bursts.
//!
//! So a frame the receiver holds at burst k is in the user's hands after
//! burst k + 2. (The status words are read before this burst's pops;
//! the frame count they show can include the frame being fetched, which
//! its user knows.) The writes (frame words and count, mode and bit-rate
//! words, clears) go out in the board's write burst of the same period,
//! in the order they were staged.
//!
//! A burst has a size limit on a network board (one datagram each way).
//! The link never makes the board's burst fail: what does not fit waits
//! for the next one (pops and staged writes, in order); if not even the
//! status words fit, that period has no status.

use super::config::{self, LineConfig};
use super::discovery::PktUartInstance;
use crate::regs::pktuart::{self as r, rcr};
use crate::transport::{Transport, TransportError};

/// Frame words popped per burst at most: a whole Modbus RTU frame (256
/// bytes). The largest frame allowed to send, too.
pub const CHUNK_WORDS: usize = 64;
/// Read entries (of one word each) a link adds to a burst at most: the
/// count, a chunk of data, the two status words.
pub const BURST_READS: usize = CHUNK_WORDS + 3;
/// Write entries (of one word each) a link stages per period at most: a
/// frame and its count, both directions' bit-rate and mode words, and
/// both clears, twice over (a clear and a resend in one period).
pub const BURST_WRITES: usize = 2 * (CHUNK_WORDS + 1 + 4 + 2);

/// Both mode/status words, as one burst read them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Status {
    /// The transmitter's mode/status word.
    pub tx_mode: u32,
    /// The receiver's mode/status word.
    pub rx_mode: u32,
}

impl Status {
    /// Whether the transmitter is still sending.
    pub fn tx_busy(&self) -> bool {
        self.tx_mode & r::tx::BUSY != 0
    }

    /// Frames in the receiver not yet asked for.
    pub fn rx_frames(&self) -> usize {
        r::nframes(self.rx_mode)
    }
}

/// Where the fetch of a received frame stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rx {
    /// No frame asked for.
    Idle,
    /// The next burst pops the count word.
    WantCount,
    /// The count came: `left` data words still to pop, `got` bytes kept.
    Data { count: u32, left: usize, got: usize },
    /// The whole frame is popped.
    Done { count: u32, got: usize },
    /// A burst carrying this frame's pops was lost: the frame is gone.
    Lost,
}

/// What the burst under way carries for this link, in this order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Carried {
    /// Status words (both, or fewer when the burst was full).
    status: usize,
    count: bool,
    data: usize,
}

impl Carried {
    fn words(&self) -> usize {
        self.status + usize::from(self.count) + self.data
    }
}

/// One PktUART's share of its board's bursts (see the module docs).
#[derive(Debug)]
pub struct PktUartLink {
    inst: PktUartInstance,
    status: Option<Status>,
    rx: Rx,
    carried: Option<Carried>,
    frame: [u8; CHUNK_WORDS * 4],
    /// Staged one-word writes (address, word); those before `sent` went
    /// out already.
    writes: [(u32, u32); BURST_WRITES],
    staged: usize,
    sent: usize,
}

impl PktUartLink {
    /// A link to `inst`, its buffers sized (load time).
    pub fn new(inst: PktUartInstance) -> PktUartLink {
        PktUartLink {
            inst,
            status: None,
            rx: Rx::Idle,
            carried: None,
            frame: [0; CHUNK_WORDS * 4],
            writes: [(0, 0); BURST_WRITES],
            staged: 0,
            sent: 0,
        }
    }

    /// The PktUART.
    pub fn instance(&self) -> &PktUartInstance {
        &self.inst
    }

    // ---- the user's side (the realtime function between read and write)

    /// The status words the last read burst brought, once: `None` when no
    /// burst arrived since the last call.
    pub fn take_status(&mut self) -> Option<Status> {
        self.status.take()
    }

    /// Whether a frame is being fetched.
    pub fn fetching(&self) -> bool {
        self.rx != Rx::Idle
    }

    /// Fetches the next received frame: the first call asks the next
    /// bursts for it, later calls give `None` until it is all in, then
    /// its count word and the bytes copied to `out` (at most `out`'s
    /// length, and at most [`CHUNK_WORDS`] words' worth). A lost burst
    /// gives [`TransportError::Lost`]: the frame is gone.
    pub fn fetch_frame(&mut self, out: &mut [u8]) -> Result<Option<(u32, usize)>, TransportError> {
        match self.rx {
            Rx::Idle => {
                self.rx = Rx::WantCount;
                Ok(None)
            }
            Rx::Done { count, got } => {
                self.rx = Rx::Idle;
                let n = got.min(out.len());
                out[..n].copy_from_slice(&self.frame[..n]);
                Ok(Some((count, n)))
            }
            Rx::Lost => {
                self.rx = Rx::Idle;
                Err(TransportError::Lost)
            }
            Rx::WantCount | Rx::Data { .. } => Ok(None),
        }
    }

    /// Stages both directions' bit-rate and mode words, then both clears
    /// when `flush`.
    pub fn configure(
        &mut self,
        rx: &LineConfig,
        tx: &LineConfig,
        flush: bool,
    ) -> Result<(), TransportError> {
        let i = &self.inst;
        let (rw, tw) = (
            config::rx_words(rx, i.clock_hz, i.rx_version),
            config::tx_words(tx, i.clock_hz, i.tx_version),
        );
        let (rxr, txr) = (i.rx, i.tx);
        self.stage(rxr[r::BITRATE], rw.bitrate)?;
        self.stage(rxr[r::MODE], rw.mode)?;
        self.stage(txr[r::BITRATE], tw.bitrate)?;
        self.stage(txr[r::MODE], tw.mode)?;
        if flush {
            self.clear()?;
        }
        Ok(())
    }

    /// Stages the abort of both directions, and forgets a fetch under
    /// way (the clear empties the FIFOs it was popping).
    pub fn clear(&mut self) -> Result<(), TransportError> {
        self.rx = Rx::Idle;
        self.stage(self.inst.tx[r::MODE], r::CLEAR)?;
        self.stage(self.inst.rx[r::MODE], r::CLEAR)
    }

    /// Stages one frame (at most [`CHUNK_WORDS`] words): its words, four
    /// bytes each, low byte first, then its size into the count FIFO.
    pub fn send(&mut self, frame: &[u8]) -> Result<(), TransportError> {
        if frame.len() > CHUNK_WORDS * 4 {
            return Err(TransportError::QueueFull {
                what: "PktUART frame (256 bytes at most)",
            });
        }
        let data = self.inst.tx[r::DATA];
        for chunk in frame.chunks(4) {
            let mut b = [0u8; 4];
            b[..chunk.len()].copy_from_slice(chunk);
            self.stage(data, u32::from_le_bytes(b))?;
        }
        self.stage(self.inst.tx[r::COUNT], frame.len() as u32)
    }

    /// Stages one write after the others.
    fn stage(&mut self, addr: u32, word: u32) -> Result<(), TransportError> {
        if self.staged == self.writes.len() && self.sent > 0 {
            // Move what is still waiting to the front.
            self.writes.copy_within(self.sent..self.staged, 0);
            self.staged -= self.sent;
            self.sent = 0;
        }
        let Some(slot) = self.writes.get_mut(self.staged) else {
            return Err(TransportError::QueueFull {
                what: "PktUART writes (the board's write burst did not run)",
            });
        };
        *slot = (addr, word);
        self.staged += 1;
        Ok(())
    }

    // ---- the board's side (its read and write functions)

    /// Queues this burst's reads (see the module docs), as many as the
    /// transport takes; returns the words they bring.
    pub fn queue_reads(&mut self, t: &mut dyn Transport) -> usize {
        let mut c = Carried::default();
        let rxr = self.inst.rx;
        for reg in [self.inst.tx[r::MODE], rxr[r::MODE]] {
            if t.queue_read(reg, 1).is_err() {
                break;
            }
            c.status += 1;
        }
        if c.status == 2 {
            match self.rx {
                Rx::WantCount => c.count = t.queue_read(rxr[r::COUNT], 1).is_ok(),
                Rx::Data { left, .. } => {
                    while c.data < left.min(CHUNK_WORDS) && t.queue_read(rxr[r::DATA], 1).is_ok() {
                        c.data += 1;
                    }
                }
                _ => {}
            }
        }
        self.carried = Some(c);
        c.words()
    }

    /// Words the burst under way carries for this link (0 if none).
    pub fn carried_words(&self) -> usize {
        self.carried.map_or(0, |c| c.words())
    }

    /// The words of the burst that carried [`queue_reads`](Self::queue_reads)'
    /// reads have come: takes them (exactly that many).
    pub fn take_reads(&mut self, words: &[u32]) {
        let Some(c) = self.carried.take() else {
            return;
        };
        let mut w = words.iter().copied();
        let mut next = || w.next().unwrap_or(0);
        let (tx_mode, rx_mode) = (next(), next());
        self.status = (c.status == 2).then_some(Status { tx_mode, rx_mode });
        if c.count {
            let count = next();
            if self.rx == Rx::WantCount {
                let size = (count & rcr::NBYTES_MASK) as usize;
                self.rx = Rx::Data {
                    count,
                    left: size.div_ceil(4),
                    got: 0,
                };
            }
        }
        for _ in 0..c.data {
            let word = next();
            if let Rx::Data { count, left, got } = &mut self.rx {
                let size = (*count & rcr::NBYTES_MASK) as usize;
                for b in word.to_le_bytes() {
                    if *got < size && *got < self.frame.len() {
                        self.frame[*got] = b;
                        *got += 1;
                    }
                }
                *left -= 1;
            }
        }
        if let Rx::Data {
            count,
            left: 0,
            got,
        } = self.rx
        {
            self.rx = Rx::Done { count, got };
        }
    }

    /// The burst that carried this link's reads was lost: a frame whose
    /// words it popped is gone, and no status came.
    pub fn reads_lost(&mut self) {
        let Some(c) = self.carried.take() else {
            return;
        };
        if c.count || c.data > 0 {
            self.rx = Rx::Lost;
        }
        self.status = None;
    }

    /// Queues the staged writes into the board's write burst, in order,
    /// as many as the transport takes; the rest wait for the next burst.
    pub fn queue_writes(&mut self, t: &mut dyn Transport) {
        while let Some(&(addr, word)) = self.writes[..self.staged].get(self.sent) {
            if t.queue_write(addr, &[word]).is_err() {
                return;
            }
            self.sent += 1;
        }
        self.staged = 0;
        self.sent = 0;
    }
}

impl PktUartLink {
    /// One period of this link alone over `t`, as a board carries it:
    /// the read burst, `between` (the user's step), the write burst. For
    /// tests and benches without a board; `t` must have room for
    /// [`BURST_READS`] queued reads.
    pub fn run_period(
        &mut self,
        t: &mut dyn Transport,
        between: impl FnOnce(&mut PktUartLink),
    ) -> Result<(), TransportError> {
        let n = self.queue_reads(t);
        let mut words = [0; BURST_READS];
        let got = t
            .send_queued_reads()
            .and_then(|()| t.receive_queued_reads(&mut words[..n]));
        match got {
            Ok(()) => self.take_reads(&words[..n]),
            Err(_) => self.reads_lost(),
        }
        between(self);
        self.queue_writes(t);
        t.send_queued_writes()?;
        got
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::{ReadQueue, TransferStats};

    /// A transport answering queued reads from a script and keeping the
    /// queued writes; immediate accesses are refused.
    #[derive(Default)]
    struct Script {
        reads: ReadQueue,
        answers: Vec<u32>,
        log: Vec<(u32, usize)>,
        written: Vec<(u32, u32)>,
        /// Queued reads and writes a burst takes (none: any number).
        room: Option<(usize, usize)>,
    }

    impl Transport for Script {
        fn read(&mut self, _: u32, _: &mut [u32]) -> Result<(), TransportError> {
            Err(TransportError::Lost)
        }
        fn write(&mut self, _: u32, _: &[u32]) -> Result<(), TransportError> {
            Err(TransportError::Lost)
        }
        fn reserve(&mut self, reads: usize, _: usize, _: usize, _: usize) {
            self.reads.reserve(reads);
        }
        fn queue_read(&mut self, addr: u32, words: usize) -> Result<(), TransportError> {
            if self.room.is_some_and(|(r, _)| self.log.len() >= r) {
                return Err(TransportError::QueueFull { what: "reads" });
            }
            self.log.push((addr, words));
            self.reads.push(addr, words)
        }
        fn send_queued_reads(&mut self) -> Result<(), TransportError> {
            Ok(())
        }
        fn receive_queued_reads(&mut self, out: &mut [u32]) -> Result<(), TransportError> {
            let mut answers = std::mem::take(&mut self.answers).into_iter();
            let mut stats = TransferStats::default();
            self.reads.receive(out, &mut stats, |_, dst| {
                dst.fill_with(|| answers.next().unwrap_or(0))
            })
        }
        fn queue_write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
            if self.room.is_some_and(|(_, w)| self.written.len() >= w) {
                return Err(TransportError::QueueFull { what: "writes" });
            }
            self.written.extend(data.iter().map(|&d| (addr, d)));
            Ok(())
        }
        fn send_queued_writes(&mut self) -> Result<(), TransportError> {
            Ok(())
        }
        fn stats(&self) -> TransferStats {
            TransferStats::default()
        }
        fn describe(&self) -> String {
            "script".into()
        }
    }

    fn inst() -> PktUartInstance {
        PktUartInstance {
            name: "b.pktuart.0".into(),
            index: 0,
            tx: [0x100, 0x104, 0x108, 0x10C],
            rx: [0x200, 0x204, 0x208, 0x20C],
            clock_hz: 100_000_000,
            tx_version: 3,
            rx_version: 3,
        }
    }

    fn burst(l: &mut PktUartLink, t: &mut Script, answers: &[u32]) {
        t.log.clear();
        let n = l.queue_reads(t);
        t.answers = answers.to_vec();
        let mut out = vec![0; n];
        t.receive_queued_reads(&mut out).unwrap();
        l.take_reads(&out);
    }

    #[test]
    fn a_frame_comes_in_over_two_bursts_after_it_is_asked_for() {
        let mut t = Script::default();
        t.reserve(BURST_READS, 0, 0, 0);
        let mut l = PktUartLink::new(inst());
        burst(&mut l, &mut t, &[0, 1 << 16]);
        assert_eq!(t.log, vec![(0x10C, 1), (0x20C, 1)], "status only");
        let s = l.take_status().unwrap();
        assert_eq!((s.tx_busy(), s.rx_frames()), (false, 1));
        assert_eq!(l.take_status(), None, "taken once");
        let mut out = [0u8; 8];
        assert_eq!(l.fetch_frame(&mut out), Ok(None));
        burst(&mut l, &mut t, &[0, 1 << 16, 5]);
        assert_eq!(t.log[2], (0x204, 1), "the count pop after the status");
        assert_eq!(l.fetch_frame(&mut out), Ok(None));
        burst(&mut l, &mut t, &[0, 0, 0x0403_0201, 0x05]);
        assert_eq!(t.log[2..], [(0x200, 1), (0x200, 1)], "two data pops");
        assert_eq!(l.fetch_frame(&mut out), Ok(Some((5, 5))));
        assert_eq!(out[..5], [1, 2, 3, 4, 5]);
        assert!(!l.fetching());
    }

    #[test]
    fn a_lost_burst_loses_the_frame_and_writes_keep_their_order() {
        let mut t = Script::default();
        t.reserve(BURST_READS, 0, 0, 0);
        let mut l = PktUartLink::new(inst());
        let mut out = [0u8; 8];
        l.fetch_frame(&mut out).unwrap();
        l.queue_reads(&mut t);
        l.reads_lost();
        assert_eq!(l.take_status(), None);
        assert_eq!(l.fetch_frame(&mut out), Err(TransportError::Lost));
        l.send(&[1, 2, 3, 4, 5]).unwrap();
        l.clear().unwrap();
        l.queue_writes(&mut t);
        assert_eq!(
            t.written,
            vec![
                (0x100, 0x0403_0201),
                (0x100, 5),
                (0x104, 5),
                (0x10C, r::CLEAR),
                (0x20C, r::CLEAR)
            ]
        );
        assert!(l.send(&[0; 257]).is_err(), "over 256 bytes");
    }

    #[test]
    fn what_a_full_burst_cannot_take_waits_for_the_next() {
        let mut t = Script::default();
        t.reserve(BURST_READS, 0, 0, 0);
        let mut l = PktUartLink::new(inst());
        let mut out = [0u8; 16];
        // Room for the status and one data pop a burst.
        t.room = Some((3, 2));
        l.fetch_frame(&mut out).unwrap();
        burst(&mut l, &mut t, &[0, 1 << 16, 9]);
        burst(&mut l, &mut t, &[0, 0, 0x0403_0201]);
        assert_eq!(l.fetch_frame(&mut out), Ok(None), "two words left");
        burst(&mut l, &mut t, &[0, 0, 0x0807_0605]);
        burst(&mut l, &mut t, &[0, 0, 0x09]);
        assert_eq!(l.fetch_frame(&mut out), Ok(Some((9, 9))));
        assert_eq!(out[..9], [1, 2, 3, 4, 5, 6, 7, 8, 9]);
        // No room even for the status: no status that period.
        t.room = Some((1, 2));
        burst(&mut l, &mut t, &[0]);
        assert_eq!(l.take_status(), None);
        // A 5-byte frame and its count: three writes, two a burst.
        l.send(&[1, 2, 3, 4, 5]).unwrap();
        l.queue_writes(&mut t);
        assert_eq!(t.written, [(0x100, 0x0403_0201), (0x100, 5)]);
        t.written.clear();
        l.queue_writes(&mut t);
        assert_eq!(t.written, [(0x104, 5)], "the count follows");
        t.written.clear();
        l.queue_writes(&mut t);
        assert!(t.written.is_empty());
    }
}
