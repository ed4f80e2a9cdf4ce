//! A simulated PLX bridge with an FPGA behind it: the programming lines
//! of a 5i20 (PLX 9030: /PROGRAM, /INIT, DONE, /WRITE, /LED on GPIO) or a
//! 5i22 (PLX 9054: /PROGRAM on USERo, DONE on USERi) and the FPGA's
//! configuration port on the data port, as a [`PortBus`].
//!
//! The FPGA behaves as the loader expects of a Xilinx part: /PROGRAM low
//! clears it (DONE and /INIT low); released, it raises /INIT after a few
//! reads ([`SimPlxBridge::set_clear_reads`]); it takes bytes on the data
//! port (on the 9030 only while /WRITE is low), bit-reversed back as the
//! card's wiring does; it raises DONE only after a whole, valid stream
//! of the simulator's format ([`bitstream`]) for its own part; a stream
//! for another part or with a bad checksum pulls /INIT low (the CRC
//! error) and DONE stays low; a stream cut short leaves both as they
//! were. Once DONE, [`SimPlxBridge::design`] names the firmware it runs.
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

use std::sync::Mutex;

use hal_driver::bus::{PortBus, ALL_ONES};

use crate::fpga::{Bridge, PlxPorts};
use crate::regs::{plx9030, plx9054};

/// Where the simulated bridge's configuration registers start.
pub const CTRL_BASE: u16 = 0xE000;
/// Ports of the configuration registers.
pub const CTRL_LEN: u16 = 0x100;
/// The simulated data port.
pub const DATA_BASE: u16 = 0xE400;

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

/// The FPGA's configuration state.
#[derive(Debug, Default)]
struct Fpga {
    /// Held in reset by /PROGRAM.
    held: bool,
    /// Reads left before /INIT rises after /PROGRAM is released (`None`:
    /// never).
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

#[derive(Debug)]
struct State {
    ctrl: u32,
    /// The other local configuration registers, as written (all 0 at
    /// first, as an old 9030 EEPROM leaves LASxBRD's READY# bit).
    others: [u32; CTRL_LEN as usize / 4],
    fpga: Fpga,
    clear_reads: Option<u32>,
    done_stuck_low: bool,
    bytes: u64,
}

/// The simulated bridge and FPGA.
#[derive(Debug)]
pub struct SimPlxBridge {
    bridge: Bridge,
    part_id: u32,
    state: Mutex<State>,
    errors: std::sync::atomic::AtomicU64,
}

impl SimPlxBridge {
    /// A bridge of kind `bridge` with an unconfigured FPGA of `part`.
    pub fn new(bridge: Bridge, part: &str) -> SimPlxBridge {
        let ctrl = match bridge {
            // Outputs high (inactive) as the EEPROM leaves them.
            Bridge::Plx9030 => plx9030::PROGRAM | plx9030::WRITE | plx9030::LED,
            Bridge::Plx9054 => plx9054::PROGRAM,
        };
        SimPlxBridge {
            bridge,
            part_id: fnv1a(part.as_bytes()),
            state: Mutex::new(State {
                ctrl,
                others: [0; CTRL_LEN as usize / 4],
                fpga: Fpga::default(),
                clear_reads: Some(3),
                done_stuck_low: false,
                bytes: 0,
            }),
            errors: Default::default(),
        }
    }

    /// The bridge kind.
    pub fn bridge(&self) -> Bridge {
        self.bridge
    }

    /// Its ports, for the loader: both BARs on this bus.
    pub fn ports(&self) -> PlxPorts<'_> {
        PlxPorts {
            bridge: self.bridge,
            ctrl: self,
            ctrl_base: CTRL_BASE,
            data: self,
            data_base: DATA_BASE,
        }
    }

    /// How many control-register reads the FPGA takes to clear after
    /// /PROGRAM is released; `None`: it never does (/INIT stays low).
    pub fn set_clear_reads(&self, reads: Option<u32>) {
        self.lock().clear_reads = reads;
    }

    /// A fault: DONE never rises, whatever the stream.
    pub fn set_done_stuck_low(&self, stuck: bool) {
        self.lock().done_stuck_low = stuck;
    }

    /// The design the FPGA runs, once DONE is high.
    pub fn design(&self) -> Option<String> {
        let s = self.lock();
        match &s.fpga.verdict {
            Some(Verdict::Done(d)) if !s.done_stuck_low && !s.fpga.held => Some(d.clone()),
            _ => None,
        }
    }

    /// Data bytes the FPGA took since it was made.
    pub fn bytes_taken(&self) -> u64 {
        self.lock().bytes
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn ctrl_offset(&self) -> u16 {
        match self.bridge {
            Bridge::Plx9030 => plx9030::GPIOC,
            Bridge::Plx9054 => plx9054::CNTRL,
        }
    }

    fn program_low(&self, ctrl: u32) -> bool {
        match self.bridge {
            Bridge::Plx9030 => ctrl & plx9030::PROGRAM == 0,
            Bridge::Plx9054 => ctrl & plx9054::PROGRAM_ENABLE != 0 && ctrl & plx9054::PROGRAM == 0,
        }
    }

    fn write_ctrl(&self, value: u32) {
        let mut s = self.lock();
        s.ctrl = value;
        let low = self.program_low(value);
        let clear_reads = s.clear_reads;
        let f = &mut s.fpga;
        if low {
            *f = Fpga {
                held: true,
                ..Fpga::default()
            };
        } else if f.held {
            f.held = false;
            f.clearing = clear_reads;
        }
    }

    fn read_ctrl(&self) -> u32 {
        let mut s = self.lock();
        let stuck = s.done_stuck_low;
        let f = &mut s.fpga;
        if !f.held && !f.init {
            match &mut f.clearing {
                Some(0) => f.init = true,
                Some(n) => *n -= 1,
                None => {}
            }
        }
        let done = matches!(f.verdict, Some(Verdict::Done(_))) && !stuck && !f.held;
        let init = f.init && f.verdict != Some(Verdict::Bad);
        let ctrl = s.ctrl;
        match self.bridge {
            Bridge::Plx9030 => {
                let mut v = ctrl & !(plx9030::DONE | plx9030::INIT);
                if done {
                    v |= plx9030::DONE;
                }
                if init {
                    v |= plx9030::INIT;
                }
                v
            }
            Bridge::Plx9054 => {
                let mut v = ctrl & !plx9054::DONE;
                if done && ctrl & plx9054::DONE_ENABLE != 0 {
                    v |= plx9054::DONE;
                }
                v
            }
        }
    }

    fn data(&self, byte: u8) {
        let mut s = self.lock();
        let writing = match self.bridge {
            Bridge::Plx9030 => s.ctrl & plx9030::WRITE == 0,
            Bridge::Plx9054 => true,
        };
        let part_id = self.part_id;
        let f = &mut s.fpga;
        if f.held || !f.init || !writing || f.verdict.is_some() {
            return;
        }
        // The card wires the data bus reversed: undo the driver's reversal.
        let b = byte.reverse_bits();
        if !f.synced {
            f.window = [f.window[1], f.window[2], f.window[3], b];
            f.synced = f.window == SYNC;
        } else if f.body.len() < MAX_FRAMES + 1024 {
            f.body.push(b);
            match judge(&f.body, part_id) {
                Verdict::Incomplete => {}
                v => f.verdict = Some(v),
            }
        } else {
            f.verdict = Some(Verdict::Bad);
        }
        s.bytes += 1;
    }

    fn miss(&self) {
        self.errors
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }
}

impl PortBus for SimPlxBridge {
    fn inb(&self, _port: u16) -> u8 {
        self.miss();
        ALL_ONES as u8
    }
    fn outb(&self, port: u16, value: u8) {
        if port == DATA_BASE {
            self.data(value);
        } else {
            self.miss();
        }
    }
    fn inw(&self, _port: u16) -> u16 {
        self.miss();
        ALL_ONES as u16
    }
    fn outw(&self, _port: u16, _value: u16) {
        self.miss();
    }
    fn inl(&self, port: u16) -> u32 {
        match port.checked_sub(CTRL_BASE) {
            Some(off) if off == self.ctrl_offset() => self.read_ctrl(),
            Some(off) if off < CTRL_LEN && off % 4 == 0 => self.lock().others[off as usize / 4],
            _ => {
                self.miss();
                ALL_ONES
            }
        }
    }
    fn outl(&self, port: u16, value: u32) {
        match port.checked_sub(CTRL_BASE) {
            Some(off) if off == self.ctrl_offset() => self.write_ctrl(value),
            Some(off) if off < CTRL_LEN && off % 4 == 0 => {
                self.lock().others[off as usize / 4] = value;
            }
            _ => self.miss(),
        }
    }
    fn errors(&self) -> u64 {
        self.errors.load(std::sync::atomic::Ordering::Relaxed)
    }
    fn describe(&self) -> String {
        format!("simulated {} bridge", self.bridge.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fpga::{plx, FpgaError, ProgramStep};

    fn ports(b: &SimPlxBridge) -> PlxPorts<'_> {
        b.ports()
    }

    fn step_of(e: FpgaError) -> (ProgramStep, String) {
        match e {
            FpgaError::Program { step, reason } => (step, reason),
            e => panic!("not a programming error: {e}"),
        }
    }

    #[test]
    fn both_bridges_load_a_whole_stream_and_name_the_design() {
        for bridge in [Bridge::Plx9030, Bridge::Plx9054] {
            let b = SimPlxBridge::new(bridge, "2s200pq208");
            assert_eq!(b.design(), None);
            let s = bitstream("SVST8_4", "2s200pq208");
            plx::program(&ports(&b), &s).unwrap();
            assert_eq!(b.design().as_deref(), Some("SVST8_4"), "{bridge:?}");
            assert_eq!(b.errors(), 0);
        }
    }

    #[test]
    fn a_reload_starts_from_a_cleared_fpga() {
        let b = SimPlxBridge::new(Bridge::Plx9030, "2s200pq208");
        plx::program(&ports(&b), &bitstream("SV12", "2s200pq208")).unwrap();
        plx::program(&ports(&b), &bitstream("SVST8_4", "2s200pq208")).unwrap();
        assert_eq!(b.design().as_deref(), Some("SVST8_4"));
    }

    #[test]
    fn a_stream_cut_short_never_raises_done() {
        for bridge in [Bridge::Plx9030, Bridge::Plx9054] {
            let b = SimPlxBridge::new(bridge, "3s400pq208");
            let s = bitstream("SVST8_4", "3s400pq208");
            let (step, why) = step_of(plx::program(&ports(&b), &s[..s.len() - 100]).unwrap_err());
            assert_eq!(step, ProgramStep::CheckDone);
            assert!(why.contains("DONE did not rise"), "{why}");
            assert_eq!(b.design(), None);
        }
    }

    #[test]
    fn a_stream_for_another_part_is_a_crc_error_on_the_9030() {
        let b = SimPlxBridge::new(Bridge::Plx9030, "2s200pq208");
        let s = bitstream("SVST8_4", "3s400pq208");
        let (step, why) = step_of(plx::program(&ports(&b), &s).unwrap_err());
        assert_eq!(step, ProgramStep::CheckDone);
        assert!(why.contains("CRC error"), "{why}");
        let mut s = bitstream("SVST8_4", "2s200pq208");
        let n = s.len();
        s[n - 10] ^= 1;
        let (_, why) = step_of(plx::program(&ports(&b), &s).unwrap_err());
        assert!(why.contains("CRC error"), "{why}");
    }

    #[test]
    fn an_fpga_that_never_clears_fails_at_the_init_wait() {
        let b = SimPlxBridge::new(Bridge::Plx9030, "2s200pq208");
        b.set_clear_reads(None);
        let (step, why) =
            step_of(plx::program(&ports(&b), &bitstream("SV12", "2s200pq208")).unwrap_err());
        assert_eq!(step, ProgramStep::WaitInit);
        assert!(why.contains("3300 reads"), "{why}");
    }

    #[test]
    fn done_stuck_low_fails_the_done_check_on_both_bridges() {
        for bridge in [Bridge::Plx9030, Bridge::Plx9054] {
            let b = SimPlxBridge::new(bridge, "2s200pq208");
            b.set_done_stuck_low(true);
            let (step, why) =
                step_of(plx::program(&ports(&b), &bitstream("SV12", "2s200pq208")).unwrap_err());
            assert_eq!(step, ProgramStep::CheckDone, "{bridge:?}");
            assert!(why.contains("DONE did not rise"), "{why}");
        }
    }

    #[test]
    fn bytes_are_taken_only_while_write_is_low_on_the_9030() {
        let b = SimPlxBridge::new(Bridge::Plx9030, "2s200pq208");
        b.outb(DATA_BASE, 0x55);
        assert_eq!(b.bytes_taken(), 0);
    }

    #[test]
    fn a_port_outside_the_bridge_stops_the_load_at_its_step() {
        let b = SimPlxBridge::new(Bridge::Plx9054, "3s400pq208");
        let p = PlxPorts {
            data_base: DATA_BASE + 1,
            ..ports(&b)
        };
        let (step, why) = step_of(plx::program(&p, &bitstream("SV12", "3s400pq208")).unwrap_err());
        assert_eq!(step, ProgramStep::Load);
        assert!(why.contains("simulated PLX 9054 bridge"), "{why}");
    }

    #[test]
    fn the_9030_ready_bits_are_set_where_clear() {
        let b = SimPlxBridge::new(Bridge::Plx9030, "2s200pq208");
        assert_eq!(plx::fix_9030_ready(&ports(&b)).unwrap(), 4);
        assert_eq!(b.inl(CTRL_BASE + 0x2C), 2);
        assert_eq!(plx::fix_9030_ready(&ports(&b)).unwrap(), 0);
    }
}
