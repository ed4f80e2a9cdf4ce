//! The SPI transport: HostMot2 register bursts as Mesa SPI frames
//! ([`super::frame`]) on an [`SpiBus`].
//!
//! Each burst is one message: a command word and its data, split into
//! frames of at most [`MAX_BURST`] words. Like a memory window it needs
//! no batching: queued reads are read when the receive asks for them,
//! queued writes are written at once. The message buffer is made when
//! the transport is, so the cycle's transfers allocate nothing. Reads
//! may run at a lower clock than writes (`spiclk_rate_rd`).

use std::sync::Arc;

use hal_driver::bus::{SpiBus, MAX_MESSAGE_WORDS};

use super::frame::{Command, MAX_BURST};
use crate::transport::{check_window, ReadQueue, TransferStats, Transport, TransportError};

/// Words of the largest message this transport sends: a whole number of
/// full frames that fits the bus's largest message.
const MESSAGE_WORDS: usize = (MAX_MESSAGE_WORDS / (MAX_BURST + 1)) * (MAX_BURST + 1);

/// A [`Transport`] of SPI frames over `bus`.
pub struct SpiTransport {
    bus: Arc<dyn SpiBus>,
    write_hz: u32,
    read_hz: u32,
    message: Vec<u32>,
    reads: ReadQueue,
    stats: TransferStats,
    errors: u64,
}

impl std::fmt::Debug for SpiTransport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpiTransport")
            .field("bus", &self.bus.describe())
            .field("write_hz", &self.write_hz)
            .field("read_hz", &self.read_hz)
            .finish()
    }
}

/// The message of a burst of `words` registers from `addr`: one frame
/// per [`MAX_BURST`] words, data words from `data` (a write) or filler
/// (a read). Returns the message's length.
fn frame_burst(message: &mut [u32], addr: u32, words: usize, data: Option<&[u32]>) -> usize {
    let mut at = 0;
    let mut done = 0;
    while done < words {
        let n = (words - done).min(MAX_BURST);
        let a = (addr + 4 * done as u32) as u16;
        let cmd = match data {
            Some(_) => Command::write(a, n as u8),
            None => Command::read(a, n as u8),
        };
        message[at] = cmd.encode();
        let slot = &mut message[at + 1..at + 1 + n];
        match data {
            Some(d) => slot.copy_from_slice(&d[done..done + n]),
            None => slot.fill(0),
        }
        at += 1 + n;
        done += n;
    }
    at
}

/// Frames in a message of `words` data words.
fn message_len(words: usize) -> usize {
    words + words.div_ceil(MAX_BURST)
}

impl SpiTransport {
    /// A transport over `bus`, writing at `write_hz` and reading at
    /// `read_hz`.
    pub fn new(bus: Arc<dyn SpiBus>, write_hz: u32, read_hz: u32) -> SpiTransport {
        let errors = bus.errors();
        SpiTransport {
            bus,
            write_hz,
            read_hz,
            message: vec![0; MESSAGE_WORDS],
            reads: ReadQueue::default(),
            stats: TransferStats::default(),
            errors,
        }
    }

    fn check_bus(&mut self) -> Result<(), TransportError> {
        let now = self.bus.errors();
        if now != self.errors {
            self.errors = now;
            return Err(TransportError::Bus { count: now });
        }
        Ok(())
    }

    /// The most data words one message carries.
    fn chunk() -> usize {
        MESSAGE_WORDS / (MAX_BURST + 1) * MAX_BURST
    }
}

/// Reads `buf.len()` registers from `addr` in as many messages as needed.
fn read_burst(bus: &dyn SpiBus, message: &mut [u32], hz: u32, addr: u32, buf: &mut [u32]) {
    let chunk = SpiTransport::chunk();
    for (k, part) in buf.chunks_mut(chunk).enumerate() {
        let at = addr + (4 * k * chunk) as u32;
        let len = frame_burst(message, at, part.len(), None);
        bus.transfer(&mut message[..len], hz);
        let mut m = 0;
        let mut got = 0;
        while got < part.len() {
            let n = (part.len() - got).min(MAX_BURST);
            part[got..got + n].copy_from_slice(&message[m + 1..m + 1 + n]);
            m += 1 + n;
            got += n;
        }
    }
}

impl Transport for SpiTransport {
    fn read(&mut self, addr: u32, buf: &mut [u32]) -> Result<(), TransportError> {
        check_window(addr, buf.len())?;
        read_burst(&*self.bus, &mut self.message, self.read_hz, addr, buf);
        self.stats.words_read += buf.len() as u64;
        self.stats.read_bursts += 1;
        self.check_bus()
    }

    fn write(&mut self, addr: u32, data: &[u32]) -> Result<(), TransportError> {
        check_window(addr, data.len())?;
        let chunk = Self::chunk();
        for (k, part) in data.chunks(chunk).enumerate() {
            let at = addr + (4 * k * chunk) as u32;
            let len = frame_burst(&mut self.message, at, part.len(), Some(part));
            debug_assert_eq!(len, message_len(part.len()));
            self.bus.transfer(&mut self.message[..len], self.write_hz);
        }
        self.stats.words_written += data.len() as u64;
        self.stats.write_bursts += 1;
        self.check_bus()
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
        let (bus, message, hz) = (&*self.bus, &mut self.message, self.read_hz);
        self.reads.receive(out, &mut self.stats, |addr, dst| {
            read_burst(bus, message, hz, addr, dst)
        })?;
        self.check_bus()
    }

    fn send_queued_writes(&mut self) -> Result<(), TransportError> {
        self.check_bus()
    }

    fn stats(&self) -> TransferStats {
        self.stats
    }

    /// One SPI device serves one thread at a time (LinuxCNC's hm2_spi
    /// llio is not thread-safe either).
    fn threadsafe(&self) -> bool {
        false
    }

    fn describe(&self) -> String {
        format!(
            "{}, {} kHz write / {} kHz read",
            self.bus.describe(),
            self.write_hz / 1000,
            self.read_hz / 1000
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spi::frame::{serve, Registers};
    use std::sync::Mutex;

    /// Messages seen: (words, clock).
    type Messages = Vec<(usize, u32)>;

    /// A device of 16 K registers that serves frames and logs messages.
    struct Device {
        regs: Mutex<(Vec<u32>, Messages)>,
    }

    impl Registers for Vec<u32> {
        fn read(&mut self, addr: u32) -> u32 {
            self[addr as usize / 4]
        }
        fn write(&mut self, addr: u32, value: u32) {
            self[addr as usize / 4] = value;
        }
    }

    impl SpiBus for Device {
        fn transfer(&self, buf: &mut [u32], speed_hz: u32) {
            let mut g = self.regs.lock().unwrap();
            g.1.push((buf.len(), speed_hz));
            serve(buf, &mut g.0).unwrap();
        }
        fn errors(&self) -> u64 {
            0
        }
        fn describe(&self) -> String {
            "mock".into()
        }
    }

    fn device() -> Arc<Device> {
        Arc::new(Device {
            regs: Mutex::new(((0..16384).collect(), Vec::new())),
        })
    }

    #[test]
    fn bursts_become_frames_of_at_most_127_words() {
        let d = device();
        let mut t = SpiTransport::new(d.clone(), 24_000_000, 12_000_000);
        let mut buf = vec![0u32; 300];
        t.read(0x400, &mut buf).unwrap();
        assert_eq!(buf[0], 0x100);
        assert_eq!(buf[299], 0x100 + 299);
        t.write(0x800, &[7; 130]).unwrap();
        let g = d.regs.lock().unwrap();
        assert_eq!(g.0[0x200], 7);
        assert_eq!(g.0[0x200 + 129], 7);
        assert_eq!(g.0[0x200 + 130], 0x200 + 130);
        // 300 words: 3 frames in one message at the read clock; 130
        // words: 2 frames at the write clock.
        assert_eq!(g.1, [(303, 12_000_000), (132, 24_000_000)]);
    }

    #[test]
    fn long_bursts_take_several_messages() {
        let d = device();
        let mut t = SpiTransport::new(d.clone(), 1, 1);
        let mut buf = vec![0u32; 2000];
        t.read(0, &mut buf).unwrap();
        assert!(buf.iter().enumerate().all(|(i, &v)| v == i as u32));
        let g = d.regs.lock().unwrap();
        assert!(g.1.iter().all(|&(n, _)| n <= MAX_MESSAGE_WORDS));
        assert_eq!(g.1.len(), 2);
    }

    #[test]
    fn queued_reads_and_window_checks() {
        let d = device();
        let mut t = SpiTransport::new(d, 1, 1);
        t.reserve(2, 3, 0, 0);
        t.queue_read(0x10, 2).unwrap();
        t.queue_read(0x40, 1).unwrap();
        t.send_queued_reads().unwrap();
        let mut out = [0u32; 3];
        t.receive_queued_reads(&mut out).unwrap();
        assert_eq!(out, [4, 5, 16]);
        assert_eq!(t.stats().read_bursts, 2);
        assert!(matches!(
            t.read(0xFFFC, &mut [0; 2]),
            Err(TransportError::OutOfWindow { .. })
        ));
        assert!(t.describe().starts_with("mock"));
    }

    #[test]
    fn message_lengths() {
        assert_eq!(message_len(1), 2);
        assert_eq!(message_len(127), 128);
        assert_eq!(message_len(128), 130);
        assert_eq!(MESSAGE_WORDS % (MAX_BURST + 1), 0);
    }
}
