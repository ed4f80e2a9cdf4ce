//! Filters and calculus: lowpass, ilowpass, ddt, integ, biquad, lincurve;
//! in their own files also filter_kalman and led_dim.
//!
//! As in the other families, each component's per-call arithmetic is a
//! plain function or struct independent of pins; the HAL glue reads the
//! pins, calls it and writes the pins.

pub mod biquad;
pub mod filter_kalman;
pub mod led_dim;
pub mod lincurve;

use hal_core::Result;

use crate::cmath::f64_to_i64;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// lowpass: the next output from the current one (`out` is read back).
/// `load` copies the input straight through.
pub fn lowpass(input: f64, load: bool, gain: f64, out: f64) -> f64 {
    if load {
        input
    } else {
        out + (input - out) * gain
    }
}

/// ilowpass: a low-pass filter on integers, computed in floating point
/// and rounded half up.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Ilowpass {
    /// The filtered value (before scaling), starting at 0.
    pub value: f64,
}

impl Ilowpass {
    /// One call: returns the new `out`. The rounded value goes through a
    /// C `(int64_t)` cast and then keeps its low 32 bits, so results
    /// beyond the s32 range wrap.
    pub fn step(&mut self, input: i32, scale: f64, gain: f64) -> i32 {
        self.value = self.value + (f64::from(input) - self.value) * gain;
        f64_to_i64((self.value * scale + 0.5).floor()) as i32
    }
}

/// ddt: the derivative of the input over one period.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Ddt {
    /// The previous input (0 before the first call, so a non-zero first
    /// input gives a spike).
    pub old: f64,
}

impl Ddt {
    /// One call with the thread period in ns.
    pub fn step(&mut self, input: f64, period_ns: i64) -> f64 {
        let out = (input - self.old) / (period_ns as f64 * 1e-9);
        self.old = input;
        out
    }
}

/// integ: one call from the current output `out` (read back). Returns the
/// value to write to `out`, or `None` when `out` is left as it is.
///
/// This is the behaviour at the reference commit (and what the golden
/// output shows): while `reset` is TRUE the output is not written, only
/// clamped if 0 lies outside `[min, max]`.
pub fn integ(
    input: f64,
    gain: f64,
    reset: bool,
    min: f64,
    max: f64,
    out: f64,
    fperiod: f64,
) -> Option<f64> {
    let mut written = None;
    let v = if reset {
        0.0
    } else {
        let v = out + gain * input * fperiod;
        written = Some(v);
        v
    };
    if v > max {
        written = Some(max);
    }
    if v < min {
        written = Some(min);
    }
    written
}

/// `lowpass`: single-pole low-pass filter.
pub struct LowpassComp;
impl HalComp for LowpassComp {
    const NAME: &'static str = "lowpass";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let load = inst.pin_in::<bool>("load")?;
        let gain = inst.param_rw::<f64>("gain", 0.0)?;
        inst.funct("_", true, move |_| {
            out.set(lowpass(input.get(), load.get(), gain.get(), out.get()))
        })
    }
}
halcomp_module!(pub LOWPASS, LowpassComp, "low-pass filter");

/// `ilowpass`: low-pass filter with integer inputs and outputs.
pub struct IlowpassComp;
impl HalComp for IlowpassComp {
    const NAME: &'static str = "ilowpass";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<i32>("in")?;
        let out = inst.pin_out::<i32>("out")?;
        let scale = inst.param_rw::<f64>("scale", 1024.0)?;
        let gain = inst.param_rw::<f64>("gain", 0.5)?;
        let mut st = Ilowpass::default();
        inst.funct("_", true, move |_| {
            out.set(st.step(input.get(), scale.get(), gain.get()))
        })
    }
}
halcomp_module!(pub ILOWPASS, IlowpassComp, "low-pass filter with integer inputs and outputs");

/// `ddt`: differentiator.
pub struct DdtComp;
impl HalComp for DdtComp {
    const NAME: &'static str = "ddt";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let mut st = Ddt::default();
        inst.funct("_", true, move |ctx| {
            out.set(st.step(input.get(), ctx.period()))
        })
    }
}
halcomp_module!(pub DDT, DdtComp, "compute the derivative of the input function");

/// `integ`: integrator with gain, reset and output limits.
pub struct IntegComp;
impl HalComp for IntegComp {
    const NAME: &'static str = "integ";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let gain = inst.pin_in_init::<f64>("gain", 1.0)?;
        let out = inst.pin_out::<f64>("out")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let max = inst.pin_in_init::<f64>("max", 1e20)?;
        let min = inst.pin_in_init::<f64>("min", -1e20)?;
        inst.funct("_", true, move |ctx| {
            let r = integ(
                input.get(),
                gain.get(),
                reset.get(),
                min.get(),
                max.get(),
                out.get(),
                ctx.fperiod(),
            );
            if let Some(v) = r {
                out.set(v);
            }
        })
    }
}
halcomp_module!(pub INTEG, IntegComp, "integrator with gain pin and windup limits");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &LOWPASS,
        &ILOWPASS,
        &DDT,
        &INTEG,
        &biquad::BIQUAD,
        &lincurve::LINCURVE,
        &filter_kalman::MODULE,
        &led_dim::MODULE,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lowpass_load_and_gain() {
        // Default gain 0: never moves.
        assert_eq!(lowpass(5.0, false, 0.0, 1.0), 1.0);
        assert_eq!(lowpass(5.0, true, 0.0, 1.0), 5.0);
        assert_eq!(lowpass(1.0, false, 0.1, 0.0), 0.1);
        assert_eq!(lowpass(1.0, false, 1.0, 0.3), 1.0);
    }

    #[test]
    fn ilowpass_wraps_beyond_s32() {
        let mut f = Ilowpass::default();
        assert_eq!(f.step(21474, 100000.0, 1.0), 2_147_400_000);
        assert_eq!(f.step(21475, 100000.0, 1.0), -2_147_467_296);
        // Beyond the i64 range: i64::MIN, whose low 32 bits are 0.
        let mut f = Ilowpass::default();
        assert_eq!(f.step(1, 1e300, 1.0), 0);
    }

    #[test]
    fn ilowpass_reaches_target_with_low_gain() {
        let mut f = Ilowpass::default();
        let mut out = 0;
        for (target, want) in [(4, 4), (0, 0), (-5, -5)] {
            for _ in 0..1000 {
                out = f.step(target, 1.0, 0.1);
            }
            assert_eq!(out, want);
        }
        // Default scale and gain: half way, times 1024.
        let mut f = Ilowpass::default();
        assert_eq!(f.step(2, 1024.0, 0.5), 1024);
    }

    #[test]
    fn ddt_first_call_spikes() {
        let mut d = Ddt::default();
        assert_eq!(d.step(1.0, 1_000_000), 1000.0);
        assert_eq!(d.step(1.0, 1_000_000), 0.0);
        assert_eq!(d.step(0.5, 1_000_000), -500.0);
    }

    #[test]
    fn integ_accumulates_clamps_and_reset_leaves_out() {
        let t = 0.001;
        assert_eq!(integ(1.0, 1.0, false, -1e20, 1e20, 0.0, t), Some(0.001));
        assert_eq!(
            integ(2.0, 3.0, false, -1e20, 1e20, 1.0, t),
            Some(1.0 + 2.0 * 3.0 * t)
        );
        // Clamped at max and min: no wind-up beyond the limits.
        assert_eq!(integ(1000.0, 1.0, false, -1.0, 0.5, 0.4, t), Some(0.5));
        assert_eq!(integ(-1000.0, 1.0, false, -1.0, 0.5, -0.5, t), Some(-1.0));
        // Reset at the reference commit: out untouched...
        assert_eq!(integ(1.0, 1.0, true, -1e20, 1e20, 0.08, t), None);
        // ...unless 0 lies outside [min, max].
        assert_eq!(integ(1.0, 1.0, true, 1.0, 2.0, 1.5, t), Some(1.0));
        assert_eq!(integ(1.0, 1.0, true, -2.0, -1.0, -1.5, t), Some(-1.0));
    }

    mod hal {
        use super::super::*;
        use crate::testing::{float, TestHost};
        use hal_core::Value;

        #[test]
        fn names_and_defaults() {
            let h = TestHost::new("lim-fnames");
            for def in modules() {
                h.load(def, &[]).unwrap();
            }
            assert_eq!(h.getp("lowpass.0.gain"), Value::Float(0.0));
            assert_eq!(h.getp("ilowpass.0.scale"), Value::Float(1024.0));
            assert_eq!(h.getp("ilowpass.0.gain"), Value::Float(0.5));
            assert_eq!(h.get("ilowpass.0.out"), Value::S32(0));
            assert_eq!(h.get("integ.0.gain"), Value::Float(1.0));
            assert_eq!(h.get("integ.0.max"), Value::Float(1e20));
            assert_eq!(h.get("integ.0.min"), Value::Float(-1e20));
            assert_eq!(h.get("biquad.0.Q"), Value::Float(biquad::DEFAULT_Q));
            assert_eq!(h.get("biquad.0.f0"), Value::Float(250.0));
            assert_eq!(h.get("biquad.0.type"), Value::U32(0));
            assert_eq!(h.getp("biquad.0.n0"), Value::Float(1.0));
            for p in ["biquad.0.s1", "biquad.0.s2", "biquad.0.valid", "ddt.0.out"] {
                h.get(p);
            }
            // lincurve with no personality: two breakpoints.
            assert_eq!(
                h.items("lincurve.0."),
                [
                    "lincurve.0.in",
                    "lincurve.0.out",
                    "lincurve.0.out-io",
                    "lincurve.0.time",
                    "lincurve.0.tmax",
                    "lincurve.0.tmax-increased",
                    "lincurve.0.x-val-00",
                    "lincurve.0.x-val-01",
                    "lincurve.0.y-val-00",
                    "lincurve.0.y-val-01",
                ]
            );
        }

        #[test]
        fn lincurve_personality_is_clamped_per_instance() {
            let h = TestHost::new("lim-lcp");
            h.load(&lincurve::LINCURVE, &["names=a,b,c", "personality=5,40"])
                .unwrap();
            let count = |p: &str| h.items(p).len();
            assert_eq!(count("a.x-val-"), 5);
            assert_eq!(count("b.x-val-"), 16);
            assert_eq!(count("b.y-val-"), 16);
            h.getp("b.y-val-15");
            // Not given: 0, clamped to 2.
            assert_eq!(count("c.x-val-"), 2);
        }

        #[test]
        fn filters_run_in_a_thread() {
            let mut h = TestHost::new("lim-frun");
            for def in modules() {
                h.load(def, &[]).unwrap();
            }
            // integ: out grows by gain * in * T per cycle.
            h.set("integ.0.in", Value::Float(1.0));
            h.set("integ.0.gain", Value::Float(2.0));
            // ddt of a constant: only the first call is non-zero.
            h.set("ddt.0.in", Value::Float(3.0));
            // lowpass with load copies the input.
            h.set("lowpass.0.in", Value::Float(4.0));
            h.set("lowpass.0.load", Value::Bit(true));
            h.set("ilowpass.0.in", Value::S32(7));
            h.setp("ilowpass.0.gain", Value::Float(1.0));
            h.setp("ilowpass.0.scale", Value::Float(1.0));
            // biquad low-pass, designed on the rising edge of enable.
            h.set("biquad.0.type", Value::U32(1));
            h.set("biquad.0.f0", Value::Float(50.0));
            h.set("biquad.0.enable", Value::Bit(true));
            h.set("biquad.0.in", Value::Float(1.0));
            // lincurve: 0..10 maps to 0..100.
            h.setp("lincurve.0.x-val-01", Value::Float(10.0));
            h.setp("lincurve.0.y-val-01", Value::Float(100.0));
            h.set("lincurve.0.in", Value::Float(2.5));
            let functs = [
                "integ.0",
                "ddt.0",
                "lowpass.0",
                "ilowpass.0",
                "biquad.0",
                "lincurve.0",
            ];
            h.thread(&functs);
            let n = h.run(10);
            let integ = float(h.get("integ.0.out"));
            assert!((integ - 0.002 * n as f64).abs() < 1e-9, "{integ} after {n}");
            assert_eq!(h.get("ddt.0.out"), Value::Float(0.0));
            assert_eq!(h.get("lowpass.0.out"), Value::Float(4.0));
            assert_eq!(h.get("ilowpass.0.out"), Value::S32(7));
            assert_eq!(h.get("biquad.0.valid"), Value::Bit(true));
            let c = biquad::design(1, 50.0, biquad::DEFAULT_Q, 1_000_000).unwrap();
            assert_eq!(h.getp("biquad.0.n0"), Value::Float(c.n0));
            assert_eq!(h.getp("biquad.0.d2"), Value::Float(c.d2));
            assert_eq!(h.get("lincurve.0.out"), Value::Float(25.0));
            assert_eq!(h.get("lincurve.0.out-io"), Value::Float(25.0));
        }
    }
}
