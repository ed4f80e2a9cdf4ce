//! One PktUART reached only through its board's per-cycle bursts, for
//! realtime users (`hm2_modbus`): the board's `read` carries the link's
//! reads in its one read burst and hands their words over; its `write`
//! carries the writes the user staged since. The user never touches the
//! transport, so no period costs a round trip of its own (on hm2_eth
//! every immediate access is one).
//!
//! Per read burst the link adds, after the board's TRAM regions:
//!
//! 1. the receive-count pop, when the user asked for the next frame in
//!    the period before;
//! 2. up to [`CHUNK_WORDS`] pops of that frame's data, once its count
//!    word (and so its size) came in the burst before; a longer frame
//!    drains over several bursts;
//! 3. the transmitter's and the receiver's mode/status words, read last
//!    so they show the FIFOs after this burst's pops.
//!
//! So a frame the receiver holds at burst k is in the user's hands after
//! burst k + 2. The writes (frame words and count, mode and bit-rate
//! words, clears) go out in the board's write burst of the same period,
//! in the order they were staged.

use super::config::{self, LineConfig};
use super::discovery::PktUartInstance;
use crate::regs::pktuart::{self as r, rcr};
use crate::transport::{Transport, TransportError, WriteQueue};

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

/// What the burst under way carries for this link.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Carried {
    count: bool,
    data: usize,
}

impl Carried {
    fn words(&self) -> usize {
        usize::from(self.count) + self.data + 2
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
    writes: WriteQueue,
}

impl PktUartLink {
    /// A link to `inst`, its buffers sized (load time).
    pub fn new(inst: PktUartInstance) -> PktUartLink {
        let mut writes = WriteQueue::default();
        writes.reserve(BURST_WRITES, BURST_WRITES);
        PktUartLink {
            inst,
            status: None,
            rx: Rx::Idle,
            carried: None,
            frame: [0; CHUNK_WORDS * 4],
            writes,
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
        self.writes.push(rxr[r::BITRATE], &[rw.bitrate])?;
        self.writes.push(rxr[r::MODE], &[rw.mode])?;
        self.writes.push(txr[r::BITRATE], &[tw.bitrate])?;
        self.writes.push(txr[r::MODE], &[tw.mode])?;
        if flush {
            self.clear()?;
        }
        Ok(())
    }

    /// Stages the abort of both directions, and forgets a fetch under
    /// way (the clear empties the FIFOs it was popping).
    pub fn clear(&mut self) -> Result<(), TransportError> {
        self.rx = Rx::Idle;
        self.writes.push(self.inst.tx[r::MODE], &[r::CLEAR])?;
        self.writes.push(self.inst.rx[r::MODE], &[r::CLEAR])
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
            self.writes.push(data, &[u32::from_le_bytes(b)])?;
        }
        self.writes
            .push(self.inst.tx[r::COUNT], &[frame.len() as u32])
    }

    // ---- the board's side (its read and write functions)

    /// Queues this burst's reads (see the module docs); returns the words
    /// they bring.
    pub fn queue_reads(&mut self, t: &mut dyn Transport) -> Result<usize, TransportError> {
        let mut c = Carried::default();
        let rxr = self.inst.rx;
        match self.rx {
            Rx::WantCount => {
                t.queue_read(rxr[r::COUNT], 1)?;
                c.count = true;
            }
            Rx::Data { left, .. } if left > 0 => {
                c.data = left.min(CHUNK_WORDS);
                for _ in 0..c.data {
                    t.queue_read(rxr[r::DATA], 1)?;
                }
            }
            _ => {}
        }
        t.queue_read(self.inst.tx[r::MODE], 1)?;
        t.queue_read(rxr[r::MODE], 1)?;
        self.carried = Some(c);
        Ok(c.words())
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
        self.status = Some(Status {
            tx_mode: next(),
            rx_mode: next(),
        });
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

    /// Queues the writes staged since the last call into the board's
    /// write burst, in order.
    pub fn queue_writes(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let r = self
            .writes
            .iter()
            .try_for_each(|(a, d)| t.queue_write(a, d));
        self.writes.clear();
        r
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
        let n = self.queue_reads(t)?;
        let mut words = [0; BURST_READS];
        let got = t
            .send_queued_reads()
            .and_then(|()| t.receive_queued_reads(&mut words[..n]));
        match got {
            Ok(()) => self.take_reads(&words[..n]),
            Err(_) => self.reads_lost(),
        }
        between(self);
        self.queue_writes(t)?;
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
        let n = l.queue_reads(t).unwrap();
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
        burst(&mut l, &mut t, &[5, 0, 0]);
        assert_eq!(t.log[0], (0x204, 1), "the count pop first");
        assert_eq!(l.fetch_frame(&mut out), Ok(None));
        burst(&mut l, &mut t, &[0x0403_0201, 0x05, 0, 0]);
        assert_eq!(t.log[..2], [(0x200, 1), (0x200, 1)], "two data pops");
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
        l.queue_reads(&mut t).unwrap();
        l.reads_lost();
        assert_eq!(l.take_status(), None);
        assert_eq!(l.fetch_frame(&mut out), Err(TransportError::Lost));
        l.send(&[1, 2, 3, 4, 5]).unwrap();
        l.clear().unwrap();
        l.queue_writes(&mut t).unwrap();
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
}
