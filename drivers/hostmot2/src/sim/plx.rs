//! A simulated PLX bridge with an FPGA behind it: the programming lines
//! of a 5i20 (PLX 9030: /PROGRAM, /INIT, DONE, /WRITE, /LED on GPIO) or a
//! 5i22 (PLX 9054: /PROGRAM on USERo, DONE on USERi) and the FPGA's
//! configuration port on the data port, as a [`PortBus`].
//!
//! The FPGA is the simulated part of [`super::xilinx`]: /PROGRAM,
//! /INIT, DONE and the data port reach its [`ConfigPort`]; on the 9030 it
//! takes bytes only while /WRITE is low. Once DONE,
//! [`SimPlxBridge::design`] names the firmware it runs.

use std::sync::Mutex;

use hal_driver::bus::{PortBus, ALL_ONES};

use super::xilinx::ConfigPort;
pub use super::xilinx::{bitfile, bitstream};
use crate::fpga::{Bridge, PlxPorts};
use crate::regs::{plx9030, plx9054};

/// Where the simulated bridge's configuration registers start.
pub const CTRL_BASE: u16 = 0xE000;
/// Ports of the configuration registers.
pub const CTRL_LEN: u16 = 0x100;
/// The simulated data port.
pub const DATA_BASE: u16 = 0xE400;

#[derive(Debug)]
struct State {
    ctrl: u32,
    /// The other local configuration registers, as written (all 0 at
    /// first, as an old 9030 EEPROM leaves LASxBRD's READY# bit).
    others: [u32; CTRL_LEN as usize / 4],
    fpga: ConfigPort,
    clear_reads: Option<u32>,
    done_stuck_low: bool,
    bytes: u64,
}

/// The simulated bridge and FPGA.
#[derive(Debug)]
pub struct SimPlxBridge {
    bridge: Bridge,
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
            state: Mutex::new(State {
                ctrl,
                others: [0; CTRL_LEN as usize / 4],
                fpga: ConfigPort::new(part),
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
        if s.done_stuck_low {
            return None;
        }
        s.fpga.design().map(str::to_string)
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
        if low {
            s.fpga.hold();
        } else {
            s.fpga.release(clear_reads);
        }
    }

    fn read_ctrl(&self) -> u32 {
        let mut s = self.lock();
        s.fpga.poll();
        let done = s.fpga.done() && !s.done_stuck_low;
        let init = s.fpga.init();
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
        if writing && s.fpga.take(byte) {
            s.bytes += 1;
        }
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
