//! The configuration side of a simulated Xilinx FPGA, as the cards
//! without flash expose it to their loader: the PLX-bridged PCI cards
//! ([`super::plx`]) and the 7I43's CPLD ([`super::cpld`]) put the same
//! part behind different lines.
//!
//! The part behaves as a loader expects: /PROGRAM low clears it (DONE and
//! /INIT low); released, it raises /INIT after a few status reads
//! ([`ConfigPort::release`]); it takes configuration bytes, bit-reversed
//! back as the cards' wiring does; it raises DONE only after a whole,
//! valid stream of the simulator's format ([`bitstream`]) for its own
//! part; a stream for another part or with a bad checksum pulls /INIT
//! low (the CRC error) and DONE stays low; a stream cut short leaves both
//! as they were. Once DONE, [`ConfigPort::design`] names the firmware it
//! runs.
//!
//! The simulator's stream, after any number of 0xFF bytes:
//!
//! | bytes | content |
//! |---|---|
//! | 4 | the Xilinx sync word AA 99 55 66 |
//! | 4 | `HM2S`, this simulator's stream |
//! | 4 | part ID: FNV-1a of the part name (`2s200pq208`) |
//! | 2 + n | design name length, name (`SVST8_4`) |
//! | 4 + m | frame data length, frame data |
//! | 4 | FNV-1a of everything from `HM2S` to the last frame byte |
//!
//! All numbers big-endian. Real Xilinx streams are not modelled: a
//! Mesa bitfile never raises DONE here.

const SYNC: [u8; 4] = [0xAA, 0x99, 0x55, 0x66];
const TAG: &[u8; 4] = b"HM2S";
/// Longest frame data the simulated FPGA takes.
const MAX_FRAMES: usize = 4 << 20;
/// Frame bytes of a generated stream (the real parts need 100 KiB to
/// 1 MiB; the simulator's stream only has to be long enough to be cut).
const FRAME_BYTES: usize = 4096;

/// FNV-1a, 32 bits: the simulator's part IDs and checksum.
fn fnv1a(bytes: &[u8]) -> u32 {
    bytes.iter().fold(0x811C_9DC5u32, |h, &b| {
        (h ^ b as u32).wrapping_mul(0x0100_0193)
    })
}

/// The simulator's bitstream of `design` for `part`, as it appears in
/// the bitfile (before the driver's bit reversal).
pub fn bitstream(design: &str, part: &str) -> Vec<u8> {
    let mut body = Vec::with_capacity(FRAME_BYTES + 64);
    body.extend_from_slice(TAG);
    body.extend_from_slice(&fnv1a(part.as_bytes()).to_be_bytes());
    let name = &design.as_bytes()[..design.len().min(u16::MAX as usize)];
    body.extend_from_slice(&(name.len() as u16).to_be_bytes());
    body.extend_from_slice(name);
    body.extend_from_slice(&(FRAME_BYTES as u32).to_be_bytes());
    body.extend((0..FRAME_BYTES).map(|i| (i as u32).wrapping_mul(2_654_435_761) as u8 >> 1));
    let sum = fnv1a(&body);
    body.extend_from_slice(&sum.to_be_bytes());
    let mut out = vec![0xFF; 8];
    out.extend_from_slice(&SYNC);
    out.extend_from_slice(&body);
    out
}

/// A whole bitfile of `design` for `part` in the simulator's format.
pub fn bitfile(design: &str, part: &str) -> Vec<u8> {
    crate::fpga::bitfile::build(
        &format!("{}.ncd;UserID=0xFFFFFFFF", design.to_ascii_lowercase()),
        part,
        "2026/01/01",
        "00:00:00",
        &bitstream(design, part),
    )
}

/// What the stream received so far amounts to.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Verdict {
    /// More bytes needed.
    Incomplete,
    /// The stream is wrong: /INIT goes low.
    Bad,
    /// Configured with this design.
    Done(String),
}

/// Judges the bytes after the sync word.
fn judge(body: &[u8], part_id: u32) -> Verdict {
    let be32 = |at: usize| {
        body.get(at..at + 4)
            .map(|b| u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    };
    if body.len() < 4 {
        return Verdict::Incomplete;
    }
    if &body[..4] != TAG {
        return Verdict::Bad;
    }
    let Some(id) = be32(4) else {
        return Verdict::Incomplete;
    };
    if id != part_id {
        return Verdict::Bad;
    }
    let Some(n) = body
        .get(8..10)
        .map(|b| u16::from_be_bytes([b[0], b[1]]) as usize)
    else {
        return Verdict::Incomplete;
    };
    let Some(m) = be32(10 + n) else {
        return Verdict::Incomplete;
    };
    let m = m as usize;
    if m > MAX_FRAMES {
        return Verdict::Bad;
    }
    let end = 14 + n + m;
    let Some(sum) = be32(end) else {
        return Verdict::Incomplete;
    };
    if sum != fnv1a(&body[..end]) {
        return Verdict::Bad;
    }
    match std::str::from_utf8(&body[10..10 + n]) {
        Ok(name) => Verdict::Done(name.to_string()),
        Err(_) => Verdict::Bad,
    }
}

/// The configuration state of one simulated part.
#[derive(Debug)]
pub struct ConfigPort {
    part_id: u32,
    /// Held in reset by /PROGRAM.
    held: bool,
    /// Status reads left before /INIT rises after /PROGRAM is released
    /// (`None`: never).
    clearing: Option<u32>,
    /// /INIT high: ready for data (or configured).
    init: bool,
    /// The last four bytes before sync.
    window: [u8; 4],
    /// Sync word seen.
    synced: bool,
    /// Bytes after the sync word.
    body: Vec<u8>,
    /// The outcome, once decided.
    verdict: Option<Verdict>,
}

impl ConfigPort {
    /// An unconfigured part named `part` (`2s200pq208`), as at power-up.
    pub fn new(part: &str) -> ConfigPort {
        ConfigPort::with_part_id(fnv1a(part.as_bytes()))
    }

    fn with_part_id(part_id: u32) -> ConfigPort {
        ConfigPort {
            part_id,
            held: false,
            clearing: None,
            init: false,
            window: [0; 4],
            synced: false,
            body: Vec::new(),
            verdict: None,
        }
    }

    /// /PROGRAM low: the part forgets its design and holds.
    pub fn hold(&mut self) {
        *self = ConfigPort {
            held: true,
            ..ConfigPort::with_part_id(self.part_id)
        };
    }

    /// /PROGRAM released: the part clears itself over `clear_reads`
    /// status reads (`None`: it never does). No effect unless held.
    pub fn release(&mut self, clear_reads: Option<u32>) {
        if self.held {
            self.held = false;
            self.clearing = clear_reads;
        }
    }

    /// Whether /PROGRAM holds the part.
    pub fn held(&self) -> bool {
        self.held
    }

    /// A status read: one step of the clearing after a release.
    pub fn poll(&mut self) {
        if !self.held && !self.init {
            match &mut self.clearing {
                Some(0) => self.init = true,
                Some(n) => *n -= 1,
                None => {}
            }
        }
    }

    /// /INIT as the part drives it: high once cleared, low again on a
    /// CRC error.
    pub fn init(&self) -> bool {
        self.init && self.verdict != Some(Verdict::Bad)
    }

    /// DONE: configured from a whole, valid stream and not held.
    pub fn done(&self) -> bool {
        matches!(self.verdict, Some(Verdict::Done(_))) && !self.held
    }

    /// The design the part runs, once DONE.
    pub fn design(&self) -> Option<&str> {
        match &self.verdict {
            Some(Verdict::Done(d)) if !self.held => Some(d),
            _ => None,
        }
    }

    /// One byte on the configuration data lines, as the driver wrote it
    /// (bit-reversed by the cards' wiring). Returns whether the part took
    /// it: not while held, before /INIT, or once the stream is decided.
    pub fn take(&mut self, wired: u8) -> bool {
        if self.held || !self.init || self.verdict.is_some() {
            return false;
        }
        let b = wired.reverse_bits();
        if !self.synced {
            self.window = [self.window[1], self.window[2], self.window[3], b];
            self.synced = self.window == SYNC;
        } else if self.body.len() < MAX_FRAMES + 1024 {
            self.body.push(b);
            match judge(&self.body, self.part_id) {
                Verdict::Incomplete => {}
                v => self.verdict = Some(v),
            }
        } else {
            self.verdict = Some(Verdict::Bad);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(port: &mut ConfigPort, stream: &[u8]) {
        port.hold();
        port.release(Some(0));
        port.poll();
        for &b in stream {
            port.take(b.reverse_bits());
        }
    }

    #[test]
    fn a_whole_stream_for_the_part_raises_done_and_names_the_design() {
        let mut p = ConfigPort::new("3s400tq144");
        assert!(!p.done());
        load(&mut p, &bitstream("SVST4_4", "3s400tq144"));
        assert!(p.done() && p.init());
        assert_eq!(p.design(), Some("SVST4_4"));
        p.hold();
        assert_eq!(p.design(), None, "/PROGRAM clears it");
    }

    #[test]
    fn another_parts_stream_is_a_crc_error_and_a_cut_one_is_not_done() {
        let mut p = ConfigPort::new("3s200tq144");
        load(&mut p, &bitstream("SV8", "3s400tq144"));
        assert!(!p.done() && !p.init(), "CRC error pulls /INIT low");
        let s = bitstream("SV8", "3s200tq144");
        load(&mut p, &s[..s.len() - 1]);
        assert!(!p.done() && p.init());
    }

    #[test]
    fn nothing_is_taken_before_init() {
        let mut p = ConfigPort::new("3s200tq144");
        p.hold();
        assert!(!p.take(0xFF));
        p.release(Some(2));
        assert!(!p.take(0xFF), "still clearing");
        for _ in 0..3 {
            p.poll();
        }
        assert!(p.take(0xFF));
    }
}
