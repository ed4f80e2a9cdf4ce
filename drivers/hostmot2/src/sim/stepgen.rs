//! Simulated step generators (hardware.md 5.9.4): a 48-bit DDS
//! accumulator per instance (16 integer step bits, 32 fraction bits) to
//! which the signed Rate is added at ClockLow × MasterDDS / 2^32 per
//! second; the readable accumulator is bits 47..16.
//!
//! A step is due whenever the integer part changes; the output makes them
//! no faster than the timing registers allow (a register holding N means
//! N + 1 clocks, a step takes PulseWidth + PulseIdle and a reversal adds
//! DirSetup + DirHold), so a rate above that makes the steps lag behind
//! the accumulator, as a step line cannot pulse faster than its timing.
//! Firmware 0xC2 latches the accumulator on an index or probe edge.

use crate::regs::stepgen as r;

/// One step generator.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Gen {
    /// Rate register.
    pub rate: u32,
    /// Accumulator, unwrapped (48-bit register = low 48 bits).
    pub acc: i128,
    /// Mode register.
    pub mode: u32,
    /// DirSetup, DirHold, PulseWidth, PulseIdle registers.
    pub timing: [u32; 4],
    /// Table words as written (last phase first).
    pub table: Vec<u32>,
    /// TableLength register.
    pub table_len: u32,
    /// Latched accumulator (bits 31..8 readable).
    pub latched: u32,
    /// Steps made at the output so far.
    pub emitted: i64,
    /// Clock ticks available for steps not yet made.
    budget: u64,
    /// Direction of the last step.
    pub forward: bool,
    index_level: bool,
    probe_level: bool,
}

impl Gen {
    /// The accumulator register (bits 47..16).
    pub fn accumulator(&self) -> u32 {
        (self.acc >> 16) as u32
    }

    /// Whole steps the accumulator holds.
    pub fn target_steps(&self) -> i64 {
        (self.acc >> 32) as i64
    }

    /// Clocks one step takes at the output.
    pub fn clocks_per_step(&self) -> u64 {
        (self.timing[2] as u64 + 1) + (self.timing[3] as u64 + 1)
    }

    fn clocks_per_reversal(&self) -> u64 {
        (self.timing[0] as u64 + 1) + (self.timing[1] as u64 + 1)
    }
}

/// The step generator module.
#[derive(Debug, Clone, Default)]
pub struct SimStepgens {
    /// Per instance.
    pub gens: Vec<Gen>,
    /// MasterDDS register.
    pub master_dds: u32,
    dds: u64,
}

impl SimStepgens {
    /// `n` generators.
    pub fn new(n: usize) -> SimStepgens {
        SimStepgens {
            gens: vec![Gen::default(); n],
            ..Default::default()
        }
    }

    /// A register read.
    pub fn read(&self, reg: usize, inst: usize) -> u32 {
        if reg == r::MASTER_DDS {
            return self.master_dds;
        }
        let Some(g) = self.gens.get(inst) else {
            return 0;
        };
        match reg {
            r::RATE => g.rate,
            r::ACCUMULATOR => g.accumulator(),
            r::MODE => (g.latched & 0xFFFF_FF00) | (g.mode & 0xFF),
            r::DIR_SETUP => g.timing[0],
            r::DIR_HOLD => g.timing[1],
            r::PULSE_WIDTH => g.timing[2],
            r::PULSE_IDLE => g.timing[3],
            r::TABLE_LENGTH => g.table_len,
            _ => 0,
        }
    }

    /// A register write.
    pub fn write(&mut self, reg: usize, inst: usize, v: u32) {
        if reg == r::MASTER_DDS {
            self.master_dds = v;
            return;
        }
        let Some(g) = self.gens.get_mut(inst) else {
            return;
        };
        let t = v & r::TIMING_MAX;
        match reg {
            r::RATE => g.rate = v,
            r::ACCUMULATOR => {
                let old = g.acc;
                let reg48 = (v as i128) << 16;
                // Keep the unwrapped history: replace the low 48 bits.
                g.acc = (old & !((1i128 << 48) - 1)) | reg48;
                g.emitted += g.target_steps() - (old >> 32) as i64;
            }
            r::MODE => g.mode = v,
            r::DIR_SETUP => g.timing[0] = t,
            r::DIR_HOLD => g.timing[1] = t,
            r::PULSE_WIDTH => g.timing[2] = t,
            r::PULSE_IDLE => g.timing[3] = t,
            r::TABLE_DATA => {
                if g.table.len() >= r::TABLE_MAX as usize {
                    g.table.remove(0);
                }
                g.table.push(v);
            }
            r::TABLE_LENGTH => g.table_len = v & 0xF,
            _ => {}
        }
    }

    /// Lets `ticks` of ClockLow pass; returns nothing, steps made are
    /// read from each [`Gen::emitted`].
    pub fn advance(&mut self, ticks: u64) {
        let total = self.dds as u128 + ticks as u128 * self.master_dds as u128;
        let additions = (total >> 32) as i128;
        self.dds = total as u64 & 0xFFFF_FFFF;
        for g in &mut self.gens {
            g.acc += (g.rate as i32 as i128) * additions;
            g.budget += ticks;
            let per_step = g.clocks_per_step();
            let mut pending = g.target_steps() - g.emitted;
            while pending != 0 {
                let forward = pending > 0;
                let cost = per_step
                    + if forward != g.forward {
                        g.clocks_per_reversal()
                    } else {
                        0
                    };
                if g.budget < cost {
                    break;
                }
                let n = if forward == g.forward {
                    (g.budget / per_step).min(pending.unsigned_abs()) as i64
                } else {
                    1
                };
                g.budget -= if forward == g.forward {
                    n as u64 * per_step
                } else {
                    cost
                };
                g.forward = forward;
                g.emitted += if forward { n } else { -n };
                pending = g.target_steps() - g.emitted;
            }
            if pending == 0 {
                // Idle time does not save up faster steps for later.
                g.budget = g.budget.min(per_step);
            }
        }
    }

    /// Takes the index and probe input levels of generator `i`
    /// (firmware 0xC2): an edge of the chosen polarity latches the
    /// accumulator once.
    pub fn sense(&mut self, i: usize, index: bool, probe: bool) {
        let Some(g) = self.gens.get_mut(i) else {
            return;
        };
        let acc = g.accumulator();
        let edge = |was: bool, now: bool, polarity: bool| was != now && now == polarity;
        if g.mode & r::MODE_LATCH_ON_INDEX != 0
            && edge(g.index_level, index, g.mode & r::MODE_INDEX_POLARITY != 0)
        {
            g.latched = acc;
            g.mode &= !r::MODE_LATCH_ON_INDEX;
        }
        if g.mode & r::MODE_LATCH_ON_PROBE != 0
            && edge(g.probe_level, probe, g.mode & r::MODE_PROBE_POLARITY != 0)
        {
            g.latched = acc;
            g.mode &= !r::MODE_LATCH_ON_PROBE;
        }
        g.index_level = index;
        g.probe_level = probe;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLOCK: u64 = 100_000_000;

    fn gen_at(rate_hz: f64) -> SimStepgens {
        let mut s = SimStepgens::new(1);
        s.write(r::MASTER_DDS, 0, 0xFFFF_FFFF);
        let rate = (rate_hz * 4_294_967_296.0 / CLOCK as f64) as i32 as u32;
        s.write(r::RATE, 0, rate);
        s
    }

    #[test]
    fn the_accumulator_integrates_the_rate() {
        let mut s = gen_at(10_000.0);
        s.advance(CLOCK / 10); // 100 ms
        let steps = s.gens[0].target_steps();
        assert!((999..=1000).contains(&steps), "{steps}");
        assert_eq!(s.read(r::ACCUMULATOR, 0) >> 16, steps as u32);
        assert_eq!(s.gens[0].emitted, steps, "timing 0: every step made");
        let mut s = gen_at(-10_000.0);
        s.advance(CLOCK / 10);
        assert!((-1000..=-999).contains(&s.gens[0].target_steps()));
    }

    #[test]
    fn timing_limits_the_output_rate() {
        let mut s = gen_at(200_000.0);
        // 5 us + 5 us per step: at most 100 kHz at the output.
        s.write(r::PULSE_WIDTH, 0, 499);
        s.write(r::PULSE_IDLE, 0, 499);
        s.advance(CLOCK / 100); // 10 ms
        let g = &s.gens[0];
        assert!((1999..=2000).contains(&g.target_steps()));
        assert!((999..=1001).contains(&g.emitted), "{}", g.emitted);
    }

    #[test]
    fn latches_on_an_index_edge_once() {
        let mut s = gen_at(1_000.0);
        s.write(r::MODE, 0, r::MODE_LATCH_ON_INDEX | r::MODE_INDEX_POLARITY);
        s.advance(CLOCK / 100);
        s.sense(0, false, false);
        s.sense(0, true, false);
        let m = s.read(r::MODE, 0);
        assert_eq!(m & r::MODE_LATCH_ON_INDEX, 0);
        assert_eq!(m >> 8, s.gens[0].accumulator() >> 8);
    }
}
