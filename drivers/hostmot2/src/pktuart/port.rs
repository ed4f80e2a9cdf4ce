//! One PktUART driven through a [`Transport`]: configuration, frames out
//! (bytes packed four to a word, low byte first, each frame starting on a
//! word, then its size into the count FIFO) and frames in (the count FIFO
//! popped once per frame, then the frame's words).
//!
//! Every call here is one or a few immediate register accesses: for
//! load-time set-up, tools and tests. Realtime users reach a PktUART
//! through its board's per-cycle bursts instead ([`super::link`]).

use super::config::{self, LineConfig};
use super::discovery::PktUartInstance;
use crate::regs::pktuart as r;
use crate::transport::{Transport, TransportError};

/// The largest frame this port sends or takes in, in 32-bit words.
pub const MAX_FRAME_WORDS: usize = r::MAX_FRAME_BYTES.div_ceil(4);

/// A PktUART and the transport it is reached through.
#[derive(Debug, Clone)]
pub struct PktUartPort {
    inst: PktUartInstance,
}

impl PktUartPort {
    /// The port for `inst`.
    pub fn new(inst: PktUartInstance) -> PktUartPort {
        PktUartPort { inst }
    }

    /// The instance.
    pub fn instance(&self) -> &PktUartInstance {
        &self.inst
    }

    /// Writes both directions' bit-rate and mode words, then clears both
    /// FIFOs when `flush` is set.
    pub fn configure(
        &self,
        t: &mut dyn Transport,
        rx: &LineConfig,
        tx: &LineConfig,
        flush: bool,
    ) -> Result<(), TransportError> {
        let i = &self.inst;
        let w = config::rx_words(rx, i.clock_hz, i.rx_version);
        t.write(i.rx[r::BITRATE], &[w.bitrate])?;
        t.write(i.rx[r::MODE], &[w.mode])?;
        let w = config::tx_words(tx, i.clock_hz, i.tx_version);
        t.write(i.tx[r::BITRATE], &[w.bitrate])?;
        t.write(i.tx[r::MODE], &[w.mode])?;
        if flush {
            self.clear(t)?;
        }
        Ok(())
    }

    /// Aborts both directions and empties their FIFOs.
    pub fn clear(&self, t: &mut dyn Transport) -> Result<(), TransportError> {
        t.write(self.inst.tx[r::MODE], &[r::CLEAR])?;
        t.write(self.inst.rx[r::MODE], &[r::CLEAR])
    }

    /// Queues one frame for sending. `scratch` holds the packed words
    /// (at least `frame.len().div_ceil(4)` of them).
    pub fn send(
        &self,
        t: &mut dyn Transport,
        frame: &[u8],
        scratch: &mut [u32],
    ) -> Result<(), TransportError> {
        let n = frame.len().min(r::MAX_FRAME_BYTES);
        let words = n.div_ceil(4).min(scratch.len());
        for (w, chunk) in scratch.iter_mut().zip(frame[..n].chunks(4)) {
            let mut b = [0u8; 4];
            b[..chunk.len()].copy_from_slice(chunk);
            *w = u32::from_le_bytes(b);
        }
        for w in &scratch[..words] {
            t.write(self.inst.tx[r::DATA], std::slice::from_ref(w))?;
        }
        t.write(self.inst.tx[r::COUNT], &[n as u32])
    }

    /// The transmitter's mode/status word.
    pub fn tx_status(&self, t: &mut dyn Transport) -> Result<u32, TransportError> {
        let mut w = [0];
        t.read(self.inst.tx[r::MODE], &mut w)?;
        Ok(w[0])
    }

    /// The receiver's mode/status word.
    pub fn rx_status(&self, t: &mut dyn Transport) -> Result<u32, TransportError> {
        let mut w = [0];
        t.read(self.inst.rx[r::MODE], &mut w)?;
        Ok(w[0])
    }

    /// Pops the next received frame's count word (size and error bits).
    pub fn pop_frame_size(&self, t: &mut dyn Transport) -> Result<u32, TransportError> {
        let mut w = [0];
        t.read(self.inst.rx[r::COUNT], &mut w)?;
        Ok(w[0])
    }

    /// Pops a received frame of `bytes` bytes into `out` (which must have
    /// room for them): its words are always all popped, so the next frame
    /// starts clean, even when `out` is short.
    pub fn read_frame(
        &self,
        t: &mut dyn Transport,
        bytes: usize,
        out: &mut [u8],
    ) -> Result<usize, TransportError> {
        let words = bytes.min(r::MAX_FRAME_BYTES).div_ceil(4);
        let mut got = 0;
        for _ in 0..words {
            let mut w = [0];
            t.read(self.inst.rx[r::DATA], &mut w)?;
            for b in w[0].to_le_bytes() {
                if got < bytes && got < out.len() {
                    out[got] = b;
                    got += 1;
                }
            }
        }
        Ok(got)
    }
}
