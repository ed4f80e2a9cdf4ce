//! `timedelay`: follows `in` after it has differed from `out` for
//! `on-delay` (rising) or `off-delay` (falling) seconds.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

use super::write_changed;

/// The pin values one call of `timedelay` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TimeDelayVars {
    /// Pin `in`.
    pub input: bool,
    /// Pin `out` (read back).
    pub out: bool,
    /// Pin `on-delay` (seconds).
    pub on_delay: f64,
    /// Pin `off-delay` (seconds).
    pub off_delay: f64,
    /// Pin `elapsed` (seconds).
    pub elapsed: f64,
}

/// Per-instance state of `timedelay`.
#[derive(Debug, Clone, Default)]
pub struct TimeDelay {
    /// Time `in` has differed from `out`, summed period by period.
    timer: f64,
}

impl TimeDelay {
    /// One call; `fperiod` is the period in seconds.
    pub fn step(&mut self, v: &mut TimeDelayVars, fperiod: f64) {
        let x = v.input;
        if x != v.out {
            self.timer += fperiod;
            v.elapsed = self.timer;
            if x {
                if self.timer >= v.on_delay {
                    v.out = true;
                    self.timer = 0.0;
                }
            } else if self.timer >= v.off_delay {
                v.out = false;
                self.timer = 0.0;
            }
        } else {
            // elapsed keeps showing the last accumulated time.
            self.timer = 0.0;
        }
    }
}

/// The `timedelay` component.
pub struct TimeDelayComp;
impl HalComp for TimeDelayComp {
    const NAME: &'static str = "timedelay";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let out = inst.pin_out::<bool>("out")?;
        let on_delay = inst.pin_in_init::<f64>("on-delay", 0.5)?;
        let off_delay = inst.pin_in_init::<f64>("off-delay", 0.5)?;
        let elapsed = inst.pin_out::<f64>("elapsed")?;
        let mut state = TimeDelay::default();
        inst.funct("_", true, move |ctx| {
            let old = TimeDelayVars {
                input: input.get(),
                out: out.get(),
                on_delay: on_delay.get(),
                off_delay: off_delay.get(),
                elapsed: elapsed.get(),
            };
            let mut v = old;
            state.step(&mut v, ctx.fperiod());
            write_changed(&out, old.out, v.out);
            if v.elapsed.to_bits() != old.elapsed.to_bits() {
                elapsed.set(v.elapsed);
            }
        })
    }
}
halcomp_module!(pub MODULE, TimeDelayComp, "delays the rising and falling edges of a bit");

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::FunctCtx;

    #[test]
    fn self_oscillating_through_an_inverter() {
        // LinuxCNC's timedelay.0 test: a `not` feeds out back to in,
        // 1/512 s period, delays of 4.5 and 8.5 periods.
        let fperiod = FunctCtx::new(1_953_125).fperiod();
        let mut t = TimeDelay::default();
        let mut v = TimeDelayVars {
            on_delay: 0.0087890625,
            off_delay: 0.0166015625,
            ..Default::default()
        };
        let mut outs = Vec::new();
        for _ in 0..32 {
            v.input = !v.out;
            t.step(&mut v, fperiod);
            outs.push(v.out);
        }
        let rises: Vec<usize> = (1..outs.len())
            .filter(|&i| outs[i] && !outs[i - 1])
            .collect();
        let falls: Vec<usize> = (1..outs.len())
            .filter(|&i| !outs[i] && outs[i - 1])
            .collect();
        assert_eq!(rises, [4, 18]);
        assert_eq!(falls, [13, 27]);
    }

    #[test]
    fn elapsed_holds_after_match_and_timer_restarts() {
        let mut t = TimeDelay::default();
        let mut v = TimeDelayVars {
            on_delay: 0.0035,
            off_delay: 0.5,
            ..Default::default()
        };
        v.input = true;
        t.step(&mut v, 0.001);
        t.step(&mut v, 0.001);
        assert!(!v.out);
        // Input drops before the delay: elapsed keeps 0.002, timer resets.
        v.input = false;
        t.step(&mut v, 0.001);
        assert_eq!(v.elapsed, 0.002);
        v.input = true;
        for _ in 0..3 {
            t.step(&mut v, 0.001);
        }
        assert!(!v.out);
        t.step(&mut v, 0.001);
        assert!(v.out);
    }

    #[test]
    fn zero_delay_switches_in_the_first_call() {
        let mut t = TimeDelay::default();
        let mut v = TimeDelayVars {
            input: true,
            ..Default::default()
        };
        t.step(&mut v, 0.001);
        assert!(v.out);
        assert_eq!(v.elapsed, 0.001);
        v.input = false;
        t.step(&mut v, 0.001);
        assert!(!v.out);
    }
}
