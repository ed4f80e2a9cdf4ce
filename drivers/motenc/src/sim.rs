//! A register-level model of a MOTENC-100 or MOTENC-Lite (hardware.md
//! §4.5), behind the layer's [`SimBoard`](hal_driver::sim::SimBoard) so
//! the driver runs on it exactly as on the card.
//!
//! The outside world: each encoder channel k is a [`ServoAxis`] (a DC
//! motor, position in revolutions, with a quadrature encoder on its
//! shaft) driven by DAC k through an amplifier of gain 1, enabled by the
//! output its `amp_enable` names (0..31); the counter counts that encoder. Digital inputs, the E-stop
//! input and the ADC voltages are set by hand; digital outputs and DAC
//! voltages are read back. Everything moves only in
//! [`advance`](BoardModel::advance).
//!
//! Behaviour the documents do not settle, modelled as follows (the
//! driver does not depend on these choices):
//!
//! * Index: a channel armed by writing 1 to its encoderCount zeroes its
//!   counter at the first index pulse crossed and sets its latched flag;
//!   writing 0 disarms it and clears the flag.
//! * Watchdog: enabled by control bit 2, it bites when no restart (0x5A
//!   to watchdogReset, or a DAC write with control bit 4) came for 8 ms
//!   (16 ms with bit 0). A bitten board holds every DAC at 0 V and every
//!   output off until 0x5A is written; writing the control register
//!   restarts the count but does not end a bite.
//! * The ADC converts the selected list in 5 µs per channel; status bit
//!   18 is set meanwhile; results are read in list order, 14-bit.
//! * digitalIo reads back the written outputs in its low half; an absent
//!   FPGA 1 (Lite) and unlisted offsets read 0.
//! * [`unplug`](MotencModel::unplug) makes every register read all ones
//!   and ignore writes, as a board that left the bus.

use hal_driver::plant::ServoAxis;
use hal_driver::sim::{BoardModel, MemModel};

use crate::board::BoardKind;
use crate::regs;

/// Conversion time of one ADC channel.
pub const ADC_NS_PER_CHANNEL: u64 = 5_000;

/// The most inputs a board has (MOTENC-100).
const MAX_INPUTS: usize = 68;

/// The board model.
#[derive(Debug, Clone)]
pub struct MotencModel {
    kind: BoardKind,
    jumper_id: u8,
    version_reg: u32,
    present: bool,
    now_ns: u64,
    axes: Vec<ServoAxis>,
    counter_zero: [i64; 8],
    armed: [bool; 8],
    latched: [bool; 8],
    dac_codes: [u32; regs::DACS],
    adc_volts: [f64; regs::ADCS],
    adc_command: u32,
    adc_busy_until: Option<u64>,
    adc_results: [u32; regs::ADCS],
    adc_count: usize,
    adc_next: usize,
    inputs_on: [bool; MAX_INPUTS],
    estop: bool,
    outputs_word: [u32; 2],
    watchdog_control: u32,
    last_kick_ns: u64,
    bitten: bool,
    bites: u64,
    bitten_at_ns: Option<u64>,
    timer: [u32; 3],
}

impl MotencModel {
    /// A board of `kind` with ID jumpers `jumper_id` (0..3), its motors
    /// at rest at 0, inputs off, nothing written yet.
    pub fn new(kind: BoardKind, jumper_id: u8) -> MotencModel {
        MotencModel {
            kind,
            jumper_id: jumper_id & 3,
            version_reg: kind.version(),
            present: true,
            now_ns: 0,
            axes: (0..kind.encoders()).map(|_| ServoAxis::default()).collect(),
            counter_zero: [0; 8],
            armed: [false; 8],
            latched: [false; 8],
            dac_codes: [regs::DAC_ZERO; regs::DACS],
            adc_volts: [0.0; regs::ADCS],
            adc_command: 0,
            adc_busy_until: None,
            adc_results: [0; regs::ADCS],
            adc_count: 0,
            adc_next: 0,
            inputs_on: [false; MAX_INPUTS],
            estop: false,
            outputs_word: [0xFFFF_FFFF; 2],
            watchdog_control: 0,
            last_kick_ns: 0,
            bitten: false,
            bites: 0,
            bitten_at_ns: None,
            timer: [0; 3],
        }
    }

    /// The kind of board.
    pub fn kind(&self) -> BoardKind {
        self.kind
    }

    /// The board's simulated time.
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// Encoder channel `k`'s mechanics.
    pub fn axis(&self, k: usize) -> &ServoAxis {
        &self.axes[k]
    }

    /// Encoder channel `k`'s mechanics, to change.
    pub fn axis_mut(&mut self, k: usize) -> &mut ServoAxis {
        &mut self.axes[k]
    }

    /// Turns encoder `k`'s shaft to `revs` by hand, counting and
    /// latching on the way as when the motor turns it.
    pub fn turn_to(&mut self, k: usize, revs: f64) {
        let moved = self.axes[k].turn_to(revs);
        self.sense_index(k, moved.first_index);
    }

    /// The hardware counter of encoder `k`.
    pub fn counter(&self, k: usize) -> i32 {
        (self.axes[k].encoder.count() - self.counter_zero[k]) as i32
    }

    /// Whether encoder `k` is armed to clear on the next index.
    pub fn index_armed(&self, k: usize) -> bool {
        self.armed[k]
    }

    /// Whether encoder `k` latched an index since it was armed.
    pub fn index_latched(&self, k: usize) -> bool {
        self.latched[k]
    }

    /// Switches digital input `n` on (pulled low) or off.
    pub fn set_input(&mut self, n: usize, on: bool) {
        if n < self.kind.inputs() {
            self.inputs_on[n] = on;
        }
    }

    /// Sets the E-stop input (status bit 19).
    pub fn set_estop(&mut self, active: bool) {
        self.estop = active;
    }

    /// Whether digital output `n` is on (driven low, not held off by a
    /// bitten watchdog).
    pub fn output(&self, n: usize) -> bool {
        let (fpga, bit) = (n / regs::OUTPUTS_PER_FPGA, n % regs::OUTPUTS_PER_FPGA);
        n < self.kind.outputs() && !self.bitten && self.outputs_word[fpga] & (1 << bit) == 0
    }

    /// The word last written to FPGA `fpga`'s digitalIo (outputs
    /// active low in bits 15..0), whatever the watchdog does.
    pub fn outputs_written(&self, fpga: usize) -> u32 {
        self.outputs_word[fpga]
    }

    /// The code last written to DAC `n`.
    pub fn dac_code(&self, n: usize) -> u32 {
        self.dac_codes[n]
    }

    /// The voltage DAC `n` outputs (0 V while the watchdog has bitten).
    pub fn dac_volts(&self, n: usize) -> f64 {
        if self.bitten {
            0.0
        } else {
            regs::dac_volts(self.dac_codes[n])
        }
    }

    /// Applies `volts` to ADC input `n`.
    pub fn set_adc_volts(&mut self, n: usize, volts: f64) {
        self.adc_volts[n] = volts;
    }

    /// Whether the watchdog has bitten (and not been restarted since).
    pub fn watchdog_bitten(&self) -> bool {
        self.bitten
    }

    /// When the watchdog last bit, in board time.
    pub fn watchdog_bitten_at(&self) -> Option<u64> {
        self.bitten_at_ns
    }

    /// How many times the watchdog has bitten.
    pub fn watchdog_bites(&self) -> u64 {
        self.bites
    }

    /// The watchdog control register.
    pub fn watchdog_control(&self) -> u32 {
        self.watchdog_control
    }

    /// Whether the timer interrupt is disabled.
    pub fn timer_irq_disabled(&self) -> bool {
        self.timer[1] & 1 != 0
    }

    /// The board leaves the bus: reads all ones, writes vanish.
    pub fn unplug(&mut self) {
        self.present = false;
    }

    /// The board answers again.
    pub fn plug(&mut self) {
        self.present = true;
    }

    /// Makes boardVersion read `value` (a damaged or foreign board).
    pub fn set_version_register(&mut self, value: u32) {
        self.version_reg = value;
    }

    /// Encoder `k` crossed an index at shaft count `first_index`: an
    /// armed counter clears there and latches.
    fn sense_index(&mut self, k: usize, first_index: Option<i64>) {
        if let Some(at) = first_index {
            if self.armed[k] && !self.latched[k] {
                self.counter_zero[k] = at;
                self.latched[k] = true;
            }
        }
    }

    /// The voltage axis `k`'s motor sees.
    fn drive_volts(&self, k: usize) -> f64 {
        let enabled = self.axes[k].amp_enable.is_none_or(|o| self.output(o));
        if enabled {
            self.dac_volts(k)
        } else {
            0.0
        }
    }

    /// Inputs `first..first + count` as an active-low word, input
    /// `first` on bit 0.
    fn input_word(&self, first: usize, count: usize) -> u32 {
        (0..count)
            .filter(|i| !self.inputs_on[first + i])
            .fold(0, |w, i| w | 1 << i)
    }

    fn status(&self, fpga: usize) -> u32 {
        let mut s = if fpga == 0 {
            self.input_word(16, 16)
                | (self.jumper_id as u32) << regs::STATUS_ID_SHIFT
                | if self.adc_busy_until.is_some() {
                    regs::STATUS_ADC_BUSY
                } else {
                    0
                }
                | if self.estop { regs::STATUS_ESTOP } else { 0 }
        } else {
            self.input_word(48, 20)
        };
        for j in 0..regs::ENCODERS_PER_FPGA {
            let k = fpga * regs::ENCODERS_PER_FPGA + j;
            if self.axes[k].encoder.z() {
                s |= 1 << (regs::STATUS_INDEX_SHIFT + j as u32);
            }
            if self.latched[k] {
                s |= 1 << (regs::STATUS_LATCH_SHIFT + j as u32);
            }
        }
        s
    }

    fn kick(&mut self) {
        self.last_kick_ns = self.now_ns;
    }

    fn finish_adc(&mut self) {
        let list = regs::adc_command_channels(self.adc_command);
        self.adc_count = list.len();
        self.adc_next = 0;
        for (i, ch) in list.enumerate() {
            self.adc_results[i] = regs::adc_raw(self.adc_volts[ch]);
        }
        self.adc_busy_until = None;
    }
}

impl BoardModel for MotencModel {
    fn advance(&mut self, dt_ns: u64) {
        self.now_ns += dt_ns;
        let c = self.watchdog_control;
        if c & regs::WATCHDOG_ENABLE != 0
            && !self.bitten
            && self.now_ns - self.last_kick_ns > regs::watchdog_timeout_ns(c)
        {
            self.bitten = true;
            self.bites += 1;
            self.bitten_at_ns = Some(self.now_ns);
        }
        for k in 0..self.axes.len() {
            let volts = self.drive_volts(k);
            let moved = self.axes[k].drive(volts, dt_ns);
            self.sense_index(k, moved.first_index);
        }
        if self.adc_busy_until.is_some_and(|t| t <= self.now_ns) {
            self.finish_adc();
        }
    }

    fn describe(&self) -> String {
        format!("simulated {} (ID {})", self.kind, self.jumper_id)
    }
}

impl MemModel for MotencModel {
    fn len(&self) -> usize {
        regs::SIM_WINDOW_LEN
    }

    fn read32(&mut self, offset: usize) -> u32 {
        if !self.present {
            return hal_driver::bus::ALL_ONES;
        }
        let fpgas = self.kind.fpgas();
        match offset {
            o if o < 2 * regs::FPGA_STRIDE && o / regs::FPGA_STRIDE >= fpgas => 0,
            o if o < 2 * regs::FPGA_STRIDE => {
                let (fpga, reg) = (o / regs::FPGA_STRIDE, o % regs::FPGA_STRIDE);
                match reg {
                    0x00..=0x0C => self.counter(fpga * regs::ENCODERS_PER_FPGA + reg / 4) as u32,
                    0x10 => {
                        self.input_word(fpga * 32, 16) << 16 | (self.outputs_word[fpga] & 0xFFFF)
                    }
                    0x14 => self.status(fpga),
                    0x1C => self.version_reg,
                    _ => 0,
                }
            }
            regs::ADC_DATA_COMMAND if self.adc_next < self.adc_count => {
                self.adc_next += 1;
                self.adc_results[self.adc_next - 1]
            }
            _ => 0,
        }
    }

    fn write32(&mut self, offset: usize, value: u32) {
        if !self.present {
            return;
        }
        let fpgas = self.kind.fpgas();
        match offset {
            o if o < 2 * regs::FPGA_STRIDE => {
                let (fpga, reg) = (o / regs::FPGA_STRIDE, o % regs::FPGA_STRIDE);
                if fpga >= fpgas {
                    return;
                }
                match reg {
                    0x00..=0x0C => {
                        let k = fpga * regs::ENCODERS_PER_FPGA + reg / 4;
                        self.armed[k] = value & 1 != 0;
                        if !self.armed[k] {
                            self.latched[k] = false;
                        }
                    }
                    0x10 => self.outputs_word[fpga] = value,
                    0x14 => {
                        for j in 0..regs::ENCODERS_PER_FPGA {
                            if value & (1 << j) != 0 {
                                let k = fpga * regs::ENCODERS_PER_FPGA + j;
                                self.counter_zero[k] = self.axes[k].encoder.count();
                            }
                        }
                    }
                    _ => {}
                }
            }
            regs::TIMER_COMPARE | regs::TIMER_IRQ_DISABLE | regs::TIMER_IRQ_ENABLE => {
                self.timer[(offset - regs::TIMER_COMPARE) / 4] = value;
            }
            regs::WATCHDOG_CONTROL => {
                self.watchdog_control = value;
                self.kick();
            }
            regs::WATCHDOG_RESET if value == regs::WATCHDOG_KICK => {
                self.kick();
                self.bitten = false;
            }
            o if (regs::dac(0)..=regs::dac(regs::DACS - 1)).contains(&o) => {
                self.dac_codes[(o - regs::dac(0)) / 4] = value;
                if self.watchdog_control & regs::WATCHDOG_DAC_RESETS != 0 && !self.bitten {
                    self.kick();
                }
            }
            regs::ADC_DATA_COMMAND => self.adc_command = value,
            regs::ADC_START if value & 1 != 0 => {
                let n = regs::adc_command_channels(self.adc_command).len() as u64;
                self.adc_busy_until = Some(self.now_ns + n.max(1) * ADC_NS_PER_CHANNEL);
                self.adc_count = 0;
                self.adc_next = 0;
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::board::{identify, Motenc};
    use hal_driver::bus::RegWindow;
    use hal_driver::sim::SimBoard;
    use std::sync::Arc;

    fn board(kind: BoardKind) -> (Arc<SimBoard<MotencModel>>, Motenc) {
        let sim = Arc::new(SimBoard::new(MotencModel::new(kind, 0)));
        let id = identify(&*sim).unwrap();
        let drv = Motenc::new(sim.clone(), id);
        drv.init();
        (sim, drv)
    }

    #[test]
    fn dac_voltage_turns_the_motor_and_the_counter_counts() {
        let (sim, drv) = board(BoardKind::Motenc100);
        drv.write_dac(2, regs::dac_code(-2.0));
        sim.advance(1_000_000_000);
        // -2 V on 2 rev/s/V with 0.05 V friction: about -3.9 rev/s after
        // the 20 ms time constant.
        let c = drv.count(2) as i32;
        assert!((-16_000..-15_000).contains(&c), "{c}");
        assert_eq!(c, sim.with(|m| m.counter(2)));
        assert_eq!(drv.count(3), 0, "other channels stand still");
        drv.bus().write32(regs::status_control(0), 1 << 2);
        assert_eq!(drv.count(2), 0, "statusControl bit resets the counter");
    }

    #[test]
    fn armed_index_zeroes_the_counter_and_latches() {
        let (sim, drv) = board(BoardKind::Motenc100);
        sim.with(|m| m.turn_to(5, 0.25));
        drv.arm_index(5, true);
        sim.with(|m| m.turn_to(5, 1.5)); // index at 4000
        assert_eq!(drv.count(5), 2000, "counts since the index");
        let st = drv.status(1);
        assert_ne!(st & 1 << (regs::STATUS_LATCH_SHIFT + 1), 0);
        drv.arm_index(5, false);
        assert_eq!(drv.status(1) & 0xF << regs::STATUS_LATCH_SHIFT, 0);
        sim.with(|m| m.turn_to(5, 2.0)); // index at 8000 while disarmed
        assert_eq!(drv.count(5), 4000, "not cleared when disarmed");
        assert_ne!(drv.status(1) & 1 << (regs::STATUS_INDEX_SHIFT + 1), 0);
    }

    #[test]
    fn adc_converts_lists_in_time() {
        let (sim, drv) = board(BoardKind::MotencLite);
        for n in 0..8 {
            sim.with(|m| m.set_adc_volts(n, n as f64 * 0.5 - 2.0));
        }
        drv.adc_start(regs::ADC_CMD_CH4_7);
        assert_ne!(drv.status(0) & regs::STATUS_ADC_BUSY, 0);
        sim.advance(19_999);
        assert_ne!(drv.status(0) & regs::STATUS_ADC_BUSY, 0, "4 x 5 us");
        sim.advance(1);
        assert_eq!(drv.status(0) & regs::STATUS_ADC_BUSY, 0);
        let got: Vec<i32> = (0..4).map(|_| drv.adc_result()).collect();
        let want: Vec<i32> = (4..8)
            .map(|n| ((n as f64 * 0.5 - 2.0) / regs::ADC_VOLTS_PER_COUNT).round() as i32)
            .collect();
        assert_eq!(got, want);
    }

    #[test]
    fn inputs_and_outputs_are_active_low() {
        let (sim, drv) = board(BoardKind::Motenc100);
        sim.with(|m| {
            m.set_input(0, true);
            m.set_input(17, true);
            m.set_input(33, true);
            m.set_input(66, true);
        });
        assert_eq!(drv.digital_io(0) >> 16, 0xFFFE);
        assert_eq!(drv.status(0) & 0xFFFF, 0xFFFD);
        assert_eq!(drv.digital_io(1) >> 16, 0xFFFD);
        assert_eq!(drv.status(1) & 0xF_FFFF, 0xB_FFFF);
        assert!(!sim.with(|m| m.output(3)), "init turned outputs off");
        drv.write_outputs(0, 1 << 3);
        drv.write_outputs(1, 1 << 15);
        assert!(sim.with(|m| m.output(3) && m.output(31) && !m.output(4)));
    }

    #[test]
    fn watchdog_bites_without_kicks_and_holds_outputs_off() {
        let (sim, drv) = board(BoardKind::Motenc100);
        drv.write_outputs(0, 1);
        drv.write_dac(0, regs::dac_code(5.0));
        drv.set_watchdog(regs::WATCHDOG_ENABLE | regs::WATCHDOG_DAC_RESETS);
        for _ in 0..20 {
            sim.advance(1_000_000);
            drv.write_dac(0, regs::dac_code(5.0));
        }
        assert!(!sim.with(|m| m.watchdog_bitten()), "DAC writes restart it");
        sim.advance(8_000_000);
        assert!(!sim.with(|m| m.watchdog_bitten()), "8 ms is not past 8 ms");
        sim.advance(1);
        assert!(sim.with(|m| m.watchdog_bitten()));
        assert!(sim.with(|m| m.dac_volts(0) == 0.0 && !m.output(0)));
        drv.write_dac(0, regs::dac_code(5.0));
        sim.advance(1_000_000);
        assert!(
            sim.with(|m| m.watchdog_bitten()),
            "a DAC write does not end it"
        );
        drv.kick_watchdog();
        assert!(sim.with(|m| !m.watchdog_bitten() && m.output(0)));
        assert!((sim.with(|m| m.dac_volts(0)) - 5.0).abs() < 0.01);
        drv.set_watchdog(regs::WATCHDOG_ENABLE | regs::WATCHDOG_16MS);
        sim.advance(12_000_000);
        assert!(!sim.with(|m| m.watchdog_bitten()), "16 ms timebase");
        sim.advance(5_000_000);
        assert_eq!(sim.with(|m| m.watchdog_bites()), 2);
    }

    #[test]
    fn an_unplugged_board_reads_all_ones() {
        let (sim, drv) = board(BoardKind::Motenc100);
        sim.with(|m| m.unplug());
        assert_eq!(drv.status(0), u32::MAX);
        assert!(!drv.answers());
        sim.with(|m| m.plug());
        assert!(drv.answers());
    }

    #[test]
    fn amplifier_enable_output_gates_the_motor() {
        let (sim, drv) = board(BoardKind::Motenc100);
        sim.with(|m| m.axis_mut(0).amp_enable = Some(7));
        drv.write_dac(0, regs::dac_code(3.0));
        sim.advance(100_000_000);
        assert_eq!(drv.count(0), 0, "amplifier off");
        drv.write_outputs(0, 1 << 7);
        sim.advance(100_000_000);
        assert!(drv.count(0) as i32 > 100);
    }
}
