//! `stepgen.make-pulses`: the per-channel DDS, step timers and output
//! waveform, independent of HAL pins.
//!
//! The position accumulator `accum` is a fixed-point step count with
//! [`PICKOFF`] fraction bits; every call adds `addval` to it, and a step
//! happens whenever bit `PICKOFF` changes (the position crossed k + 0.5
//! steps, since it starts at half a step).

use super::steptype::StepType;

/// Fraction bits of the accumulator.
pub const PICKOFF: u32 = 28;

/// The accumulator's start value: half a step.
pub const HALF_STEP: i64 = 1 << (PICKOFF - 1);

/// The DDS registers that make-pulses and update-freq share.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dds {
    /// Position in steps, [`PICKOFF`] fraction bits, offset by half a step.
    pub accum: i64,
    /// What make-pulses adds to `accum` per call.
    pub addval: i64,
    /// The `addval` update-freq asks for.
    pub target_addval: i64,
    /// Largest change of `addval` per make-pulses call (0 = no limit).
    pub deltalim: i64,
}

impl Default for Dds {
    fn default() -> Dds {
        Dds {
            accum: HALF_STEP,
            addval: 0,
            target_addval: 0,
            deltalim: 0,
        }
    }
}

impl Dds {
    /// Whole steps, floor-rounded: `rawcounts` and `counts`.
    #[inline(always)]
    pub fn counts(&self) -> i32 {
        (self.accum >> PICKOFF) as i32
    }
}

/// The timing values make-pulses reads each call (ns): the current values
/// of `steplen`, the hold time (`dirhold` for type 0, `dirdelay` for the
/// others) and `dirsetup` (0 except for type 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PulseTiming {
    /// Step pulse length.
    pub steplen: u32,
    /// Time the direction is held after a step.
    pub hold: u32,
    /// Extra time before the DDS may reverse (type 0's `dirsetup`).
    pub setup: u32,
}

impl Default for PulseTiming {
    /// The parameters' defaults: 1 ns each, no setup.
    fn default() -> PulseTiming {
        PulseTiming {
            steplen: 1,
            hold: 1,
            setup: 0,
        }
    }
}

/// What make-pulses keeps per channel besides the shared DDS registers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PulseGen {
    step_type: StepType,
    /// Time left of the step pulse (`steplen`).
    pub timer1: u32,
    /// Time left until the direction may change (pulse + hold).
    pub timer2: u32,
    /// Time left until the DDS may reverse (pulse + hold + setup).
    pub timer3: u32,
    /// The DDS is frozen until `timer3` expires (a reversal came too soon).
    pub hold_dds: bool,
    /// Direction of the last motion: -1, 0 (none yet) or +1.
    pub curr_dir: i32,
    /// Position in the phase table (types 2..15).
    pub state: i32,
}

/// Result of one make-pulses call of one channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PulseResult {
    /// The DDS advanced this call (enabled and not frozen); only then is
    /// `rawcounts` rewritten.
    pub advanced: bool,
    /// A step happened this call.
    pub step: bool,
}

impl PulseGen {
    /// A channel of the given type in its load-time state.
    pub fn new(step_type: StepType) -> PulseGen {
        PulseGen {
            step_type,
            timer1: 0,
            timer2: 0,
            timer3: 0,
            hold_dds: false,
            curr_dir: 0,
            state: 0,
        }
    }

    /// One make-pulses call for this channel: `period` is the thread's
    /// period in ns, `enable` the enable pin; `timing` reads the current
    /// timing parameters, and is called only when a step happens (as
    /// LinuxCNC reads them only then). Updates `dds.accum` and
    /// `dds.addval`.
    #[inline]
    pub fn update(
        &mut self,
        period: i64,
        enable: bool,
        timing: impl FnOnce() -> PulseTiming,
        dds: &mut Dds,
    ) -> PulseResult {
        // Count the timers down (compared as 64-bit signed values, as the
        // C code compares an unsigned int with a long).
        let count_down = |t: &mut u32| -> bool {
            if *t > 0 {
                if i64::from(*t) > period {
                    *t = (i64::from(*t) - period) as u32;
                } else {
                    *t = 0;
                    return true;
                }
            }
            false
        };
        count_down(&mut self.timer1);
        count_down(&mut self.timer2);
        if count_down(&mut self.timer3) {
            self.hold_dds = false;
        }

        // Ramp addval toward the target, at most deltalim per call.
        if !self.hold_dds && enable {
            let old = dds.addval;
            let tgt = dds.target_addval;
            let lim = dds.deltalim;
            let new = if lim != 0 {
                if tgt > old.wrapping_add(lim) {
                    old.wrapping_add(lim)
                } else if tgt < old.wrapping_sub(lim) {
                    old.wrapping_sub(lim)
                } else {
                    tgt
                }
            } else {
                tgt
            };
            dds.addval = new;
            // A reversal (zero counts as positive) must wait for timer3.
            if (new >= 0) != (old >= 0) && self.timer3 != 0 {
                self.hold_dds = true;
            }
        }

        // Advance the accumulator.
        let mut result = PulseResult {
            advanced: false,
            step: false,
        };
        if !self.hold_dds && enable {
            let before = dds.accum;
            dds.accum = before.wrapping_add(dds.addval);
            result.advanced = true;
            result.step = (before ^ dds.accum) & (1 << PICKOFF) != 0;
        }

        // The direction follows addval once the hold time is over.
        if self.timer2 == 0 {
            if dds.addval > 0 {
                self.curr_dir = 1;
            } else if dds.addval < 0 {
                self.curr_dir = -1;
            }
        }

        if result.step {
            let timing = timing();
            self.timer1 = timing.steplen;
            self.timer2 = self.timer1.wrapping_add(timing.hold);
            self.timer3 = self.timer2.wrapping_add(timing.setup);
            if self.step_type.kind() >= 2 {
                let cycle_max = self.step_type.cycle_len() as i32 - 1;
                self.state = self.state.wrapping_add(self.curr_dir);
                if self.state < 0 {
                    self.state = cycle_max;
                } else if self.state > cycle_max {
                    self.state = 0;
                }
            }
        }
        result
    }

    /// The output bits after the last call: type 0 bit 0 = step, bit 1 =
    /// dir; type 1 bit 0 = up, bit 1 = down; types 2..15 bit p = phase p.
    #[inline(always)]
    pub fn outputs(&self) -> u8 {
        match self.step_type.kind() {
            0 => u8::from(self.timer1 != 0) | u8::from(self.curr_dir < 0) << 1,
            1 => {
                if self.timer1 == 0 {
                    0
                } else if self.curr_dir < 0 {
                    2
                } else {
                    1
                }
            }
            _ => self.step_type.pattern(self.state),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stepgen::model::Stepgen;
    use crate::stepgen::ChannelConfig;

    const ONE_STEP: i64 = 1 << PICKOFF;

    /// A one-channel module of type `kind`, enabled, with the default
    /// make-pulses timing (1 ns pulse and hold, no setup) whatever the
    /// type.
    fn chan(kind: u8) -> Stepgen {
        let mut sg = Stepgen::new(&[ChannelConfig {
            step_type: StepType::builtin(kind).unwrap(),
            velocity_mode: false,
        }]);
        sg.chans[0].enable = true;
        set_timing(&mut sg, PulseTiming::default());
        sg
    }

    /// Sets the timing parameters make-pulses reads.
    fn set_timing(sg: &mut Stepgen, t: PulseTiming) {
        let p = &mut sg.chans[0].params;
        (p.steplen, p.hold, p.setup) = (t.steplen, t.hold, t.setup);
    }

    #[test]
    fn step_occurs_when_crossing_half_steps() {
        let mut sg = chan(0);
        set_timing(
            &mut sg,
            PulseTiming {
                steplen: 100,
                hold: 100,
                setup: 100,
            },
        );
        // A quarter step per call: steps on the 2nd, 6th and 10th calls
        // (call indexes 1, 5, 9), crossing positions
        // 1.0, 2.0, 3.0 (bit PICKOFF flips).
        sg.chans[0].dds.target_addval = ONE_STEP / 4;
        let mut stepped = Vec::new();
        for call in 0..12 {
            if sg.make_pulses(100) == 1 {
                stepped.push(call);
            }
        }
        assert_eq!(stepped, [1, 5, 9]);
        assert_eq!(sg.chans[0].rawcounts, 3);
        assert_eq!(sg.chans[0].dds.counts(), 3);
    }

    #[test]
    fn step_pulse_lasts_steplen_rounded_up_to_calls() {
        let mut sg = chan(0);
        set_timing(
            &mut sg,
            PulseTiming {
                steplen: 250,
                hold: 1,
                setup: 1,
            },
        );
        // An eighth of a step per call: the position reaches 1.0 (bit
        // PICKOFF flips) on the fourth call.
        sg.chans[0].dds.target_addval = ONE_STEP / 8;
        let mut highs = Vec::new();
        for _ in 0..9 {
            sg.make_pulses(100);
            highs.push(sg.chans[0].outputs & 1);
        }
        // 250 ns rounds up to three 100 ns calls.
        assert_eq!(highs, [0, 0, 0, 1, 1, 1, 0, 0, 0]);
    }

    #[test]
    fn timers_count_down_in_period_steps_and_clamp_at_zero() {
        let mut g = PulseGen::new(StepType::builtin(0).unwrap());
        g.timer1 = 250;
        g.timer2 = 100;
        g.timer3 = 50;
        g.hold_dds = true;
        let mut dds = Dds::default();
        g.update(100, false, PulseTiming::default, &mut dds);
        assert_eq!((g.timer1, g.timer2, g.timer3), (150, 0, 0));
        assert!(!g.hold_dds, "timer3 expiring releases the DDS");
        // A period longer than u32 is compared as a 64-bit value.
        g.timer1 = u32::MAX;
        g.update(1 << 40, false, PulseTiming::default, &mut dds);
        assert_eq!(g.timer1, 0);
    }

    #[test]
    fn disabled_channel_freezes_dds_but_drives_outputs() {
        let mut sg = chan(2);
        sg.chans[0].enable = false;
        sg.chans[0].dds.target_addval = ONE_STEP;
        sg.make_pulses(1000);
        assert_eq!(sg.chans[0].dds.addval, 0);
        assert_eq!(sg.chans[0].dds.accum, HALF_STEP);
        // Quadrature state 0 drives phase-A before any motion.
        assert_eq!(sg.chans[0].outputs, 1);
    }

    #[test]
    fn ramp_is_limited_by_deltalim() {
        let mut sg = chan(0);
        sg.chans[0].dds.target_addval = 1000;
        sg.chans[0].dds.deltalim = 300;
        let mut seen = Vec::new();
        for _ in 0..5 {
            sg.make_pulses(1000);
            seen.push(sg.chans[0].dds.addval);
        }
        assert_eq!(seen, [300, 600, 900, 1000, 1000]);
        sg.chans[0].dds.target_addval = -1000;
        sg.make_pulses(1000);
        assert_eq!(sg.chans[0].dds.addval, 700);
        // deltalim 0 jumps straight to the target.
        sg.chans[0].dds.deltalim = 0;
        sg.make_pulses(1000);
        assert_eq!(sg.chans[0].dds.addval, -1000);
    }

    #[test]
    fn reversal_waits_for_timer3_and_direction_for_timer2() {
        let mut sg = chan(0);
        set_timing(
            &mut sg,
            PulseTiming {
                steplen: 100,
                hold: 200,
                setup: 300,
            },
        );
        // Just below one step per call forward: the first call steps.
        sg.chans[0].dds.target_addval = ONE_STEP - 1;
        sg.make_pulses(100);
        assert_eq!(sg.chans[0].outputs, 1, "step high, dir forward");
        assert_eq!(
            (
                sg.chans[0].gen.timer1,
                sg.chans[0].gen.timer2,
                sg.chans[0].gen.timer3
            ),
            (100, 300, 600)
        );
        // Reverse at once: addval crosses zero while timer3 runs.
        sg.chans[0].dds.target_addval = -(ONE_STEP - 1);
        let accum = sg.chans[0].dds.accum;
        sg.make_pulses(100);
        assert!(sg.chans[0].gen.hold_dds);
        assert_eq!(sg.chans[0].dds.accum, accum, "DDS frozen");
        assert_eq!(sg.chans[0].dds.addval, -(ONE_STEP - 1));
        assert_eq!(sg.chans[0].gen.curr_dir, 1, "timer2 still running");
        assert_eq!(sg.chans[0].outputs, 0);
        // timer2 expires two calls later: dir flips; timer3 three after.
        let mut log = Vec::new();
        for _ in 0..6 {
            sg.make_pulses(100);
            log.push((
                sg.chans[0].gen.hold_dds,
                sg.chans[0].gen.curr_dir,
                sg.chans[0].outputs,
            ));
        }
        assert_eq!(log[0], (true, 1, 0));
        assert_eq!(log[1], (true, -1, 2));
        assert_eq!(log[3], (true, -1, 2));
        assert_eq!(log[4], (false, -1, 3), "released, steps backwards");
    }

    #[test]
    fn up_down_outputs_follow_direction() {
        let mut sg = chan(1);
        sg.chans[0].params.steplen = 100;
        sg.chans[0].dds.target_addval = ONE_STEP - 1;
        sg.make_pulses(100);
        assert_eq!(sg.chans[0].outputs, 1, "up");
        sg.make_pulses(100);
        assert_eq!(sg.chans[0].outputs, 1, "second step");
        sg.chans[0].dds.target_addval = -(ONE_STEP - 1);
        sg.chans[0].gen.timer3 = 0;
        sg.chans[0].gen.timer2 = 0;
        // addval reverses, DDS moves back: the step is a down step.
        sg.make_pulses(100);
        assert_eq!(sg.chans[0].outputs, 2, "down");
        sg.chans[0].dds.target_addval = 0;
        sg.make_pulses(1000);
        sg.make_pulses(1000);
        assert_eq!(sg.chans[0].outputs, 0);
    }

    #[test]
    fn phase_state_wraps_both_ways() {
        let mut sg = chan(3);
        sg.chans[0].params.steplen = 10;
        sg.chans[0].dds.target_addval = ONE_STEP;
        let mut pats = Vec::new();
        for _ in 0..4 {
            sg.make_pulses(100);
            pats.push(sg.chans[0].outputs);
        }
        assert_eq!(pats, [2, 4, 1, 2]);
        // Backwards through the table, wrapping below state 0.
        sg.chans[0].dds.target_addval = -ONE_STEP;
        sg.chans[0].gen.state = 0;
        sg.make_pulses(100);
        assert_eq!((sg.chans[0].gen.state, sg.chans[0].outputs), (2, 4));
    }

    #[test]
    fn accumulator_wraps_and_counts_floor() {
        let mut sg = chan(0);
        sg.chans[0].dds.accum = i64::MAX - 10;
        sg.chans[0].dds.target_addval = 20;
        sg.make_pulses(100);
        assert_eq!(sg.chans[0].dds.accum, i64::MIN + 9);
        sg.chans[0].dds.accum = -1;
        assert_eq!(sg.chans[0].dds.counts(), -1);
        sg.chans[0].dds.accum = (5i64 << 32) << PICKOFF;
        assert_eq!(sg.chans[0].dds.counts(), 0, "low 32 bits of the step count");
    }
}
