//! `oneshot`: a pulse of `width` seconds on a selected edge of `in`,
//! optionally retriggerable, with a reset.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

use super::write_changed;

/// The pin and param values one call of `oneshot` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OneShotVars {
    /// Pin `in`.
    pub input: bool,
    /// Pin `reset`.
    pub reset: bool,
    /// Pin `out`.
    pub out: bool,
    /// Pin `out-not`.
    pub out_not: bool,
    /// Pin `width` (seconds).
    pub width: f64,
    /// Pin `time-left` (seconds).
    pub time_left: f64,
    /// Param `retriggerable`.
    pub retriggerable: bool,
    /// Param `rising`: trigger on rising edges.
    pub rising: bool,
    /// Param `falling`: trigger on falling edges.
    pub falling: bool,
}

/// Per-instance state of `oneshot`.
#[derive(Debug, Clone, Default)]
pub struct OneShot {
    /// Seconds left of the current pulse.
    timer: f64,
    /// `in` at the previous call.
    old_in: bool,
}

impl OneShot {
    /// One call; `fperiod` is the period in seconds (`period * 1e-9`).
    pub fn step(&mut self, v: &mut OneShotVars, fperiod: f64) {
        if v.reset {
            self.timer = 0.0;
            self.old_in = false;
            v.out = false;
            v.out_not = true;
            // time-left keeps its value.
            return;
        }
        let mut trig =
            (v.input && !self.old_in && v.rising) || (self.old_in && !v.input && v.falling);
        self.old_in = v.input;
        if self.timer > 0.0 {
            if !v.retriggerable {
                trig = false;
            }
            self.timer -= fperiod;
            if self.timer < 0.0 {
                self.timer = 0.0;
            }
        }
        if trig {
            self.timer = v.width;
        }
        v.time_left = self.timer;
        if self.timer > 0.0 {
            v.out = true;
            v.out_not = false;
        } else {
            v.out = false;
            v.out_not = true;
        }
    }
}

/// The `oneshot` component.
pub struct OneShotComp;
impl HalComp for OneShotComp {
    const NAME: &'static str = "oneshot";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let out = inst.pin_out::<bool>("out")?;
        let out_not = inst.pin_out::<bool>("out-not")?;
        let width = inst.pin_in::<f64>("width")?;
        let time_left = inst.pin_out::<f64>("time-left")?;
        let retriggerable = inst.param_rw::<bool>("retriggerable", true)?;
        let rising = inst.param_rw::<bool>("rising", true)?;
        let falling = inst.param_rw::<bool>("falling", false)?;
        let mut state = OneShot::default();
        inst.funct("_", true, move |ctx| {
            let old = OneShotVars {
                input: input.get(),
                reset: reset.get(),
                out: out.get(),
                out_not: out_not.get(),
                width: width.get(),
                time_left: time_left.get(),
                retriggerable: retriggerable.get(),
                rising: rising.get(),
                falling: falling.get(),
            };
            let mut v = old;
            state.step(&mut v, ctx.fperiod());
            write_changed(&out, old.out, v.out);
            write_changed(&out_not, old.out_not, v.out_not);
            if v.time_left.to_bits() != old.time_left.to_bits() {
                time_left.set(v.time_left);
            }
        })
    }
}
halcomp_module!(pub MODULE, OneShotComp, "one-shot pulse generator");

#[cfg(test)]
mod tests {
    use super::*;

    fn vars(width: f64) -> OneShotVars {
        OneShotVars {
            width,
            retriggerable: true,
            rising: true,
            ..Default::default()
        }
    }

    /// Runs `inputs`, returns `out` per call.
    fn run(v: &mut OneShotVars, inputs: &[bool], fperiod: f64) -> Vec<bool> {
        let mut o = OneShot::default();
        inputs
            .iter()
            .map(|&x| {
                v.input = x;
                o.step(v, fperiod);
                v.out
            })
            .collect()
    }

    #[test]
    fn first_call_sets_out_not() {
        let mut o = OneShot::default();
        let mut v = vars(1.0);
        o.step(&mut v, 0.001);
        assert!(!v.out && v.out_not);
    }

    #[test]
    fn pulse_length_is_about_width_over_period() {
        let mut v = vars(0.0105);
        let r = run(&mut v, &[true; 20], 0.001);
        // Triggers at call 0, then 0.0095, ..., 0.0005 (10 more calls).
        assert_eq!(r.iter().filter(|&&b| b).count(), 11);
        assert!(r[..11].iter().all(|&b| b));
        assert_eq!(v.time_left, 0.0);
    }

    #[test]
    fn zero_or_negative_width_gives_no_pulse() {
        for w in [0.0, -1.0] {
            let mut v = vars(w);
            assert_eq!(run(&mut v, &[false, true, true], 0.001), [false; 3]);
        }
    }

    #[test]
    fn edge_selection() {
        let mut v = OneShotVars {
            rising: false,
            falling: true,
            ..vars(0.0015)
        };
        let r = run(&mut v, &[true, true, false, false, false], 0.001);
        assert_eq!(r, [false, false, true, true, false]);
    }

    #[test]
    fn retrigger_reloads_only_when_enabled() {
        let inputs = [true, false, true, false, false, false, false];
        let mut v = vars(0.0035);
        assert_eq!(
            run(&mut v, &inputs, 0.001),
            [true, true, true, true, true, true, false]
        );
        let mut v = OneShotVars {
            retriggerable: false,
            ..vars(0.0035)
        };
        assert_eq!(
            run(&mut v, &inputs, 0.001),
            [true, true, true, true, false, false, false]
        );
    }

    #[test]
    fn reset_clears_but_keeps_time_left() {
        let mut o = OneShot::default();
        let mut v = vars(0.01);
        v.input = true;
        o.step(&mut v, 0.001);
        assert_eq!(v.time_left, 0.01);
        v.reset = true;
        o.step(&mut v, 0.001);
        assert!(!v.out && v.out_not);
        assert_eq!(v.time_left, 0.01);
        // After reset old_in is 0, so a held-high input triggers again.
        v.reset = false;
        o.step(&mut v, 0.001);
        assert!(v.out);
        assert_eq!(v.time_left, 0.01);
    }
}
