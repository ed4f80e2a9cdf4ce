//! Limits and comparators: limit1, limit2, limit3, comp, wcomp, near,
//! deadzone, minmax; in their own files also limit_axis and simple_tp.
//!
//! Each component's per-call arithmetic lives in a plain function or
//! struct that knows nothing about pins, so it can be tested directly
//! and reused; the HAL glue reads the pins, calls it and writes the pins.

pub mod limit3;
pub mod limit_axis;
pub mod simple_tp;

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

pub use limit3::{Limit3, Limit3Inputs};

/// Default lower limit of the limiters (LinuxCNC's `-1e20`).
pub const DEFAULT_MIN: f64 = -1e20;
/// Default upper limit of the limiters (LinuxCNC's `1e20`).
pub const DEFAULT_MAX: f64 = 1e20;

/// limit1's clamp: the minimum first, then the maximum, so the maximum
/// wins when `min > max`.
pub fn limit1(input: f64, min: f64, max: f64) -> f64 {
    let mut t = input;
    if t < min {
        t = min;
    }
    if t > max {
        t = max;
    }
    t
}

/// limit2's clamp helper: `lo` if below it, otherwise `hi` if above it.
fn clamp(v: f64, lo: f64, hi: f64) -> f64 {
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

/// limit2: position limits plus a slew-rate limit.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Limit2 {
    /// The previous output (starts at 0, so the output ramps from 0).
    pub old_out: f64,
}

impl Limit2 {
    /// One call: clamp `input` to `[min, max]`; on `load` jump there,
    /// otherwise move at most `maxv * fperiod` from the previous output.
    pub fn step(
        &mut self,
        input: f64,
        load: bool,
        min: f64,
        max: f64,
        maxv: f64,
        fperiod: f64,
    ) -> f64 {
        let mut t = clamp(input, min, max);
        if !load {
            let d = maxv * fperiod;
            t = clamp(t, self.old_out - d, self.old_out + d);
        }
        self.old_out = t;
        t
    }
}

/// comp's outputs after one call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompOut {
    /// `out`: TRUE when `in1` is clearly above `in0`.
    pub out: bool,
    /// `equal`: TRUE when the difference lies within the hysteresis band.
    pub equal: bool,
}

/// comp: compares `in1` (non-inverting) with `in0` (inverting). Inside
/// the band `±hyst/2`, `out` keeps `prev_out` and `equal` is set.
pub fn comp(in0: f64, in1: f64, hyst: f64, prev_out: bool) -> CompOut {
    let d = in1 - in0;
    let h = 0.5 * hyst;
    if d < -h {
        CompOut {
            out: false,
            equal: false,
        }
    } else if d > h {
        CompOut {
            out: true,
            equal: false,
        }
    } else {
        CompOut {
            out: prev_out,
            equal: true,
        }
    }
}

/// wcomp's outputs: `(out, under, over)`, with `out` TRUE strictly
/// inside the window and the bounds themselves counting as outside.
pub fn wcomp(input: f64, min: f64, max: f64) -> (bool, bool, bool) {
    let under = input <= min;
    let over = input >= max;
    (!(under || over), under, over)
}

/// near: whether `in1` and `in2` are within a ratio `scale` (when it is
/// above 1) or an absolute `difference` of each other.
pub fn near(in1: f64, in2: f64, scale: f64, difference: f64) -> bool {
    let (mut a, mut b) = (in1, in2);
    if a < 0.0 {
        a = -a;
        b = -b;
    }
    (scale > 1.0 && a / scale <= b && b <= a * scale) || (a - b).abs() <= difference
}

/// deadzone: outputs `center` inside `center ± threshold/2`, and outside
/// it the input moved towards the centre by half the threshold.
pub fn deadzone(input: f64, center: f64, threshold: f64) -> f64 {
    let h = threshold / 2.0;
    let lo = center - h;
    let hi = center + h;
    if input < lo {
        input + h
    } else if input > hi {
        input - h
    } else {
        center
    }
}

/// minmax: the new `(min, max)` from the current outputs. A reset
/// restarts both at the input.
pub fn minmax(input: f64, reset: bool, min: f64, max: f64) -> (f64, f64) {
    if reset {
        return (input, input);
    }
    let max = if input > max { input } else { max };
    let min = if input < min { input } else { min };
    (min, max)
}

/// `limit1`: out = in clamped to [min, max].
pub struct Limit1Comp;
impl HalComp for Limit1Comp {
    const NAME: &'static str = "limit1";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let min = inst.pin_in_init::<f64>("min", DEFAULT_MIN)?;
        let max = inst.pin_in_init::<f64>("max", DEFAULT_MAX)?;
        inst.funct("_", true, move |_| {
            out.set(limit1(input.get(), min.get(), max.get()))
        })
    }
}
halcomp_module!(pub LIMIT1, Limit1Comp, "limit the output signal to fall between min and max");

/// `limit2`: limit1 plus a maximum rate of change `maxv` (per second).
pub struct Limit2Comp;
impl HalComp for Limit2Comp {
    const NAME: &'static str = "limit2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let load = inst.pin_in::<bool>("load")?;
        let min = inst.pin_in_init::<f64>("min", DEFAULT_MIN)?;
        let max = inst.pin_in_init::<f64>("max", DEFAULT_MAX)?;
        let maxv = inst.pin_in_init::<f64>("maxv", DEFAULT_MAX)?;
        let mut st = Limit2::default();
        inst.funct("_", true, move |ctx| {
            out.set(st.step(
                input.get(),
                load.get(),
                min.get(),
                max.get(),
                maxv.get(),
                ctx.fperiod(),
            ))
        })
    }
}
halcomp_module!(pub LIMIT2, Limit2Comp, "limit the output signal to fall between min and max and limit its slew rate");

/// `limit3`: position, velocity and acceleration limiter.
pub struct Limit3Comp;
impl HalComp for Limit3Comp {
    const NAME: &'static str = "limit3";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let enable = inst.pin_in_init::<bool>("enable", true)?;
        let out = inst.pin_out::<f64>("out")?;
        let load = inst.pin_in::<bool>("load")?;
        let min = inst.pin_in_init::<f64>("min", DEFAULT_MIN)?;
        let max = inst.pin_in_init::<f64>("max", DEFAULT_MAX)?;
        let maxv = inst.pin_in_init::<f64>("maxv", DEFAULT_MAX)?;
        let maxa = inst.pin_in_init::<f64>("maxa", 1e7)?;
        let smooth_steps = inst.pin_in_init::<u32>("smooth-steps", 2)?;
        let mut st = Limit3::default();
        inst.funct("_", true, move |ctx| {
            let inputs = Limit3Inputs {
                input: input.get(),
                enable: enable.get(),
                load: load.get(),
                min: min.get(),
                max: max.get(),
                maxv: maxv.get(),
                maxa: maxa.get(),
                smooth_steps: smooth_steps.get(),
            };
            // The component reads its own output back (it may be linked).
            let o = st.step(&inputs, out.get(), ctx.fperiod());
            out.set(o);
        })
    }
}
halcomp_module!(pub LIMIT3, Limit3Comp, "follow input signal while obeying limits on position, velocity and acceleration");

/// `comp`: two-input comparator with hysteresis.
pub struct CompComp;
impl HalComp for CompComp {
    const NAME: &'static str = "comp";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let out = inst.pin_out::<bool>("out")?;
        let equal = inst.pin_out::<bool>("equal")?;
        let hyst = inst.param_rw::<f64>("hyst", 0.0)?;
        inst.funct("_", true, move |_| {
            let r = comp(in0.get(), in1.get(), hyst.get(), out.get());
            out.set(r.out);
            equal.set(r.equal);
        })
    }
}
halcomp_module!(pub COMP, CompComp, "two input comparator with hysteresis");

/// `wcomp`: window comparator.
pub struct WcompComp;
impl HalComp for WcompComp {
    const NAME: &'static str = "wcomp";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let min = inst.pin_in::<f64>("min")?;
        let max = inst.pin_in::<f64>("max")?;
        let out = inst.pin_out::<bool>("out")?;
        let under = inst.pin_out::<bool>("under")?;
        let over = inst.pin_out::<bool>("over")?;
        inst.funct("_", true, move |_| {
            let (o, u, v) = wcomp(input.get(), min.get(), max.get());
            under.set(u);
            over.set(v);
            out.set(o);
        })
    }
}
halcomp_module!(pub WCOMP, WcompComp, "window comparator");

/// `near`: whether two values are approximately equal.
pub struct NearComp;
impl HalComp for NearComp {
    const NAME: &'static str = "near";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in1 = inst.pin_in::<f64>("in1")?;
        let in2 = inst.pin_in::<f64>("in2")?;
        let out = inst.pin_out::<bool>("out")?;
        let scale = inst.param_rw::<f64>("scale", 1.0)?;
        let difference = inst.param_rw::<f64>("difference", 0.0)?;
        inst.funct("_", true, move |_| {
            out.set(near(in1.get(), in2.get(), scale.get(), difference.get()))
        })
    }
}
halcomp_module!(pub NEAR, NearComp, "determine whether two values are roughly equal");

/// `deadzone`: returns the centre value when the input is near it.
pub struct DeadzoneComp;
impl HalComp for DeadzoneComp {
    const NAME: &'static str = "deadzone";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let center = inst.param_rw::<f64>("center", 0.0)?;
        let threshold = inst.param_rw::<f64>("threshold", 1.0)?;
        inst.funct("_", true, move |_| {
            out.set(deadzone(input.get(), center.get(), threshold.get()))
        })
    }
}
halcomp_module!(pub DEADZONE, DeadzoneComp, "return the center if within the threshold");

/// `minmax`: tracks the smallest and largest input since the last reset.
pub struct MinmaxComp;
impl HalComp for MinmaxComp {
    const NAME: &'static str = "minmax";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let max = inst.pin_out::<f64>("max")?;
        let min = inst.pin_out::<f64>("min")?;
        inst.funct("_", true, move |_| {
            // Both outputs are read back: they hold the running extremes.
            let (lo, hi) = minmax(input.get(), reset.get(), min.get(), max.get());
            min.set(lo);
            max.set(hi);
        })
    }
}
halcomp_module!(pub MINMAX, MinmaxComp, "track the minimum and maximum values of the input to the outputs");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &LIMIT1,
        &LIMIT2,
        &LIMIT3,
        &COMP,
        &WCOMP,
        &NEAR,
        &DEADZONE,
        &MINMAX,
        &limit_axis::MODULE,
        &simple_tp::MODULE,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limit1_clamps_and_max_wins() {
        assert_eq!(limit1(0.5, -1.0, 1.0), 0.5);
        assert_eq!(limit1(-3.0, -1.0, 1.0), -1.0);
        assert_eq!(limit1(3.0, -1.0, 1.0), 1.0);
        // min > max: the max test comes last and wins.
        assert_eq!(limit1(0.0, 2.0, 1.0), 1.0);
        assert_eq!(limit1(5.0, 2.0, 1.0), 1.0);
        assert_eq!(limit1(1e30, DEFAULT_MIN, DEFAULT_MAX), 1e20);
        assert!(limit1(f64::NAN, -1.0, 1.0).is_nan());
    }

    #[test]
    fn limit2_ramps_from_zero_and_load_jumps() {
        let mut l = Limit2::default();
        let t = 0.001;
        // maxv 100/s at 1 ms: 0.1 per call.
        assert_eq!(l.step(1.0, false, -10.0, 10.0, 100.0, t), 0.1);
        assert_eq!(l.step(1.0, false, -10.0, 10.0, 100.0, t), 0.2);
        // load jumps straight to the clamped input.
        assert_eq!(l.step(50.0, true, -10.0, 10.0, 100.0, t), 10.0);
        assert_eq!(l.old_out, 10.0);
        // Then rate-limited from there.
        assert_eq!(l.step(-10.0, false, -10.0, 10.0, 100.0, t), 9.9);
        // Position clamp applies before the rate limit.
        let mut l = Limit2 { old_out: 0.5 };
        assert_eq!(l.step(3.0, false, -1.0, 0.55, 1e20, t), 0.55);
    }

    #[test]
    fn comp_hysteresis_holds_output() {
        let r = comp(0.0, 1.0, 0.2, false);
        assert_eq!(
            r,
            CompOut {
                out: true,
                equal: false
            }
        );
        // Inside the band: out keeps its previous value, equal set.
        assert_eq!(
            comp(0.0, 0.05, 0.2, true),
            CompOut {
                out: true,
                equal: true
            }
        );
        assert_eq!(
            comp(0.0, -0.05, 0.2, true),
            CompOut {
                out: true,
                equal: true
            }
        );
        assert_eq!(
            comp(0.0, 0.05, 0.2, false),
            CompOut {
                out: false,
                equal: true
            }
        );
        assert_eq!(
            comp(0.0, -0.2, 0.2, true),
            CompOut {
                out: false,
                equal: false
            }
        );
        // Zero hysteresis: exact equality keeps out.
        assert_eq!(
            comp(1.0, 1.0, 0.0, true),
            CompOut {
                out: true,
                equal: true
            }
        );
        assert_eq!(
            comp(1.0, 1.0, 0.0, false),
            CompOut {
                out: false,
                equal: true
            }
        );
    }

    #[test]
    fn wcomp_bounds_count_as_outside() {
        assert_eq!(wcomp(0.0, -1.0, 1.0), (true, false, false));
        assert_eq!(wcomp(-1.0, -1.0, 1.0), (false, true, false));
        assert_eq!(wcomp(1.0, -1.0, 1.0), (false, false, true));
        // Inverted window: both flags can be set.
        assert_eq!(wcomp(0.0, 1.0, -1.0), (false, true, true));
    }

    #[test]
    fn near_scale_and_difference_modes() {
        // Defaults: exact equality only.
        assert!(near(2.0, 2.0, 1.0, 0.0));
        assert!(!near(2.0, 2.1, 1.0, 0.0));
        // Scale 1.5: within a factor.
        assert!(near(10.0, 12.0, 1.5, 0.0));
        assert!(near(-10.0, -12.0, 1.5, 0.0));
        assert!(!near(10.0, -12.0, 1.5, 0.0));
        assert!(!near(2.0, 12.0, 1.5, 0.0));
        // 0 and 0 are equal through the difference test only.
        assert!(near(0.0, 0.0, 1.5, 0.0));
        // Difference 1.5.
        assert!(near(-1.0, 0.0, 1.0, 1.5));
        assert!(!near(-1.0, 1.0, 1.0, 1.5));
    }

    #[test]
    fn deadzone_shifts_outside_the_band() {
        assert_eq!(deadzone(0.1, 0.0, 1.0), 0.0);
        assert_eq!(deadzone(0.5, 0.0, 1.0), 0.0);
        assert_eq!(deadzone(0.75, 0.0, 1.0), 0.25);
        assert_eq!(deadzone(-2.0, 0.25, 0.5), -1.75);
        assert_eq!(deadzone(2.0, 0.25, 0.5), 1.75);
    }

    #[test]
    fn minmax_tracks_and_resets() {
        let (mut lo, mut hi) = (0.0, 0.0);
        for x in [1.0, 3.0, 2.0] {
            (lo, hi) = minmax(x, false, lo, hi);
        }
        // Starting at 0, the minimum never rises above 0.
        assert_eq!((lo, hi), (0.0, 3.0));
        (lo, hi) = minmax(2.0, true, lo, hi);
        assert_eq!((lo, hi), (2.0, 2.0));
        (lo, hi) = minmax(-1.0, false, lo, hi);
        assert_eq!((lo, hi), (-1.0, 2.0));
    }

    mod hal {
        use super::super::*;
        use crate::testing::{float, TestHost};
        use hal_core::Value;

        #[test]
        fn names_and_defaults() {
            let h = TestHost::new("lim-names");
            for def in modules() {
                h.load(def, &[]).unwrap();
            }
            assert_eq!(
                h.items("limit3.0."),
                [
                    "limit3.0.enable",
                    "limit3.0.in",
                    "limit3.0.load",
                    "limit3.0.max",
                    "limit3.0.maxa",
                    "limit3.0.maxv",
                    "limit3.0.min",
                    "limit3.0.out",
                    "limit3.0.smooth-steps",
                    "limit3.0.time",
                    "limit3.0.tmax",
                    "limit3.0.tmax-increased",
                ]
            );
            assert_eq!(h.get("limit3.0.enable"), Value::Bit(true));
            assert_eq!(h.get("limit3.0.smooth-steps"), Value::U32(2));
            assert_eq!(h.get("limit3.0.maxa"), Value::Float(1e7));
            assert_eq!(h.get("limit2.0.maxv"), Value::Float(1e20));
            assert_eq!(h.get("limit1.0.min"), Value::Float(-1e20));
            assert_eq!(h.getp("comp.0.hyst"), Value::Float(0.0));
            assert_eq!(h.getp("near.0.scale"), Value::Float(1.0));
            assert_eq!(h.getp("near.0.difference"), Value::Float(0.0));
            assert_eq!(h.getp("deadzone.0.threshold"), Value::Float(1.0));
            assert_eq!(h.getp("deadzone.0.center"), Value::Float(0.0));
            for p in [
                "wcomp.0.under",
                "wcomp.0.over",
                "minmax.0.max",
                "minmax.0.min",
            ] {
                h.get(p);
            }
            let funcs: Vec<String> = h
                .instance()
                .functs()
                .unwrap()
                .into_iter()
                .map(|f| f.name)
                .collect();
            for f in [
                "limit1.0",
                "limit2.0",
                "limit3.0",
                "comp.0",
                "wcomp.0",
                "near.0",
                "deadzone.0",
                "minmax.0",
            ] {
                assert!(funcs.iter().any(|n| n == f), "{f} exported");
            }
        }

        #[test]
        fn count_and_names_select_instances() {
            let h = TestHost::new("lim-inst");
            h.load(&LIMIT1, &["count=3"]).unwrap();
            h.get("limit1.2.out");
            h.load(&NEAR, &["names=a.b,c"]).unwrap();
            h.get("a.b.out");
            h.get("c.in1");
            // Both at once is a load error that leaves nothing behind.
            assert!(h.load(&COMP, &["count=2", "names=x"]).is_err());
            assert!(h.items("comp").is_empty());
            assert!(h.items("x.").is_empty());
        }

        #[test]
        fn limit3_runs_and_reads_its_output_back() {
            let mut h = TestHost::new("lim-l3");
            h.load(&LIMIT3, &[]).unwrap();
            h.load(&COMP, &[]).unwrap();
            h.load(&MINMAX, &[]).unwrap();
            h.set("limit3.0.in", Value::Float(500.0));
            h.set("limit3.0.maxv", Value::Float(500.0));
            // comp: in1 above in0 beyond the hysteresis band.
            h.set("comp.0.in1", Value::Float(1.0));
            h.setp("comp.0.hyst", Value::Float(0.5));
            h.set("minmax.0.in", Value::Float(-2.0));
            h.thread(&["limit3.0", "comp.0", "minmax.0"]);
            let n = h.run(20);
            let out = float(h.get("limit3.0.out"));
            assert_eq!(format!("{out:.6}"), format!("{:.6}", 0.5 * n as f64));
            assert_eq!(h.get("comp.0.out"), Value::Bit(true));
            assert_eq!(h.get("comp.0.equal"), Value::Bit(false));
            assert_eq!(h.get("minmax.0.min"), Value::Float(-2.0));
            assert_eq!(h.get("minmax.0.max"), Value::Float(0.0));
        }
    }
}
