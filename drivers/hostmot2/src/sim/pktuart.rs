//! Simulated PktUART pairs. The transmitter takes data words and frame
//! sizes into FIFOs and sends one frame at a time at the configured rate
//! (BUSY while a frame is queued or on the line); a sent frame goes to the
//! [`SerialPeer`] on the other end of the line, whose answers arrive in
//! the receiver's FIFOs after their time on the wire: the data words, and
//! one count word per frame with its size, error bits and longest
//! inter-character gap, as the core reports them. The clear word aborts a
//! direction and empties its FIFOs; popping an empty data FIFO sets the
//! receiver's BadPop bit.

use std::any::Any;
use std::collections::VecDeque;

use crate::pktuart::config::baud_of;
use crate::regs::pktuart::{self as r, rcr, rx, tx};

/// The line as the board's transmitter has it set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineSettings {
    /// Baud rate.
    pub baud: u32,
    /// 0 none, 1 odd, 2 even.
    pub parity: u8,
    /// Stop bits.
    pub stop_bits: u8,
}

impl LineSettings {
    /// Bits per character: start, 8 data, parity, stop.
    pub fn char_bits(&self) -> u64 {
        1 + 8 + u64::from(self.parity != 0) + u64::from(self.stop_bits)
    }

    /// Nanoseconds `bytes` characters take on the line.
    pub fn wire_ns(&self, bytes: usize) -> u64 {
        bytes as u64 * self.char_bits() * 1_000_000_000 / u64::from(self.baud.max(1))
    }
}

/// A frame arriving at the receiver.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct RxFrame {
    /// Its bytes.
    pub bytes: Vec<u8>,
    /// Error bits of the count word ([`rcr::ERRORS`]).
    pub errors: u32,
    /// Longest gap between characters, in bit times.
    pub ichar_bits: u8,
    /// Nanoseconds between the end of the request and the first byte.
    pub turnaround_ns: u64,
}

/// What is on the other end of a PktUART's line.
pub trait SerialPeer: Send {
    /// A frame the board sent at `line`; returns the frames it answers.
    fn frame(&mut self, frame: &[u8], line: &LineSettings) -> Vec<RxFrame>;
    /// The peer, for tests to inspect.
    fn as_any(&mut self) -> &mut dyn Any;
}

/// Words a data FIFO holds.
const DATA_FIFO_WORDS: usize = 512;

/// One simulated PktUART (both halves).
pub struct SimPktUart {
    clock_hz: u32,
    tx_version: u8,
    rx_version: u8,
    tx_bitrate: u32,
    tx_mode: u32,
    tx_data: VecDeque<u32>,
    tx_counts: VecDeque<u32>,
    tx_error: u32,
    /// The frame on the wire and the nanoseconds it has left.
    sending: Option<(Vec<u8>, u64)>,
    rx_bitrate: u32,
    rx_mode: u32,
    rx_sticky: u32,
    rx_data: VecDeque<u32>,
    rx_counts: VecDeque<u32>,
    /// Frames on their way in, with nanoseconds until they are complete.
    incoming: VecDeque<(RxFrame, u64)>,
    peer: Option<Box<dyn SerialPeer>>,
    /// Frames the transmitter has sent.
    pub sent: Vec<Vec<u8>>,
}

impl std::fmt::Debug for SimPktUart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimPktUart")
            .field("tx_mode", &self.tx_mode)
            .field("rx_mode", &self.rx_mode)
            .field("sent", &self.sent.len())
            .finish()
    }
}

/// Mode bits a write sets and a read returns (the rest are status).
const TX_RW: u32 = tx::IF_SCALE
    | tx::STOP_BITS2
    | tx::PARITY_ODD
    | tx::PARITY_EN
    | 0xFF << tx::IF_DELAY_SHIFT
    | tx::DRIVE_EN
    | tx::DRIVE_AUTO
    | tx::DRIVE_DELAY_MASK;
const RX_RW: u32 = 0xFF << rx::FILTER_SHIFT
    | rx::IF_SCALE
    | rx::STOP_BITS2
    | rx::PARITY_ODD
    | rx::PARITY_EN
    | 0xFF << rx::IF_DELAY_SHIFT
    | rx::RX_EN
    | rx::RX_MASK_EN;
/// Write-only mode bits: their places read back as the frame count.
const TX_WO: u32 = tx::IF_SCALE | tx::STOP_BITS2 | tx::PARITY_ODD | tx::PARITY_EN;
const RX_WO: u32 = rx::IF_SCALE | rx::STOP_BITS2 | rx::PARITY_ODD | rx::PARITY_EN;
const RX_STICKY: u32 =
    rx::PARITY_ERROR | rx::RCFIFO_ERROR | rx::OVERRUN_ERROR | rx::START_BIT_ERROR;

impl SimPktUart {
    /// A PktUART clocked at `clock_hz` with the given module versions.
    pub fn new(clock_hz: u32, tx_version: u8, rx_version: u8) -> SimPktUart {
        SimPktUart {
            clock_hz,
            tx_version,
            rx_version,
            tx_bitrate: 0,
            tx_mode: 0,
            tx_data: VecDeque::new(),
            tx_counts: VecDeque::new(),
            tx_error: 0,
            sending: None,
            rx_bitrate: 0,
            rx_mode: 0,
            rx_sticky: 0,
            rx_data: VecDeque::new(),
            rx_counts: VecDeque::new(),
            incoming: VecDeque::new(),
            peer: None,
            sent: Vec::new(),
        }
    }

    /// Connects `peer` to the line (replacing any).
    pub fn attach(&mut self, peer: Box<dyn SerialPeer>) {
        self.peer = Some(peer);
    }

    /// Disconnects the line: nothing answers any more.
    pub fn detach(&mut self) -> Option<Box<dyn SerialPeer>> {
        self.peer.take()
    }

    /// The peer, if it is a `P`.
    pub fn peer<P: SerialPeer + 'static>(&mut self) -> Option<&mut P> {
        self.peer.as_mut()?.as_any().downcast_mut::<P>()
    }

    /// The line as the transmitter is set.
    pub fn line(&self) -> LineSettings {
        let parity = match self.tx_mode & (tx::PARITY_EN | tx::PARITY_ODD) {
            m if m & tx::PARITY_EN == 0 => 0,
            m if m & tx::PARITY_ODD != 0 => 1,
            _ => 2,
        };
        let two = self.tx_mode & tx::STOP_BITS2 != 0 && self.tx_version >= 3;
        LineSettings {
            baud: baud_of(self.tx_bitrate, self.clock_hz, self.tx_version),
            parity,
            stop_bits: 1 + u8::from(two),
        }
    }

    /// Register `reg` of the transmitter (`is_rx` false) or receiver.
    pub fn read(&mut self, is_rx: bool, reg: usize) -> u32 {
        match (is_rx, reg) {
            (false, r::BITRATE) => self.tx_bitrate,
            (true, r::BITRATE) => self.rx_bitrate,
            (false, r::MODE) => {
                let frames = self.tx_counts.len() as u32;
                let mut v = (self.tx_mode & TX_RW & !TX_WO) | (frames & 0x1F) << tx::NFRAMES_SHIFT;
                if self.sending.is_some() || frames > 0 {
                    v |= tx::BUSY;
                }
                if !self.tx_data.is_empty() {
                    v |= tx::HAS_DATA;
                }
                v | self.tx_error
            }
            (true, r::MODE) => {
                let frames = self.rx_counts.len() as u32;
                let mut v = (self.rx_mode & RX_RW & !RX_WO)
                    | (frames & 0x1F) << rx::NFRAMES_SHIFT
                    | self.rx_sticky;
                if !self.rx_data.is_empty() {
                    v |= rx::HAS_DATA;
                }
                if self.sending.is_some() && self.rx_mode & rx::RX_MASK_EN != 0 {
                    v |= rx::MASKED;
                }
                v
            }
            (true, r::COUNT) => self.rx_counts.pop_front().unwrap_or(0),
            (true, r::DATA) => self.rx_data.pop_front().unwrap_or_else(|| {
                self.rx_sticky |= rx::BAD_POP;
                0
            }),
            _ => 0,
        }
    }

    /// A write to register `reg`.
    pub fn write(&mut self, is_rx: bool, reg: usize, v: u32) {
        match (is_rx, reg) {
            (false, r::DATA) if self.tx_data.len() < DATA_FIFO_WORDS => self.tx_data.push_back(v),
            (false, r::COUNT) => {
                if self.tx_counts.len() >= r::MAX_FRAMES {
                    self.tx_error = tx::SCFIFO_ERROR;
                } else {
                    self.tx_counts.push_back(v & rcr::NBYTES_MASK);
                }
            }
            (false, r::BITRATE) => self.tx_bitrate = v,
            (true, r::BITRATE) => self.rx_bitrate = v,
            (false, r::MODE) if v == r::CLEAR => {
                self.tx_data.clear();
                self.tx_counts.clear();
                self.sending = None;
                self.tx_error = 0;
            }
            (true, r::MODE) if v == r::CLEAR => {
                self.rx_data.clear();
                self.rx_counts.clear();
                self.incoming.clear();
                self.rx_sticky = 0;
            }
            (false, r::MODE) => self.tx_mode = v & TX_RW,
            (true, r::MODE) => {
                self.rx_mode = v & RX_RW;
                self.rx_sticky &= v & RX_STICKY;
            }
            _ => {}
        }
    }

    /// Lets `dt_ns` pass on the line.
    pub fn advance(&mut self, dt_ns: u64) {
        let mut left = dt_ns;
        loop {
            if self.sending.is_none() {
                self.start_next_frame();
            }
            let next_tx = self.sending.as_ref().map(|(_, ns)| *ns);
            let next_rx = self.incoming.front().map(|(_, ns)| *ns);
            let step = match (next_tx, next_rx) {
                (None, None) => break,
                (a, b) => a.unwrap_or(u64::MAX).min(b.unwrap_or(u64::MAX)),
            };
            if step > left {
                self.pass(left);
                break;
            }
            self.pass(step);
            left -= step;
            self.complete_due();
        }
    }

    fn pass(&mut self, ns: u64) {
        if let Some((_, t)) = &mut self.sending {
            *t = t.saturating_sub(ns);
        }
        for (_, t) in &mut self.incoming {
            *t = t.saturating_sub(ns);
        }
    }

    fn start_next_frame(&mut self) {
        let Some(n) = self.tx_counts.pop_front() else {
            return;
        };
        let n = n as usize;
        let mut bytes = Vec::with_capacity(n);
        for _ in 0..n.div_ceil(4) {
            let w = self.tx_data.pop_front().unwrap_or(0);
            bytes.extend_from_slice(&w.to_le_bytes());
        }
        bytes.truncate(n);
        let t = self.line().wire_ns(n).max(1);
        self.sending = Some((bytes, t));
    }

    fn complete_due(&mut self) {
        if let Some((frame, 0)) = &self.sending {
            let frame = frame.clone();
            self.sending = None;
            let line = self.line();
            if let Some(p) = &mut self.peer {
                for f in p.frame(&frame, &line) {
                    let ns = f.turnaround_ns + line.wire_ns(f.bytes.len()).max(1);
                    // Answers queue behind each other on the line.
                    let after = self.incoming.back().map_or(0, |(_, t)| *t);
                    self.incoming.push_back((f, after + ns));
                }
            }
            self.sent.push(frame);
        }
        while self.incoming.front().is_some_and(|(_, t)| *t == 0) {
            if let Some((f, _)) = self.incoming.pop_front() {
                self.receive(f);
            }
        }
    }

    fn receive(&mut self, f: RxFrame) {
        if self.rx_mode & rx::RX_EN == 0 {
            return;
        }
        let words = f.bytes.len().div_ceil(4);
        if self.rx_counts.len() >= r::MAX_FRAMES || self.rx_data.len() + words > DATA_FIFO_WORDS {
            self.rx_sticky |= rx::RCFIFO_ERROR;
            return;
        }
        for chunk in f.bytes.chunks(4) {
            let mut b = [0u8; 4];
            b[..chunk.len()].copy_from_slice(chunk);
            self.rx_data.push_back(u32::from_le_bytes(b));
        }
        let ichar = if self.rx_version >= 3 {
            u32::from(f.ichar_bits) << rcr::ICHAR_SHIFT
        } else {
            0
        };
        if f.errors & rcr::PARITY_ERROR != 0 {
            self.rx_sticky |= rx::PARITY_ERROR;
        }
        let size = (f.bytes.len() as u32).min(rcr::NBYTES_MASK);
        self.rx_counts
            .push_back(size | (f.errors & rcr::ERRORS) | ichar);
    }
}

/// The PktUARTs of a simulated board.
#[derive(Debug, Default)]
pub struct SimPktUarts {
    /// One per instance.
    pub ports: Vec<SimPktUart>,
}

impl SimPktUarts {
    /// Lets `dt_ns` pass on every line.
    pub fn advance(&mut self, dt_ns: u64) {
        for p in &mut self.ports {
            p.advance(dt_ns);
        }
    }
}
