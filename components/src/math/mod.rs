//! Arithmetic (reference section 6): abs, abs_s32, abs_s64, sum2, mult2,
//! div2, scale, invert, hypot, blend, constant. In their own files:
//! scaled_s32_sums, offset, knob2float, feedcomp, joyhandle.
//!
//! Each component's per-call arithmetic is a plain function or struct
//! (`abs_f64`, [`Div2`], `invert`, ...) that the HAL glue calls with the
//! pin values, so the behaviour can be tested without a HAL.

pub mod feedcomp;
pub mod joyhandle;
pub mod knob2float;
pub mod offset;
pub mod scaled_s32_sums;

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;

/// Outputs of the abs family for one input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbsOut<T> {
    /// The magnitude (see the quirks of each variant).
    pub out: T,
    /// TRUE when the input took the negative branch.
    pub sign: bool,
    /// The input is above the positive threshold.
    pub is_positive: bool,
    /// The input is below the negative threshold.
    pub is_negative: bool,
}

/// `abs` of a float. `-0.0 >= 0.0`, so -0.0 passes through unchanged;
/// NaN fails the test and comes out negated with `sign` TRUE. The
/// positive/negative flags have a 1e-6 dead zone.
pub fn abs_f64(x: f64) -> AbsOut<f64> {
    let (out, sign) = if x >= 0.0 { (x, false) } else { (-x, true) };
    AbsOut {
        out,
        sign,
        is_positive: x > 0.000001,
        is_negative: x < -0.000001,
    }
}

/// `abs_s32`: negation wraps, so `i32::MIN` stays `i32::MIN`.
pub fn abs_i32(x: i32) -> AbsOut<i32> {
    let (out, sign) = if x >= 0 {
        (x, false)
    } else {
        (x.wrapping_neg(), true)
    };
    AbsOut {
        out,
        sign,
        is_positive: x > 0,
        is_negative: x < 0,
    }
}

/// `abs_s64`: negation wraps, so `i64::MIN` stays `i64::MIN`.
pub fn abs_i64(x: i64) -> AbsOut<i64> {
    let (out, sign) = if x >= 0 {
        (x, false)
    } else {
        (x.wrapping_neg(), true)
    };
    AbsOut {
        out,
        sign,
        is_positive: x > 0,
        is_negative: x < 0,
    }
}

/// Builds one abs-family instance of value type `T` around `f`.
fn abs_instance<T: hal_core::PinValue>(
    inst: &mut Inst<'_, '_>,
    uses_fp: bool,
    f: fn(T) -> AbsOut<T>,
) -> Result<()> {
    let input = inst.pin_in::<T>("in")?;
    let out = inst.pin_out::<T>("out")?;
    let sign = inst.pin_out::<bool>("sign")?;
    let is_positive = inst.pin_out::<bool>("is-positive")?;
    let is_negative = inst.pin_out::<bool>("is-negative")?;
    inst.funct("_", uses_fp, move |_| {
        let r = f(input.get());
        sign.set(r.sign);
        out.set(r.out);
        is_positive.set(r.is_positive);
        is_negative.set(r.is_negative);
    })
}

/// `abs`: absolute value of a float, with sign and threshold flags.
pub struct Abs;
impl HalComp for Abs {
    const NAME: &'static str = "abs";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        abs_instance::<f64>(inst, true, abs_f64)
    }
}
halcomp_module!(pub ABS, Abs, "absolute value and sign of a float");

/// `abs_s32`: absolute value of an s32.
pub struct AbsS32;
impl HalComp for AbsS32 {
    const NAME: &'static str = "abs_s32";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        abs_instance::<i32>(inst, false, abs_i32)
    }
}
halcomp_module!(pub ABS_S32, AbsS32, "absolute value and sign of an s32");

/// `abs_s64`: absolute value of an s64.
pub struct AbsS64;
impl HalComp for AbsS64 {
    const NAME: &'static str = "abs_s64";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        abs_instance::<i64>(inst, false, abs_i64)
    }
}
halcomp_module!(pub ABS_S64, AbsS64, "absolute value and sign of an s64");

/// The smallest deadband div2 and invert accept; a smaller one (or the
/// default 0) is replaced by it, and the param rewritten.
pub const MIN_DEADBAND: f64 = 1e-12;

/// Applies the deadband floor: the deadband to use, and whether the
/// param must be rewritten to it.
fn floor_deadband(deadband: f64) -> (f64, bool) {
    if deadband < MIN_DEADBAND {
        (MIN_DEADBAND, true)
    } else {
        (deadband, false)
    }
}

/// Where a divisor lies relative to the deadband `d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Band {
    /// `-d < x < 0`: replaced by `-d`.
    Negative,
    /// `0 <= x < d` (including an exact 0 and -0.0): replaced by `d`.
    Positive,
    /// Outside the deadband (or NaN): used as it is.
    Outside,
}

/// Classifies divisor `x` against deadband `d`.
pub fn band(x: f64, d: f64) -> Band {
    if -d < x && x < 0.0 {
        Band::Negative
    } else if 0.0 <= x && x < d {
        Band::Positive
    } else {
        Band::Outside
    }
}

/// The texts div2 writes to stderr, indexed by [`Div2Message`]. The first
/// is LinuxCNC's exact text; the second mirrors it for the positive side.
pub static DIV2_TEXTS: &[&str] = &[
    "\n \n DIV2 DIVISOR IS TOO CLOSE TO -ZERO,\n THEREFORE -DEADBAND IS USED.\n INCREASE THE DIVISOR, in1.\n \n \n",
    "\n \n DIV2 DIVISOR IS TOO CLOSE TO +ZERO,\n THEREFORE +DEADBAND IS USED.\n INCREASE THE DIVISOR, in1.\n \n \n",
];

/// Which div2 message a call wants printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Div2Message {
    /// The divisor was in `(-deadband, 0)`.
    NearNegativeZero = 0,
    /// The divisor was in `[0, deadband)`.
    NearPositiveZero = 1,
}

/// Result of one div2 call.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Div2Out {
    /// The quotient.
    pub out: f64,
    /// The value to write back to the `deadband` param, if it was floored.
    pub deadband: Option<f64>,
    /// A message to print (at most once until the divisor leaves the band).
    pub message: Option<Div2Message>,
}

/// div2's per-instance state: whether the one-time message has been
/// printed since the divisor was last outside the deadband. One flag
/// serves both sides, so crossing from -0 to +0 prints only once.
#[derive(Debug, Clone, Default)]
pub struct Div2 {
    warned: bool,
}

impl Div2 {
    /// One call: `in0 / in1`, a divisor inside the deadband replaced by
    /// the signed deadband.
    pub fn update(&mut self, in0: f64, in1: f64, deadband: f64) -> Div2Out {
        let (d, rewrite) = floor_deadband(deadband);
        let deadband = rewrite.then_some(d);
        let (out, msg) = match band(in1, d) {
            Band::Negative => (in0 / -d, Div2Message::NearNegativeZero),
            Band::Positive => (in0 / d, Div2Message::NearPositiveZero),
            Band::Outside => {
                self.warned = false;
                return Div2Out {
                    out: in0 / in1,
                    deadband,
                    message: None,
                };
            }
        };
        let message = (!self.warned).then_some(msg);
        self.warned = true;
        Div2Out {
            out,
            deadband,
            message,
        }
    }
}

/// `div2`: out = in0 / in1, with a deadband around a zero divisor.
pub struct Div2Comp;
impl HalComp for Div2Comp {
    const NAME: &'static str = "div2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let out = inst.pin_out::<f64>("out")?;
        let deadband = inst.param_rw::<f64>("deadband", 0.0)?;
        let notice = Notice::new(DIV2_TEXTS);
        let mut state = Div2::default();
        inst.funct("_", true, move |_| {
            let r = state.update(in0.get(), in1.get(), deadband.get());
            if let Some(d) = r.deadband {
                deadband.set(d);
            }
            if let Some(m) = r.message {
                notice.post(m as usize);
            }
            out.set(r.out);
        })
    }
}
halcomp_module!(pub DIV2, Div2Comp, "quotient of two inputs");

/// `scale`: out = in * gain + offset.
pub fn scale(input: f64, gain: f64, offset: f64) -> f64 {
    input * gain + offset
}

/// `scale`: gain and offset applied to a float (both pins, default 0).
pub struct Scale;
impl HalComp for Scale {
    const NAME: &'static str = "scale";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let gain = inst.pin_in::<f64>("gain")?;
        let offset = inst.pin_in::<f64>("offset")?;
        let out = inst.pin_out::<f64>("out")?;
        inst.funct("_", true, move |_| {
            out.set(scale(input.get(), gain.get(), offset.get()))
        })
    }
}
halcomp_module!(pub SCALE, Scale, "gain and offset");

/// `invert`: `1 / in` with the deadband rule of div2 (no message). Returns
/// the output and the floored deadband to write back, if any.
pub fn invert(input: f64, deadband: f64) -> (f64, Option<f64>) {
    let (d, rewrite) = floor_deadband(deadband);
    let out = match band(input, d) {
        Band::Negative => -1.0 / d,
        Band::Positive => 1.0 / d,
        Band::Outside => 1.0 / input,
    };
    (out, rewrite.then_some(d))
}

/// `invert`: reciprocal of a float.
pub struct Invert;
impl HalComp for Invert {
    const NAME: &'static str = "invert";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let deadband = inst.param_rw::<f64>("deadband", 0.0)?;
        inst.funct("_", true, move |_| {
            let (o, d) = invert(input.get(), deadband.get());
            if let Some(d) = d {
                deadband.set(d);
            }
            out.set(o);
        })
    }
}
halcomp_module!(pub INVERT, Invert, "reciprocal with a deadband around zero");

/// `hypot`: the plain formula `sqrt((a*a + b*b) + c*c)`, not the
/// overflow-safe library `hypot`.
pub fn hypot3(a: f64, b: f64, c: f64) -> f64 {
    ((a * a + b * b) + c * c).sqrt()
}

/// `hypot`: Euclidean length of a three-vector.
pub struct Hypot;
impl HalComp for Hypot {
    const NAME: &'static str = "hypot";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let in2 = inst.pin_in::<f64>("in2")?;
        let out = inst.pin_out::<f64>("out")?;
        inst.funct("_", true, move |_| {
            out.set(hypot3(in0.get(), in1.get(), in2.get()))
        })
    }
}
halcomp_module!(pub HYPOT, Hypot, "three-input hypotenuse (Euclidean distance)");

/// `blend`: `in1 * s + in2 * (1 - s)`, `s` clamped to [0, 1] unless
/// `open`.
pub fn blend(in1: f64, in2: f64, select: f64, open: bool) -> f64 {
    // `clamp` tests `< min` then `> max`, as the component does, so NaN
    // and -0.0 pass through unchanged.
    let s = if open { select } else { select.clamp(0.0, 1.0) };
    in1 * s + in2 * (1.0 - s)
}

/// `blend`: linear blend of two inputs.
pub struct Blend;
impl HalComp for Blend {
    const NAME: &'static str = "blend";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in1 = inst.pin_in::<f64>("in1")?;
        let in2 = inst.pin_in::<f64>("in2")?;
        let select = inst.pin_in::<f64>("select")?;
        let out = inst.pin_out::<f64>("out")?;
        let open = inst.param_rw::<bool>("open", false)?;
        inst.funct("_", true, move |_| {
            out.set(blend(in1.get(), in2.get(), select.get(), open.get()))
        })
    }
}
halcomp_module!(pub BLEND, Blend, "perform linear interpolation between two values");

/// `constant`: out = value. Removed from LinuxCNC in November 2025, but
/// HAL files written for 2.9 and older use it; it costs nothing to keep
/// them loading. `value` defaults to 0.0, as the real component did.
pub struct Constant;
impl HalComp for Constant {
    const NAME: &'static str = "constant";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let out = inst.pin_out::<f64>("out")?;
        let value = inst.param_rw::<f64>("value", 0.0)?;
        inst.funct("_", true, move |_| out.set(value.get()))
    }
}
halcomp_module!(pub CONSTANT, Constant, "a constant value on a pin (LinuxCNC 2.9)");

/// `mult2`: out = in0 * in1.
pub struct Mult2;
impl HalComp for Mult2 {
    const NAME: &'static str = "mult2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let out = inst.pin_out::<f64>("out")?;
        inst.funct("_", true, move |_| out.set(in0.get() * in1.get()))
    }
}
halcomp_module!(pub MULT2, Mult2, "product of two inputs");

/// `sum2`: out = (in0 * gain0 + in1 * gain1) + offset.
pub struct Sum2;
impl HalComp for Sum2 {
    const NAME: &'static str = "sum2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let out = inst.pin_out::<f64>("out")?;
        let gain0 = inst.param_rw::<f64>("gain0", 1.0)?;
        let gain1 = inst.param_rw::<f64>("gain1", 1.0)?;
        let offset = inst.param_rw::<f64>("offset", 0.0)?;
        inst.funct("_", true, move |_| {
            out.set((in0.get() * gain0.get() + in1.get() * gain1.get()) + offset.get())
        })
    }
}
halcomp_module!(pub SUM2, Sum2, "weighted sum of two inputs");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &ABS,
        &ABS_S32,
        &ABS_S64,
        &SUM2,
        &MULT2,
        &DIV2,
        &SCALE,
        &INVERT,
        &HYPOT,
        &BLEND,
        &CONSTANT,
        &scaled_s32_sums::MODULE,
        &offset::MODULE,
        &knob2float::MODULE,
        &feedcomp::MODULE,
        &joyhandle::MODULE,
    ]
}

#[cfg(test)]
mod tests;
