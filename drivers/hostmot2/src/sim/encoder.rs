//! Simulated quadrature counters (hardware.md 5.9.3): a 16-bit up/down
//! counter per instance fed by the world's encoder lines, the timestamp
//! counter and the count's timestamp, index and probe latches with the
//! one-shot ("JustOnce") self-clear, sticky quadrature errors and the
//! live A/B/Z bits.
//!
//! The index fires on every index pulse the shaft enters, whatever the
//! polarity bit (the simulated Z pulse has no edge shape); with
//! `index-mask` set it fires only while the IndexMask input is at the
//! chosen level. In counter mode the counter counts whole A cycles.

use super::world::EncoderIn;
use crate::regs::encoder as r;

/// One counter.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counter {
    /// The 16-bit count.
    pub count: u16,
    /// Timestamp of the last count change.
    pub stamp: u16,
    /// Latched count.
    pub latch: u16,
    /// Control bits (15..3).
    pub control: u32,
    /// The shaft count seen last.
    pub shaft: i64,
    /// Probe input level seen last.
    pub probe_level: bool,
    /// Live lines.
    pub lines: u32,
}

/// The encoder module.
#[derive(Debug, Clone, Default)]
pub struct SimEncoders {
    /// Per instance.
    pub counters: Vec<Counter>,
    /// Timestamp divider register.
    pub tsdiv: u32,
    /// Filter rate register.
    pub filter_rate: u32,
    /// Timestamp counter, extended.
    pub tsc: u64,
    tsc_rem: u64,
}

impl SimEncoders {
    /// `n` counters.
    pub fn new(n: usize) -> SimEncoders {
        SimEncoders {
            counters: vec![Counter::default(); n],
            ..Default::default()
        }
    }

    /// ClockLow ticks per timestamp tick.
    fn divider(&self) -> u64 {
        if self.tsdiv & 0x8000 != 0 {
            1
        } else {
            (self.tsdiv & 0xFFFF) as u64 + 2
        }
    }

    /// A register read.
    pub fn read(&self, reg: usize, inst: usize) -> u32 {
        match reg {
            r::COUNTER => self
                .counters
                .get(inst)
                .map_or(0, |c| (c.stamp as u32) << 16 | c.count as u32),
            r::LATCH_CONTROL => self.counters.get(inst).map_or(0, |c| {
                (c.latch as u32) << 16 | (c.control & r::WRITABLE) | c.lines
            }),
            r::TSDIV => self.tsdiv,
            r::TSCOUNT => self.tsc as u32 & 0xFFFF,
            r::FILTER_RATE => self.filter_rate,
            _ => 0,
        }
    }

    /// A register write.
    pub fn write(&mut self, reg: usize, inst: usize, v: u32) {
        match reg {
            r::COUNTER => {
                if let Some(c) = self.counters.get_mut(inst) {
                    c.count = 0;
                }
            }
            r::LATCH_CONTROL => {
                if let Some(c) = self.counters.get_mut(inst) {
                    // Writing the error bit clears the sticky error.
                    let sticky = if v & r::QUAD_ERROR != 0 {
                        0
                    } else {
                        c.control & r::QUAD_ERROR
                    };
                    c.control = (v & r::WRITABLE & !r::QUAD_ERROR) | sticky;
                }
            }
            r::TSDIV => self.tsdiv = v & 0xFFFF,
            r::FILTER_RATE => self.filter_rate = v,
            _ => {}
        }
    }

    /// The timestamp counter `ago_ns` before now, with `clock` Hz.
    fn stamp_at(&self, ago_ns: u64, clock: u64) -> u16 {
        let ago_ticks = ago_ns as u128 * clock as u128 / 1_000_000_000 / self.divider() as u128;
        self.tsc.wrapping_sub(ago_ticks as u64) as u16
    }

    /// Advances the timestamp counter by `low_ticks` of ClockLow.
    pub fn tick(&mut self, low_ticks: u64) {
        let d = self.divider();
        let total = self.tsc_rem + low_ticks;
        self.tsc = self.tsc.wrapping_add(total / d);
        self.tsc_rem = total % d;
    }

    /// Takes one time step's line activity for counter `i`. `probe` is
    /// the probe input level, `mask` the index mask input level.
    pub fn sense(&mut self, i: usize, e: &EncoderIn, probe: bool, mask: bool, clock: u64) {
        let stamp_of_edge = self.stamp_at(e.last_edge_ago_ns, clock);
        let Some(c) = self.counters.get_mut(i) else {
            return;
        };
        let counter_mode = c.control & r::COUNTER_MODE != 0;
        let units = |shaft: i64| {
            if counter_mode {
                shaft.div_euclid(4)
            } else {
                shaft
            }
        };
        let start = c.count;
        let delta = units(e.count) - units(c.shaft);
        let index = e.index_at.filter(|_| {
            c.control & r::INDEX_MASK == 0 || mask == (c.control & r::INDEX_MASK_POLARITY != 0)
        });
        let mut count = start.wrapping_add(delta as u16);
        if let Some(at) = index {
            let at_count = start.wrapping_add((units(at) - units(c.shaft)) as u16);
            if c.control & r::LATCH_ON_INDEX != 0 {
                c.latch = at_count;
            }
            if c.control & r::CLEAR_ON_INDEX != 0 {
                count = count.wrapping_sub(at_count);
            }
            if c.control & r::JUST_ONCE != 0 {
                c.control &= !(r::LATCH_ON_INDEX | r::CLEAR_ON_INDEX);
            }
        }
        let polarity = c.control & r::PROBE_POLARITY != 0;
        if c.control & r::LATCH_ON_PROBE != 0 && probe != c.probe_level && probe == polarity {
            c.latch = count;
            if c.control & r::JUST_ONCE != 0 {
                c.control &= !r::LATCH_ON_PROBE;
            }
        }
        c.probe_level = probe;
        if delta != 0 {
            c.stamp = stamp_of_edge;
        }
        if e.glitch {
            c.control |= r::QUAD_ERROR;
        }
        c.count = count;
        c.shaft = e.count;
        c.lines = [(e.a, r::INPUT_A), (e.b, r::INPUT_B), (e.z, r::INPUT_INDEX)]
            .iter()
            .filter(|(on, _)| *on)
            .fold(0, |w, (_, bit)| w | bit);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLOCK: u64 = 100_000_000;

    fn moved(count: i64) -> EncoderIn {
        EncoderIn {
            count,
            ..Default::default()
        }
    }

    #[test]
    fn counts_latches_and_clears_once() {
        let mut s = SimEncoders::new(1);
        s.sense(0, &moved(100), false, true, CLOCK);
        assert_eq!(s.read(r::COUNTER, 0) & 0xFFFF, 100);
        s.write(r::LATCH_CONTROL, 0, r::LATCH_ON_INDEX | r::JUST_ONCE);
        let e = EncoderIn {
            count: 150,
            index_at: Some(120),
            ..Default::default()
        };
        s.sense(0, &e, false, true, CLOCK);
        let lc = s.read(r::LATCH_CONTROL, 0);
        assert_eq!(lc >> 16, 120, "latched where the index was");
        assert_eq!(lc & r::LATCH_ON_INDEX, 0, "self-cleared");
        assert_eq!(s.read(r::COUNTER, 0) & 0xFFFF, 150);
        // Backwards through zero: the 16-bit counter wraps.
        s.sense(0, &moved(-10), false, true, CLOCK);
        assert_eq!(s.read(r::COUNTER, 0) & 0xFFFF, 0xFFF6);
        s.write(r::COUNTER, 0, 0);
        assert_eq!(s.read(r::COUNTER, 0) & 0xFFFF, 0, "a write clears");
    }

    #[test]
    fn counter_mode_probe_and_errors() {
        let mut s = SimEncoders::new(1);
        s.write(
            r::LATCH_CONTROL,
            0,
            r::COUNTER_MODE | r::LATCH_ON_PROBE | r::PROBE_POLARITY,
        );
        s.sense(0, &moved(40), false, true, CLOCK);
        assert_eq!(s.read(r::COUNTER, 0) & 0xFFFF, 10, "one count per A cycle");
        s.sense(0, &moved(44), true, true, CLOCK);
        assert_eq!(
            s.read(r::LATCH_CONTROL, 0) >> 16,
            11,
            "latched on the rising probe"
        );
        let glitch = EncoderIn {
            count: 44,
            glitch: true,
            ..Default::default()
        };
        s.sense(0, &glitch, true, true, CLOCK);
        assert_ne!(s.read(r::LATCH_CONTROL, 0) & r::QUAD_ERROR, 0);
        s.write(r::LATCH_CONTROL, 0, r::COUNTER_MODE);
        assert_ne!(s.read(r::LATCH_CONTROL, 0) & r::QUAD_ERROR, 0, "sticky");
        s.write(r::LATCH_CONTROL, 0, r::COUNTER_MODE | r::QUAD_ERROR);
        assert_eq!(
            s.read(r::LATCH_CONTROL, 0) & r::QUAD_ERROR,
            0,
            "cleared by writing 1"
        );
    }

    #[test]
    fn timestamps() {
        let mut s = SimEncoders::new(1);
        s.write(r::TSDIV, 0, 48); // 2 MHz at 100 MHz
        s.tick(100_000); // 1 ms: 2000 ticks
        assert_eq!(s.read(r::TSCOUNT, 0), 2000);
        let e = EncoderIn {
            count: 1,
            last_edge_ago_ns: 250_000,
            ..Default::default()
        };
        s.sense(0, &e, false, true, CLOCK);
        assert_eq!(s.read(r::COUNTER, 0) >> 16, 1500, "stamped 0.25 ms ago");
    }
}
