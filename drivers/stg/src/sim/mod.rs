//! A register-level model of a Servo-To-Go Model I or Model II
//! (hardware.md §3.11), behind the layer's
//! [`SimBoard`](hal_driver::sim::SimBoard) as a port bus.
//!
//! The board decodes its two windows at its base address; every other
//! port reads all ones, as an empty ISA bus. Inside:
//!
//! * eight LS7166 counters ([`Ls7166`]), each counting the encoder of a
//!   [`ServoAxis`] (a DC motor, position in revolutions, with a
//!   quadrature encoder on its shaft) that DAC n drives through an
//!   amplifier of gain 1, enabled by the digital line its `amp_enable`
//!   names (port × 8 + bit, A = 0; a high output enables);
//! * eight 13-bit DACs; an ADC with its multiplexer, a conversion time,
//!   the end-of-conversion (Model I, in the 8259's IRR) or busy (Model
//!   II, BRDTST bit 3) flag;
//! * two 8255s ([`Ppi`]): digital ports A, B, C and D (whose lines are
//!   pulled up unless the outside pulls them low), and the board's own
//!   registers on 8255 #2: Model I port D, BRDTST and INTC; Model II
//!   CNTRL0, BRDTST and port D;
//! * the BRDTST signature, one bit per read;
//! * Model I: the 8259's initialisation sequence, IRR/ISR/IMR, and the
//!   index latches of the axis pair INTC selects, cleared by reading
//!   0x403 (even axis) and 0x407 (odd axis) unless the index is still
//!   active; Model II: IDLEN, SELDI, IDL and CNTRL1.
//!
//! Where the documents leave the board's behaviour open the model
//! chooses (the driver does not rely on these): an index loads the
//! latch (OL) only while its flag (Model II IDL bit, Model I latch) is
//! clear; a Model I latch also loads OL; a Model II ADC result is kept
//! per channel, a Model I result is one register; conversions take 20 µs
//! with auto-zero, 5 µs without; 8-bit writes to a DAC change one byte.

mod ls7166;
mod ppi;

pub use ls7166::Ls7166;
pub use ppi::Ppi;

use hal_driver::plant::{EncoderMove, ServoAxis};
use hal_driver::sim::{BoardModel, PortModel, Width};

use crate::detect::Model;
use crate::regs;

/// ADC conversion time with auto-zero.
pub const ADC_NS_AUTOZERO: u64 = 20_000;
/// ADC conversion time without.
pub const ADC_NS: u64 = 5_000;
/// The board model.
#[derive(Debug, Clone)]
pub struct StgModel {
    model: Model,
    base: u16,
    present: bool,
    now_ns: u64,
    signature_pos: u8,
    axes: Vec<ServoAxis>,
    counters: [Ls7166; regs::CHANNELS],
    dacs: [u16; regs::CHANNELS],
    adc_volts: [f64; regs::CHANNELS],
    adc_mux: usize,
    adc_busy: Option<(u64, usize)>,
    adc_result: u16,
    adc_results: [u16; regs::CHANNELS],
    eoc: bool,
    ppi: [Ppi; 2],
    lines_in: [u8; 4],
    // Model I.
    pic_init_step: u8,
    pic_imr: u8,
    pic_read_isr: bool,
    latched: [bool; 2],
    // Model II.
    idlen: u8,
    seldi: u8,
    idl: u8,
    cntrl1: u8,
    /// Accesses the board does not decode (the driver should make none).
    stray: u64,
}

impl StgModel {
    /// A `model` board at `base`, motors at rest at 0, every input line
    /// high.
    pub fn new(model: Model, base: u16) -> StgModel {
        StgModel {
            model,
            base,
            present: true,
            now_ns: 0,
            signature_pos: 0,
            axes: (0..regs::CHANNELS).map(|_| ServoAxis::default()).collect(),
            counters: Default::default(),
            dacs: [regs::DAC_ZERO; regs::CHANNELS],
            adc_volts: [0.0; regs::CHANNELS],
            adc_mux: 0,
            adc_busy: None,
            adc_result: 0,
            adc_results: [0; regs::CHANNELS],
            eoc: false,
            ppi: Default::default(),
            lines_in: [0xFF; 4],
            pic_init_step: 0,
            pic_imr: 0,
            pic_read_isr: false,
            latched: [false; 2],
            idlen: 0,
            seldi: 0,
            idl: 0,
            cntrl1: 0,
            stray: 0,
        }
    }

    /// Model I or II.
    pub fn model(&self) -> Model {
        self.model
    }

    /// The base address the jumpers select.
    pub fn base(&self) -> u16 {
        self.base
    }

    /// The board's simulated time.
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// Channel `k`'s mechanics.
    pub fn axis(&self, k: usize) -> &ServoAxis {
        &self.axes[k]
    }

    /// Channel `k`'s mechanics, to change.
    pub fn axis_mut(&mut self, k: usize) -> &mut ServoAxis {
        &mut self.axes[k]
    }

    /// Turns channel `k`'s shaft to `revs` by hand, counting and
    /// latching indexes on the way as when the motor turns it.
    pub fn turn_to(&mut self, k: usize, revs: f64) {
        self.move_shaft(k, |a| a.turn_to(revs));
    }

    /// Counter `k`'s CNTR.
    pub fn counter(&self, k: usize) -> u32 {
        self.counters[k].cntr(self.axes[k].encoder.count())
    }

    /// Counter `k`'s output latch.
    pub fn output_latch(&self, k: usize) -> u32 {
        self.counters[k].ol()
    }

    /// The word last written to DAC `n`.
    pub fn dac_word(&self, n: usize) -> u16 {
        self.dacs[n]
    }

    /// The voltage DAC `n` outputs.
    pub fn dac_volts(&self, n: usize) -> f64 {
        regs::dac_volts(self.dacs[n])
    }

    /// Applies `volts` to ADC input `n`.
    pub fn set_adc_volts(&mut self, n: usize, volts: f64) {
        self.adc_volts[n] = volts;
    }

    /// Sets the level the outside drives on digital port `port`'s lines
    /// (A = 0 .. D = 3); they read so where the port is an input.
    pub fn set_port_lines(&mut self, port: usize, levels: u8) {
        self.lines_in[port] = levels;
    }

    /// Pulls line `bit` of port `port` low (`low`) or lets it go high.
    pub fn set_line_low(&mut self, port: usize, bit: u8, low: bool) {
        if low {
            self.lines_in[port] &= !(1 << bit);
        } else {
            self.lines_in[port] |= 1 << bit;
        }
    }

    /// The levels the board drives on port `port`, `None` while it is an
    /// input (port C: when either nibble is).
    pub fn port_output(&self, port: usize) -> Option<u8> {
        let (chip, p) = self.dio_port(port);
        let (v, mask) = self.ppi[chip].driven(p);
        (mask == 0xFF).then_some(v)
    }

    /// The model I INTC register (8255 #2 port C).
    pub fn intc(&self) -> u8 {
        self.ppi[1].latch(2)
    }

    /// The Model II CNTRL0 register (8255 #2 port A).
    pub fn cntrl0(&self) -> u8 {
        self.ppi[1].latch(0)
    }

    /// The Model II index enables (IDLEN) and latched flags (IDL).
    pub fn index_registers(&self) -> (u8, u8) {
        (self.idlen, self.idl)
    }

    /// The Model II CNTRL1 register.
    pub fn cntrl1(&self) -> u8 {
        self.cntrl1
    }

    /// The Model I 8259's interrupt mask.
    pub fn pic_mask(&self) -> u8 {
        self.pic_imr
    }

    /// Accesses outside the board's windows, or of a width it does not
    /// decode, so far.
    pub fn stray_accesses(&self) -> u64 {
        self.stray
    }

    /// The board leaves the bus: every port reads all ones.
    pub fn unplug(&mut self) {
        self.present = false;
    }

    /// The board answers again.
    pub fn plug(&mut self) {
        self.present = true;
    }

    /// Which 8255 and which of its ports digital port `port` is.
    fn dio_port(&self, port: usize) -> (usize, usize) {
        match (port, self.model) {
            (3, Model::One) => (1, 0),
            (3, Model::Two) => (1, 2),
            (p, _) => (0, p),
        }
    }

    /// The line level on channel `k`'s index input, true while on the
    /// index.
    fn index_active(&self, k: usize) -> bool {
        let z = self.axes[k].encoder.z();
        match self.model {
            Model::One => z == (self.intc() & regs::INTC_IXLVL != 0),
            Model::Two => z,
        }
    }

    /// The Model I pair INTC selects: (even, odd) axis.
    fn selected_pair(&self) -> (usize, usize) {
        let p = ((self.intc() >> regs::INTC_IXS_SHIFT) & 3) as usize;
        (2 * p, 2 * p + 1)
    }

    /// Moves channel `k`'s shaft with `how`: the index latches and
    /// loads on the way.
    fn move_shaft(&mut self, k: usize, how: impl FnOnce(&mut ServoAxis) -> EncoderMove) {
        let was_active = self.index_active(k);
        let moved = how(&mut self.axes[k]);
        let now = self.axes[k].encoder.count();
        match self.model {
            Model::Two => {
                let bit = 1 << k;
                let armed = self.idlen & bit != 0 && self.seldi & bit == 0;
                if let (true, Some(at)) = (armed, moved.first_index) {
                    if self.idl & bit == 0 {
                        self.idl |= bit;
                        self.counters[k].index(at);
                    }
                }
            }
            Model::One => {
                let (even, odd) = self.selected_pair();
                if k != even && k != odd {
                    return;
                }
                let slot = k - even;
                let high = self.intc() & regs::INTC_IXLVL != 0;
                // With the level set for an active-high index, entering
                // the index is the event; with the other level, leaving
                // it (the line is active everywhere else).
                let event = if high {
                    moved.first_index
                } else if was_active != self.index_active(k) || moved.index_pulses > 0 {
                    Some(now)
                } else {
                    None
                };
                if let Some(at) = event {
                    if !self.latched[slot] {
                        self.counters[k].index(at);
                    }
                    self.latched[slot] = true;
                }
                if self.index_active(k) {
                    self.latched[slot] = true;
                }
            }
        }
    }

    /// The voltage channel `k`'s motor sees.
    fn drive_volts(&self, k: usize) -> f64 {
        let enabled = self.axes[k].amp_enable.is_none_or(|line| {
            self.port_output(line / 8)
                .is_some_and(|v| v & (1 << (line % 8)) != 0)
        });
        if enabled {
            self.dac_volts(k)
        } else {
            0.0
        }
    }

    fn brdtst(&mut self) -> u8 {
        let signature = match self.model {
            Model::One => regs::SIGNATURE_MODEL1,
            Model::Two => regs::SIGNATURE_MODEL2,
        };
        let q = self.signature_pos;
        self.signature_pos = (q + 1) & 7;
        let ser = if signature & (1 << q) != 0 {
            regs::BRDTST_SER
        } else {
            0
        };
        let low = match self.model {
            Model::One => 0,
            Model::Two if self.adc_busy.is_some() => regs::BRDTST_ADC_BUSY,
            Model::Two => 0,
        };
        ser | q << regs::BRDTST_Q_SHIFT | low
    }

    /// Clears Model I latch `slot` (0 even, 1 odd) unless its index is
    /// still active.
    fn clear_latch(&mut self, slot: usize) {
        let (even, _) = self.selected_pair();
        if !self.index_active(even + slot) {
            self.latched[slot] = false;
        }
    }

    fn irr(&self) -> u8 {
        let (even, odd) = self.selected_pair();
        let mut v = 0;
        if self.index_active(even) {
            v |= regs::IRR_IXEVN;
        }
        if self.index_active(odd) {
            v |= regs::IRR_IXODD;
        }
        if self.latched[0] {
            v |= regs::IRR_LIXEVN;
        }
        if self.latched[1] {
            v |= regs::IRR_LIXODD;
        }
        if self.eoc {
            v |= regs::IRR_EOC;
        }
        v
    }

    fn start_conversion(&mut self) {
        let autozero = match self.model {
            Model::One => self.intc() & regs::INTC_AUTOZERO != 0,
            Model::Two => self.cntrl0() & regs::CNTRL0_AUTOZERO != 0,
        };
        let channel = match self.model {
            Model::One => self.adc_mux,
            Model::Two => ((self.cntrl0() >> regs::CNTRL0_MUX_SHIFT) & 7) as usize,
        };
        let t = if autozero { ADC_NS_AUTOZERO } else { ADC_NS };
        self.adc_busy = Some((self.now_ns + t, channel));
        self.eoc = false;
    }

    fn read8(&mut self, off: u16) -> u8 {
        match off {
            0x00..=0x0F => {
                let k = counter_of(off);
                if regs::counter_data(k) == off {
                    self.counters[k].read_data()
                } else {
                    0xFF
                }
            }
            regs::PORT_A => self.ppi[0].read(0, self.lines_in[0]),
            regs::PORT_B => self.ppi[0].read(1, self.lines_in[1]),
            regs::PORT_C => self.ppi[0].read(2, self.lines_in[2]),
            regs::PORT_D_OR_CNTRL0 => self.ppi[1].read(0, self.lines_in[3]),
            regs::BRDTST => {
                let v = self.brdtst();
                if self.model == Model::One {
                    self.clear_latch(0);
                }
                v
            }
            regs::INTC_OR_PORT_D => self.ppi[1].read(2, self.lines_in[3]),
            regs::D_DIR => {
                if self.model == Model::One {
                    self.clear_latch(1);
                }
                0xFF
            }
            regs::IRR_OR_IDLEN if self.model == Model::One => {
                if self.pic_read_isr {
                    0
                } else {
                    self.irr()
                }
            }
            regs::IMR_OR_SELDI if self.model == Model::One => self.pic_imr,
            regs::IDL if self.model == Model::Two => self.idl,
            _ => 0xFF,
        }
    }

    fn write8(&mut self, off: u16, v: u8) {
        match off {
            0x00..=0x0F => {
                let k = counter_of(off);
                let shaft = self.axes[k].encoder.count();
                if regs::counter_control(k) == off {
                    self.counters[k].command(v, shaft);
                } else {
                    self.counters[k].write_data(v);
                }
            }
            0x10..=0x1F => {
                // One byte of a DAC word.
                let n = ((off - 0x10) / 2) as usize;
                let shift = 8 * (off % 2);
                self.dacs[n] = (self.dacs[n] & !(0xFF << shift)) | (v as u16) << shift;
            }
            regs::PORT_A => self.ppi[0].write(0, v),
            regs::PORT_B => self.ppi[0].write(1, v),
            regs::PORT_C => self.ppi[0].write(2, v),
            regs::PORT_D_OR_CNTRL0 => self.ppi[1].write(0, v),
            regs::INTC_OR_PORT_D => self.ppi[1].write(2, v),
            regs::ABC_DIR => self.ppi[0].write_control(v),
            regs::D_DIR => self.ppi[1].write_control(v),
            regs::IRR_OR_IDLEN => match self.model {
                Model::Two => self.idlen = v,
                Model::One if v & 0x10 != 0 => {
                    // ICW1: ICW2 follows; ICW3/4 are not expected (single,
                    // no ICW4 in the driver's 0x1A).
                    self.pic_init_step = 1;
                    self.pic_imr = 0;
                    self.pic_read_isr = false;
                }
                Model::One if v & 0x18 == 0x08 => {
                    // OCW3: bits 1..0 = 10 read IRR, 11 read ISR.
                    if v & 0x02 != 0 {
                        self.pic_read_isr = v & 0x01 != 0;
                    }
                }
                Model::One => {} // OCW2: no interrupts are in service.
            },
            regs::IMR_OR_SELDI => match self.model {
                Model::Two => self.seldi = v,
                Model::One if self.pic_init_step == 1 => self.pic_init_step = 0, // ICW2
                Model::One => self.pic_imr = v,
            },
            // Writing 0 clears every flag; writing 1 has no effect.
            regs::IDL if self.model == Model::Two && v == 0 => self.idl = 0,
            regs::CNTRL1 if self.model == Model::Two => self.cntrl1 = v,
            // The Model I 8254 timer and everything else: ignored.
            _ => {}
        }
    }

    fn read16(&mut self, off: u16) -> u16 {
        match off {
            0x410..=0x41F if off % 2 == 0 => {
                let n = ((off - 0x410) / 2) as usize;
                match self.model {
                    Model::One => {
                        self.adc_mux = n;
                        self.adc_result
                    }
                    Model::Two => self.adc_results[n],
                }
            }
            _ => {
                let lo = self.read8(off) as u16;
                lo | (self.read8(off + 1) as u16) << 8
            }
        }
    }

    fn write16(&mut self, off: u16, v: u16) {
        match off {
            0x10..=0x1F if off % 2 == 0 => self.dacs[((off - 0x10) / 2) as usize] = v,
            0x410..=0x41F if off % 2 == 0 => self.start_conversion(),
            _ => {
                self.write8(off, v as u8);
                self.write8(off + 1, (v >> 8) as u8);
            }
        }
    }

    /// The offset of `port` inside the board's windows, if it decodes it.
    fn decode(&self, port: u16, width: Width) -> Option<u16> {
        let off = port.wrapping_sub(self.base);
        let last = off.checked_add(width.bytes() - 1)?;
        let low = last < regs::WINDOW_LEN;
        let high = off >= regs::HIGH_WINDOW && last < regs::HIGH_WINDOW + regs::WINDOW_LEN;
        (self.present && (low || high) && width != Width::Long).then_some(off)
    }
}

/// The counter whose data or control port `off` is.
fn counter_of(off: u16) -> usize {
    // data(n) = 2n - n%2, control(n) = data(n) + 2.
    let pair = (off / 4) as usize;
    2 * pair + (off % 2) as usize
}

impl BoardModel for StgModel {
    fn advance(&mut self, dt_ns: u64) {
        self.now_ns += dt_ns;
        for k in 0..regs::CHANNELS {
            let v = self.drive_volts(k);
            self.move_shaft(k, |a| a.drive(v, dt_ns));
        }
        if let Some((done, ch)) = self.adc_busy {
            if done <= self.now_ns {
                let raw = regs::adc_raw(self.adc_volts[ch]);
                self.adc_result = raw;
                self.adc_results[ch] = raw;
                self.adc_busy = None;
                self.eoc = true;
            }
        }
    }

    fn describe(&self) -> String {
        format!("simulated Servo-To-Go {} at {:#x}", self.model, self.base)
    }
}

impl PortModel for StgModel {
    fn read(&mut self, port: u16, width: Width) -> u32 {
        let Some(off) = self.decode(port, width) else {
            self.stray += 1;
            return match width {
                Width::Byte => 0xFF,
                Width::Word => 0xFFFF,
                Width::Long => u32::MAX,
            };
        };
        match width {
            Width::Byte => self.read8(off) as u32,
            _ => self.read16(off) as u32,
        }
    }

    fn write(&mut self, port: u16, width: Width, value: u32) {
        let Some(off) = self.decode(port, width) else {
            self.stray += 1;
            return;
        };
        match width {
            Width::Byte => self.write8(off, value as u8),
            _ => self.write16(off, value as u16),
        }
    }
}

#[cfg(test)]
mod tests;
