//! Register models of the five Pico boards: what each answers on the
//! EPP bus, at offsets from its first byte ([`crate::regs`] has the map).
//!
//! Counters count the motor positions the port model hands them
//! ([`Counters::follow`]), latch on the bus's strobe, flag and (when
//! armed) clear at the index; the DAC, step and PWM generators keep what
//! was written for the port model to turn into motor velocities. A USC
//! or UPC drives its step/PWM outputs and its digital outputs only while
//! its estop output is on and the safety chain is closed; its estop
//! input reads 1 only then. A DIO board's estop input reads 1 while the
//! board is in estop. A board made a slave follows the estop output of
//! the bus's first board with an estop circuit ([`super::PpmcPort::enabled`]).

use crate::regs::{self, ctrl, dac, dio, enc, pwm, stepgen, uxc, ID_OFFSET};
use crate::scan::{BoardId, Kind};

/// Motor counts between two index pulses.
pub const INDEX_COUNTS: i64 = 4000;
/// Counter width.
const MASK24: u32 = 0xFF_FFFF;

/// Four 24-bit counters with index latch, strobe latch and timestamps.
#[derive(Debug, Clone, Default)]
pub struct Counters {
    count: [u32; 4],
    latched: [u32; 4],
    load: [u8; 3],
    /// Index seen since the ISR was last read.
    isr: u8,
    /// Counters to clear at their next index.
    arm: u8,
    stamp: [u16; 4],
    stamp_latched: [u16; 4],
    base_latched: u16,
    /// Whether this board drives the strobe.
    pub master: bool,
    /// The filter clock code written.
    pub clock: u8,
    last_pos: [i64; 4],
}

impl Counters {
    /// Moves counter `ch` to motor position `pos`, the last count made at
    /// timebase `stamp`.
    pub fn follow(&mut self, ch: usize, pos: i64, stamp: u16) {
        let from = self.last_pos[ch];
        if pos == from {
            return;
        }
        self.last_pos[ch] = pos;
        self.stamp[ch] = stamp;
        let (lo, hi) = (from.min(pos), from.max(pos));
        // The index marks lie at multiples of INDEX_COUNTS.
        let crossed = hi.div_euclid(INDEX_COUNTS) != lo.div_euclid(INDEX_COUNTS);
        if crossed {
            self.isr |= 1 << ch;
            if self.arm & (1 << ch) != 0 {
                let mark = if pos > from {
                    hi.div_euclid(INDEX_COUNTS) * INDEX_COUNTS
                } else {
                    (lo.div_euclid(INDEX_COUNTS) + 1) * INDEX_COUNTS
                };
                self.count[ch] = (pos - mark) as u32 & MASK24;
                return;
            }
        }
        self.count[ch] = self.count[ch].wrapping_add((pos - from) as u32) & MASK24;
    }

    /// The bus's latch strobe: counts, stamps and the timebase `now`.
    pub fn latch(&mut self, now: u16) {
        self.latched = self.count;
        self.stamp_latched = self.stamp;
        self.base_latched = now;
    }

    /// The live count of channel `ch` (24 bits).
    pub fn count(&self, ch: usize) -> u32 {
        self.count[ch]
    }

    /// The index-clear bits written.
    pub fn armed(&self) -> u8 {
        self.arm
    }

    /// A counter register read (`None`: not a counter register).
    fn read(&mut self, off: u8, stamps: bool) -> Option<u8> {
        Some(match off {
            0x00..=0x0B => {
                let ch = (off / enc::COUNT_BYTES) as usize;
                (self.latched[ch] >> (8 * (off % enc::COUNT_BYTES))) as u8
            }
            enc::ISR => std::mem::take(&mut self.isr),
            0x10..=0x17 if stamps => {
                let ch = ((off - enc::TS0) / 2) as usize;
                (self.stamp_latched[ch] >> (8 * (off & 1))) as u8
            }
            0x18..=0x19 if stamps => (self.base_latched >> (8 * (off & 1))) as u8,
            _ => return None,
        })
    }

    /// A counter register write; whether the board asked for a strobe.
    fn write(&mut self, off: u8, v: u8) -> Option<bool> {
        match off {
            0x00..=0x02 => self.load[off as usize] = v,
            enc::CTRL => {
                if v & enc::CTRL_RESET_ALL == enc::CTRL_RESET_ALL {
                    let preset = u32::from_le_bytes([self.load[0], self.load[1], self.load[2], 0]);
                    self.count = [preset; 4];
                }
            }
            enc::RATE => {
                self.master = v & enc::RATE_MASTER != 0 || self.master;
                return Some(v & enc::RATE_STROBE != 0);
            }
            enc::CLOCK => self.clock = v,
            enc::INDEX => self.arm = v & 0x0F,
            _ => return None,
        }
        Some(false)
    }
}

/// A simulated board in its slot.
#[derive(Debug, Clone)]
pub struct Board {
    /// Its ID.
    pub id: BoardId,
    /// Its first slot.
    pub slot: usize,
    /// Counters (encoder board, USC, UPC).
    pub counters: Option<Counters>,
    /// Registers written that the model keeps as they are (DAC codes,
    /// divisors, control bytes, outputs).
    pub written: [u8; regs::SPAN],
    /// The digital input lines (inputs 0..15; a USC/UPC's input 15 is
    /// its estop input and reads from the estop circuit instead).
    pub inputs: u16,
    /// A USC/UPC made a slave of the first one's estop.
    pub slave: bool,
}

impl Board {
    /// A board `id` in `slot`, as it powers up (outputs off).
    pub fn new(id: BoardId, slot: usize) -> Board {
        let mut written = [0; regs::SPAN];
        if id.kind == Kind::Dac {
            // The DACs come up at mid-scale: 0 V.
            for ch in 0..4u8 {
                regs::put_le(&mut written, dac::DAC0 + 2 * ch, dac::ZERO as u32, 2);
            }
        }
        Board {
            id,
            slot,
            counters: id.kind.has_encoders().then(Counters::default),
            written,
            inputs: 0,
            slave: false,
        }
    }

    /// The bytes the board decodes.
    pub fn span(&self) -> usize {
        self.id.slots() * regs::SLOT_SIZE as usize
    }

    /// Whether the board's estop output is on (UxC: DOUT bit 7; DIO:
    /// ESTOP_OUT bit 0). Other boards have none and count as on.
    pub fn estop_out(&self) -> bool {
        match self.id.kind {
            Kind::Usc | Kind::Upc => self.written[uxc::DOUT as usize] & uxc::ESTOP_BIT != 0,
            Kind::Dio => self.written[dio::ESTOP_OUT as usize] & 1 != 0,
            _ => true,
        }
    }

    /// Whether the board's estop follows another's: a USC/UPC told so
    /// through its slave register, a DIO board through its estop
    /// register's slave value.
    pub fn is_slave(&self) -> bool {
        match self.id.kind {
            Kind::Usc | Kind::Upc => self.slave,
            Kind::Dio => self.written[dio::ESTOP_OUT as usize] == dio::SLAVE,
            _ => false,
        }
    }

    /// Whether the board has an estop circuit (digital I/O).
    pub fn has_estop(&self) -> bool {
        self.id.kind.is_uxc() || self.id.kind == Kind::Dio
    }

    /// Reads the byte at `off`; `enabled`: the estop circuit is closed
    /// and the estop output on.
    pub fn read(&mut self, off: u8, enabled: bool) -> u8 {
        if off == ID_OFFSET {
            return self.id.byte();
        }
        let stamps = self.id.has_timestamps();
        if let Some(c) = self.counters.as_mut() {
            if let Some(v) = c.read(off, stamps) {
                return v;
            }
        }
        match (self.id.kind, off) {
            (Kind::Usc | Kind::Upc, uxc::DIN_A) => self.inputs as u8,
            (Kind::Usc | Kind::Upc, uxc::DIN_B) => {
                let hi = (self.inputs >> 8) as u8 & !uxc::ESTOP_BIT;
                hi | if enabled { uxc::ESTOP_BIT } else { 0 }
            }
            (Kind::Dio, dio::DIN_A) => self.inputs as u8,
            (Kind::Dio, dio::DIN_B) => (self.inputs >> 8) as u8,
            (Kind::Dio, dio::ESTOP_IN) => u8::from(!enabled),
            _ => 0,
        }
    }

    /// Writes the byte at `off`; whether it was a latch strobe.
    pub fn write(&mut self, off: u8, v: u8) -> bool {
        if let Some(c) = self.counters.as_mut() {
            if let Some(strobe) = c.write(off, v) {
                return strobe;
            }
        }
        if self.id.kind.is_uxc() && off == uxc::SLAVE {
            self.slave = v & 1 != 0;
        }
        if let Some(b) = self.written.get_mut(off as usize) {
            *b = v;
        }
        false
    }

    /// The output byte as driven: UxC DOUT / DIO DOUT, 0 while a UxC is
    /// in estop.
    pub fn outputs(&self, enabled: bool) -> u8 {
        match self.id.kind {
            Kind::Usc | Kind::Upc if enabled => self.written[uxc::DOUT as usize],
            Kind::Dio => self.written[dio::DOUT as usize],
            _ => 0,
        }
    }

    /// The extra port's byte (USC/UPC), 0 while in estop.
    pub fn extra(&self, enabled: bool) -> u8 {
        if self.id.kind.is_uxc() && enabled {
            self.written[uxc::EXTRA as usize]
        } else {
            0
        }
    }

    /// DAC channel `ch`'s output in volts (DAC board).
    pub fn dac_volts(&self, ch: usize) -> f64 {
        let at = dac::DAC0 as usize + 2 * ch;
        let code = u16::from_le_bytes([self.written[at], self.written[at + 1]]);
        (code as f64 - 32768.0) / 32767.0 * dac::FULL_SCALE_V
    }

    fn run_dir(&self, ch: usize, reg: u8) -> (bool, f64) {
        let bits = self.written[reg as usize] >> (2 * ch);
        let dir = if bits & ctrl::FORWARD != 0 { 1.0 } else { -1.0 };
        (bits & ctrl::RUN != 0, dir)
    }

    /// Step generator `ch`'s signed rate in steps/s (USC), 0 when stopped
    /// or in estop.
    pub fn step_rate(&self, ch: usize, enabled: bool) -> f64 {
        let (run, dir) = self.run_dir(ch, stepgen::CTRL);
        if !(run && enabled) {
            return 0.0;
        }
        let at = stepgen::RATE0 + 3 * ch as u8;
        let mut b = [0u8; regs::SPAN];
        b.copy_from_slice(&self.written);
        let div = regs::get_le(&b, at, 3) + stepgen::DIVISOR_OFFSET;
        dir * stepgen::CLOCK_HZ / div as f64
    }

    /// PWM generator `ch`'s signed duty cycle (UPC), 0 when disabled or in
    /// estop.
    pub fn pwm_duty(&self, ch: usize, enabled: bool) -> f64 {
        let (run, dir) = self.run_dir(ch, pwm::CTRL);
        if !(run && enabled) {
            return 0.0;
        }
        let w = &self.written;
        let start = u16::from_le_bytes([w[pwm::FREQ_LO as usize], w[pwm::FREQ_HI as usize]]);
        let period = 65536 - start as u32;
        let at = pwm::GEN0 as usize + 2 * ch;
        let stop = u16::from_le_bytes([w[at], w[at + 1]]);
        let len = 65535 - stop as u32;
        dir * (len as f64 / period as f64).min(1.0)
    }
}
