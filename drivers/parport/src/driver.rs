//! The per-port read/write/reset algorithm of LinuxCNC's hal_parport
//! (hardware.md 2.3), independent of HAL pins: the HAL binding gathers
//! the output bits from pins and params, calls this, and publishes the
//! input bits.
//!
//! Register values are "HAL-true = electrically high": the status byte is
//! XORed with 0x80 and the control byte with 0x0B on the way in and out.
//! The last-written data and control bytes are cached in 16-bit cells
//! that start at 0xFF00, a value no byte can equal, so the first `write`
//! always reaches the hardware; later writes happen only on change.
//!
//! Data and control are each one `Latch`: cache, write time and reset
//! request. The state lives in atomics because `write` and `reset` of one
//! port may be in different threads (LinuxCNC requires them in the same
//! thread, but nothing enforces it).

use std::sync::atomic::{AtomicU16, AtomicU64, AtomicU8, Ordering::Relaxed};
use std::sync::Arc;

use crate::cfg::Mode;
use crate::clock::Clock;
use crate::port::{PortError, PortIo};
use crate::regs;

/// The cache value meaning "never written".
pub const NEVER_WRITTEN: u16 = 0xFF00;

/// What `write` should drive: every field is a bit mask in register bit
/// order (data bits 0..7 = pins 2..9; control bits 0..3 = pins 1, 14, 16,
/// 17), before the hardware-inversion correction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outputs {
    /// `pin-NN-out XOR pin-NN-out-invert` for the data pins.
    pub data: u8,
    /// Data pins whose `-out-reset` is set.
    pub data_reset_mask: u8,
    /// Their `-out-invert` (the level `reset` returns them to).
    pub data_reset_val: u8,
    /// `out XOR invert` for the control pins (low nibble).
    pub control: u8,
    /// Control pins whose `-out-reset` is set.
    pub control_reset_mask: u8,
    /// Their `-out-invert`.
    pub control_reset_val: u8,
}

/// What `read` found, corrected for the hardware inverters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Inputs {
    /// The status byte XOR 0x80 (pins 15, 13, 12, 10, 11 on bits 3..7).
    pub status: u8,
    /// The data byte, in `in` mode.
    pub data: Option<u8>,
    /// The control byte XOR 0x0B, in `x` mode (pins 1, 14, 16, 17 on
    /// bits 0..3).
    pub control: Option<u8>,
}

/// One output register's state: the last byte written, when, and what
/// `reset` should return to its inactive level.
struct Latch {
    /// The last byte written, before any inversion correction;
    /// [`NEVER_WRITTEN`] before the first write.
    cached: AtomicU16,
    /// When it was written (clock ns); `reset` waits from here.
    written_at: AtomicU64,
    /// Bits `reset` returns to `reset_val`.
    reset_mask: AtomicU8,
    /// Their inactive levels.
    reset_val: AtomicU8,
}

impl Latch {
    fn new() -> Latch {
        Latch {
            cached: AtomicU16::new(NEVER_WRITTEN),
            written_at: AtomicU64::new(0),
            reset_mask: AtomicU8::new(0),
            reset_val: AtomicU8::new(0),
        }
    }

    /// Puts `v` on the register with `put`, and remembers it and the time.
    #[inline]
    fn write(&self, v: u8, clock: &dyn Clock, put: impl FnOnce(u8)) {
        put(v);
        self.written_at.store(clock.now_ns(), Relaxed);
        self.cached.store(v as u16, Relaxed);
    }

    /// [`write`](Self::write), only if `v` differs from the last byte.
    #[inline]
    fn write_if_changed(&self, v: u8, clock: &dyn Clock, put: impl FnOnce(u8)) {
        if v as u16 != self.cached.load(Relaxed) {
            self.write(v, clock, put);
        }
    }

    /// Remembers which bits `reset` returns to which level.
    #[inline]
    fn set_reset(&self, mask: u8, val: u8) {
        self.reset_val.store(val, Relaxed);
        self.reset_mask.store(mask, Relaxed);
    }

    /// Returns the reset bits to their inactive levels with `put`, no
    /// earlier than `reset_time` ns after the last write (busy-waiting).
    /// A register never written is left alone: resetting it would drive
    /// pins (and, in `in` mode, clear the direction bit). The write time
    /// is kept, so the next `write` is timed from the real one.
    #[inline]
    fn reset(&self, reset_time: u32, clock: &dyn Clock, put: impl FnOnce(u8)) {
        let cached = self.cached.load(Relaxed);
        let out = ((cached & !(self.reset_mask.load(Relaxed) as u16))
            ^ self.reset_val.load(Relaxed) as u16) as u8;
        if cached != NEVER_WRITTEN && out as u16 != cached {
            let deadline = self
                .written_at
                .load(Relaxed)
                .wrapping_add(reset_time as u64);
            while clock.now_ns() < deadline {
                std::hint::spin_loop();
            }
            put(out);
            self.cached.store(out as u16, Relaxed);
        }
    }
}

/// One port's driver state and its register access.
pub struct PortDriver {
    mode: Mode,
    io: Arc<dyn PortIo>,
    clock: Arc<dyn Clock>,
    data: Latch,
    /// The control register, before the 0x0B correction.
    control: Latch,
}

impl std::fmt::Debug for PortDriver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PortDriver")
            .field("mode", &self.mode)
            .field("io", &self.io.describe())
            .field("data", &self.data.cached.load(Relaxed))
            .field("control", &self.control.cached.load(Relaxed))
            .finish()
    }
}

impl PortDriver {
    /// A driver for a claimed port in `mode`; `clock` times write/reset.
    pub fn new(mode: Mode, io: Arc<dyn PortIo>, clock: Arc<dyn Clock>) -> PortDriver {
        PortDriver {
            mode,
            io,
            clock,
            data: Latch::new(),
            control: Latch::new(),
        }
    }

    /// The port's mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The register access.
    pub fn io(&self) -> &Arc<dyn PortIo> {
        &self.io
    }

    /// Writes the data register.
    #[inline]
    fn put_data(&self) -> impl FnOnce(u8) + '_ {
        |v| self.io.write_data(v)
    }

    /// Writes the control register, correcting for its inverters.
    #[inline]
    fn put_control(&self) -> impl FnOnce(u8) + '_ {
        |v| self.io.write_control(v ^ regs::CONTROL_INVERTED)
    }

    /// The load-time set-up: `epp` puts the ECR in EPP mode (when the
    /// port has one); `in` sets the direction bit by reading the control
    /// register and writing it back with bit 5 set.
    pub fn init(&self) -> Result<(), PortError> {
        if self.mode == Mode::Epp && self.io.has_ecr() {
            self.io.write_ecr(regs::ECR_EPP_MODE)?;
        }
        if self.mode == Mode::In {
            let c = self.io.read_control();
            self.io.write_control(c | regs::CONTROL_DIR_IN);
        }
        if self.mode == Mode::X {
            // Release the open-collector control lines at once: claiming
            // the port may have left one pulled low until the first write.
            self.io
                .write_control(regs::CONTROL_LINES ^ regs::CONTROL_INVERTED);
        }
        Ok(())
    }

    /// `parport.N.read`: samples the input registers the mode uses.
    #[inline]
    pub fn read(&self) -> Inputs {
        Inputs {
            status: self.io.read_status() ^ regs::STATUS_INVERTED,
            data: (self.mode == Mode::In).then(|| self.io.read_data()),
            control: (self.mode == Mode::X)
                .then(|| self.io.read_control() ^ regs::CONTROL_INVERTED),
        }
    }

    /// `parport.N.write`: drives the output registers, each only if its
    /// byte changed, and remembers the reset masks for `reset`.
    #[inline]
    pub fn write(&self, o: &Outputs) {
        let clock = &*self.clock;
        let mut ctrl = if self.mode.data_out() {
            self.data.write_if_changed(o.data, clock, self.put_data());
            self.data.set_reset(o.data_reset_mask, o.data_reset_val);
            0x00
        } else {
            regs::CONTROL_DIR_IN
        };
        if self.mode.control_in() {
            // Released (high) so the open-collector lines can be read.
            ctrl |= regs::CONTROL_LINES;
        } else {
            ctrl |= o.control & regs::CONTROL_LINES;
            self.control.set_reset(
                o.control_reset_mask & regs::CONTROL_LINES,
                o.control_reset_val & regs::CONTROL_LINES,
            );
        }
        self.control
            .write_if_changed(ctrl, clock, self.put_control());
    }

    /// `parport.N.reset`: returns every pin marked for reset to its
    /// inactive level, no earlier than `reset_time` ns after the write
    /// that set it (busy-waiting). `reset_time` above a quarter of
    /// `period` is clamped; the value in force is returned so the caller
    /// can write it back into the parameter.
    #[inline]
    pub fn reset(&self, reset_time: u32, period: i64) -> u32 {
        let quarter = period / 4;
        let reset_time = if reset_time as i64 > quarter {
            quarter as u32
        } else {
            reset_time
        };
        let clock = &*self.clock;
        self.data.reset(reset_time, clock, self.put_data());
        self.control.reset(reset_time, clock, self.put_control());
        reset_time
    }

    /// Puts every output at its inactive level (`out` FALSE, i.e. the
    /// physical level of `-out-invert`), writing unconditionally.
    /// `data_invert`/`control_invert` are the invert bits in register
    /// order. The direction bit keeps its mode; `x` mode keeps its control
    /// lines released.
    pub fn safe_state(&self, data_invert: u8, control_invert: u8) {
        let clock = &*self.clock;
        let mut ctrl = 0;
        if self.mode.data_out() {
            self.data.write(data_invert, clock, self.put_data());
        } else {
            ctrl = regs::CONTROL_DIR_IN;
        }
        ctrl |= if self.mode.control_in() {
            regs::CONTROL_LINES
        } else {
            control_invert & regs::CONTROL_LINES
        };
        self.control.write(ctrl, clock, self.put_control());
    }
}

impl Drop for PortDriver {
    /// Gives the port back when the driver goes (module unload), and says
    /// once how many register accesses failed, if any did: the realtime
    /// functions cannot report them (a failed read reads as 0xFF).
    fn drop(&mut self) {
        let errors = self.io.errors();
        if errors > 0 {
            eprintln!(
                "hal_parport: {}: {errors} register accesses failed while loaded \
                 (failed reads read as 0xFF)",
                self.io.describe()
            );
        }
        self.io.release();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::SimClock;
    use crate::sim::{SimConfig, SimPort, WriteRecord};

    fn rig(mode: Mode) -> (PortDriver, Arc<SimPort>, Arc<SimClock>) {
        let clock = Arc::new(SimClock::new(1_000, 10));
        let sim = Arc::new(SimPort::new(SimConfig::new(0x378), clock.clone()));
        let drv = PortDriver::new(mode, sim.clone(), clock.clone());
        (drv, sim, clock)
    }

    fn values(w: &[WriteRecord]) -> Vec<(u16, u8)> {
        w.iter().map(|r| (r.addr, r.value)).collect()
    }

    #[test]
    fn x_mode_init_releases_the_control_lines() {
        let (d, sim, _) = rig(Mode::X);
        sim.write_control(0x0C); // what a claim may leave: pin 17 low
        sim.clear_log();
        d.init().unwrap();
        assert_eq!(values(&sim.writes()), vec![(0x37A, 0x0F ^ 0x0B)]);
    }

    #[test]
    fn first_write_always_reaches_the_hardware_then_only_changes() {
        let (d, sim, _) = rig(Mode::Out);
        let o = Outputs::default();
        d.write(&o);
        assert_eq!(values(&sim.writes()), vec![(0x378, 0x00), (0x37A, 0x0B)]);
        d.write(&o);
        assert_eq!(sim.writes().len(), 2, "nothing changed, nothing written");
        d.write(&Outputs { data: 0x81, ..o });
        d.write(&Outputs {
            data: 0x81,
            control: 0x0F,
            ..o
        });
        assert_eq!(
            values(&sim.writes()[2..]),
            vec![(0x378, 0x81), (0x37A, 0x0F ^ 0x0B)]
        );
    }

    #[test]
    fn in_mode_sets_direction_and_reads_data() {
        let (d, sim, _) = rig(Mode::In);
        d.init().unwrap();
        assert_eq!(sim.control_latch() & 0x20, 0x20);
        sim.set_input(2, false);
        sim.set_input(9, false);
        let i = d.read();
        assert_eq!(i.data, Some(0x7E));
        assert_eq!(i.control, None);
        d.write(&Outputs {
            data: 0xFF,
            control: 0x05,
            ..Default::default()
        });
        // Data is never written in `in` mode; control keeps bit 5.
        assert_eq!(values(&sim.writes()[1..]), vec![(0x37A, 0x25 ^ 0x0B)]);
        assert_eq!(sim.control_latch() & 0x20, 0x20);
    }

    #[test]
    fn status_is_corrected_for_the_busy_inverter() {
        let (d, sim, _) = rig(Mode::Out);
        assert_eq!(d.read().status & 0xF8, 0xF8, "all pins high reads all true");
        sim.set_input(11, false);
        sim.set_input(15, false);
        assert_eq!(d.read().status & 0xF8, 0x70);
        assert_eq!(d.read().data, None);
    }

    #[test]
    fn x_mode_releases_control_lines_and_reads_them() {
        let (d, sim, _) = rig(Mode::X);
        d.write(&Outputs {
            control: 0x00,
            control_reset_mask: 0x0F,
            ..Default::default()
        });
        assert_eq!(sim.control_latch(), 0x0F ^ 0x0B);
        assert_eq!(d.read().control, Some(0x0F));
        sim.set_input(14, false);
        sim.set_input(17, false);
        assert_eq!(d.read().control, Some(0x05));
        // The control reset mask is not taken in x mode.
        sim.clear_log();
        d.reset(0, 1_000_000);
        assert!(sim.writes().is_empty());
    }

    #[test]
    fn epp_writes_the_ecr_at_init() {
        let (d, sim, _) = rig(Mode::Epp);
        d.init().unwrap();
        assert_eq!(sim.ecr(), 0x94);
        assert_eq!(values(&sim.writes()), vec![(0x77A, 0x94)]);
    }

    #[test]
    fn reset_waits_for_reset_time_then_returns_pins_to_invert() {
        let (d, sim, clock) = rig(Mode::Out);
        let o = Outputs {
            data: 0b0000_0011,
            data_reset_mask: 0b0000_0011,
            data_reset_val: 0b0000_0010,
            control: 0b0001,
            control_reset_mask: 0b0001,
            control_reset_val: 0,
        };
        d.write(&o);
        let w = sim.writes();
        let (t_data, t_ctrl) = (w[0].time_ns, w[1].time_ns);
        clock.advance(0);
        assert_eq!(d.reset(5_000, 1_000_000), 5_000);
        let r = sim.writes();
        assert_eq!(values(&r[2..]), vec![(0x378, 0b10), (0x37A, 0x0B)]);
        assert!(
            r[2].time_ns >= t_data + 5_000,
            "{} vs {}",
            r[2].time_ns,
            t_data
        );
        assert!(r[2].time_ns < t_data + 5_000 + 100);
        assert!(r[3].time_ns >= t_ctrl + 5_000);
        // A second reset has nothing left to do.
        d.reset(5_000, 1_000_000);
        assert_eq!(sim.writes().len(), 4);
        // The next write with the same request drives the pins again.
        d.write(&o);
        assert_eq!(
            values(&sim.writes()[4..]),
            vec![(0x378, 0b11), (0x37A, 0x0A)]
        );
    }

    #[test]
    fn reset_time_is_clamped_to_a_quarter_period() {
        let (d, _, _) = rig(Mode::Out);
        assert_eq!(d.reset(30_000, 100_000), 25_000);
        assert_eq!(d.reset(25_000, 100_000), 25_000);
        assert_eq!(d.reset(u32::MAX, 50_003), 12_500);
        assert_eq!(d.reset(7, 3), 0, "period/4 truncates like C");
    }

    #[test]
    fn reset_before_any_write_touches_nothing() {
        // Until `write` has set a register, `reset` has nothing to return
        // to its inactive level; writing the caches' placeholder would
        // drive every pin and, in `in` mode, clear the direction bit.
        for mode in [Mode::Out, Mode::In, Mode::X] {
            let (d, sim, _) = rig(mode);
            sim.clear_log();
            d.reset(0, 1_000_000);
            assert!(
                sim.writes().is_empty(),
                "{mode:?}: {:?}",
                values(&sim.writes())
            );
        }
    }

    #[test]
    fn reset_with_no_reset_pins_writes_nothing() {
        let (d, sim, _) = rig(Mode::Out);
        d.write(&Outputs {
            data: 0xF0,
            control: 0x3,
            ..Default::default()
        });
        sim.clear_log();
        d.reset(1_000, 1_000_000);
        assert!(sim.writes().is_empty());
    }

    #[test]
    fn safe_state_drives_inactive_levels() {
        let (d, sim, _) = rig(Mode::Out);
        d.write(&Outputs {
            data: 0xFF,
            control: 0x0F,
            ..Default::default()
        });
        d.safe_state(0x81, 0x04);
        assert_eq!(sim.data_latch(), 0x81);
        assert_eq!(sim.control_latch(), 0x04 ^ 0x0B);
        assert_eq!(d.data.cached.load(Relaxed), 0x81);
        assert_eq!(d.control.cached.load(Relaxed), 0x04);
        let (d, sim, _) = rig(Mode::In);
        d.safe_state(0xFF, 0x01);
        assert_eq!(sim.control_latch(), (0x21) ^ 0x0B);
        assert!(sim.writes_to(regs::DATA).is_empty());
        let (d, sim, _) = rig(Mode::X);
        d.safe_state(0x00, 0x00);
        assert_eq!(sim.control_latch(), 0x0F ^ 0x0B);
    }
}
