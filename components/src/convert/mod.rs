//! The `conv_<in>_<out>` family: one value converted between HAL types,
//! with an optional clamp and an out-of-range flag where the target cannot
//! hold every source value.

use hal_core::{HalType, In, Out, Result, Value};

use crate::cmath::{f64_to_i32, f64_to_i64, f64_to_u32, f64_to_u64};
use crate::halcomp::{HalComp, Inst};

/// Range of an integer-like type, as i128.
fn range(t: HalType) -> (i128, i128) {
    match t {
        HalType::Bit => (0, 1),
        HalType::S32 => (i32::MIN as i128, i32::MAX as i128),
        HalType::U32 => (0, u32::MAX as i128),
        HalType::S64 => (i64::MIN as i128, i64::MAX as i128),
        HalType::U64 => (0, u64::MAX as i128),
        // Only ever a source here; its range covers every target.
        HalType::Float => (i128::MIN, i128::MAX),
        // No conversion takes or gives a port: nothing fits it.
        HalType::Port => (0, 0),
    }
}

/// Which bounds a pair tests: the source can exceed the target's top or
/// bottom. Pairs testing neither have no clamp or out-of-range.
pub fn tested_bounds(from: HalType, to: HalType) -> (bool, bool) {
    if to == HalType::Float {
        return (false, false);
    }
    let (flo, fhi) = range(from);
    let (tlo, thi) = range(to);
    (fhi > thi, flo < tlo)
}

/// A source value as a number for comparisons: integers exactly, floats as
/// themselves.
enum Num {
    Int(i128),
    Float(f64),
}

fn num(v: Value) -> Num {
    match v {
        Value::Bit(b) => Num::Int(b as i128),
        Value::Float(f) => Num::Float(f),
        Value::S32(x) => Num::Int(x as i128),
        Value::U32(x) => Num::Int(x as i128),
        Value::S64(x) => Num::Int(x as i128),
        Value::U64(x) => Num::Int(x as i128),
        Value::Port(size) => Num::Int(size as i128),
    }
}

/// C's conversion of `v` to type `to`.
pub fn c_convert(v: Value, to: HalType) -> Value {
    match (num(v), to) {
        (_, HalType::Float) => Value::Float(match v {
            Value::Bit(b) => b as u8 as f64,
            Value::Float(f) => f,
            Value::S32(x) => x as f64,
            Value::U32(x) => x as f64,
            Value::S64(x) => x as f64,
            Value::U64(x) => x as f64,
            Value::Port(size) => size as f64,
        }),
        // No conversion gives a port.
        (_, HalType::Port) => Value::Port(0),
        (Num::Int(i), HalType::Bit) => Value::Bit(i != 0),
        (Num::Int(i), HalType::S32) => Value::S32(i as i32),
        (Num::Int(i), HalType::U32) => Value::U32(i as u32),
        (Num::Int(i), HalType::S64) => Value::S64(i as i64),
        (Num::Int(i), HalType::U64) => Value::U64(i as u64),
        (Num::Float(f), HalType::Bit) => Value::Bit(f != 0.0),
        (Num::Float(f), HalType::S32) => Value::S32(f64_to_i32(f)),
        (Num::Float(f), HalType::U32) => Value::U32(f64_to_u32(f)),
        (Num::Float(f), HalType::S64) => Value::S64(f64_to_i64(f)),
        (Num::Float(f), HalType::U64) => Value::U64(f64_to_u64(f)),
    }
}

fn same(a: Value, b: Value) -> bool {
    match (a, b) {
        (Value::Float(x), Value::Float(y)) => x == y,
        _ => a.to_bits() == b.to_bits(),
    }
}

/// One `conv_<in>_<out>` pair, with its bounds worked out once at load
/// rather than on every call.
#[derive(Debug, Clone, Copy)]
pub struct Conversion {
    from: HalType,
    to: HalType,
    /// The source can exceed the target's top.
    test_hi: bool,
    /// The source can go below the target's bottom.
    test_lo: bool,
    /// The target's range, as integers (integer sources) and as floats
    /// (float sources).
    lo: i128,
    hi: i128,
    lo_f: f64,
    hi_f: f64,
    /// What clamping to the top or the bottom outputs.
    top: Value,
    bottom: Value,
}

impl Conversion {
    /// The conversion from `from` to `to`.
    pub fn new(from: HalType, to: HalType) -> Conversion {
        let (test_hi, test_lo) = tested_bounds(from, to);
        let (lo, hi) = range(to);
        Conversion {
            from,
            to,
            test_hi,
            test_lo,
            lo,
            hi,
            lo_f: lo as f64,
            hi_f: hi as f64,
            top: c_convert(Value::U64(hi as u64), to),
            bottom: c_convert(Value::S64(lo as i64), to),
        }
    }

    /// Whether the pair can lose information, and so has a `clamp` param
    /// and an `out-of-range` pin.
    pub fn checked(&self) -> bool {
        self.test_hi || self.test_lo
    }

    /// One conversion of `v` (of the source type); returns the output and
    /// the new out-of-range flag (`None` leaves it unchanged, as wrap mode
    /// does when nothing was lost).
    #[inline]
    pub fn step(&self, v: Value, clamp: bool) -> (Value, Option<bool>) {
        if clamp {
            let (above, below) = match num(v) {
                Num::Int(i) => (i > self.hi, i < self.lo),
                Num::Float(f) => (f > self.hi_f, f < self.lo_f),
            };
            if self.test_hi && above {
                return (self.top, Some(true));
            }
            if self.test_lo && below {
                return (self.bottom, Some(true));
            }
            return (c_convert(v, self.to), Some(false));
        }
        let out = c_convert(v, self.to);
        let lost = !same(c_convert(out, self.from), v);
        (out, lost.then_some(true))
    }
}

/// Builds one conversion instance.
fn build(inst: &mut Inst<'_, '_>, from: HalType, to: HalType) -> Result<()> {
    let input = inst.pin_raw::<In>("in", from)?;
    let output = inst.pin_raw::<Out>("out", to)?;
    let uses_fp = from == HalType::Float || to == HalType::Float;
    let conv = Conversion::new(from, to);
    if !conv.checked() {
        return inst.funct("_", uses_fp, move |_| {
            output.set_bits(c_convert(input.value(), to).to_bits());
        });
    }
    let out_of_range = inst.pin_out::<bool>("out-of-range")?;
    let clamp = inst.param_rw::<bool>("clamp", false)?;
    inst.funct("_", uses_fp, move |_| {
        let (out, flag) = conv.step(input.value(), clamp.get());
        output.set_bits(out.to_bits());
        if let Some(f) = flag {
            out_of_range.set(f);
        }
    })
}

macro_rules! conv {
    ($($ty:ident $static:ident $name:literal $from:ident $to:ident;)*) => {
        $(
            #[doc = concat!("`", $name, "`.")]
            pub struct $ty;
            impl HalComp for $ty {
                const NAME: &'static str = $name;
                fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
                    build(inst, HalType::$from, HalType::$to)
                }
            }
            crate::halcomp_module!(pub $static, $ty, concat!("converts ", stringify!($from), " to ", stringify!($to)));
        )*
        /// Every module of this family.
        pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
            vec![$(&$static),*]
        }
    };
}

conv! {
    ConvBitFloat CONV_BIT_FLOAT "conv_bit_float" Bit Float;
    ConvBitS32 CONV_BIT_S32 "conv_bit_s32" Bit S32;
    ConvBitU32 CONV_BIT_U32 "conv_bit_u32" Bit U32;
    ConvBitS64 CONV_BIT_S64 "conv_bit_s64" Bit S64;
    ConvBitU64 CONV_BIT_U64 "conv_bit_u64" Bit U64;
    ConvFloatS32 CONV_FLOAT_S32 "conv_float_s32" Float S32;
    ConvFloatU32 CONV_FLOAT_U32 "conv_float_u32" Float U32;
    ConvFloatS64 CONV_FLOAT_S64 "conv_float_s64" Float S64;
    ConvFloatU64 CONV_FLOAT_U64 "conv_float_u64" Float U64;
    ConvS32Bit CONV_S32_BIT "conv_s32_bit" S32 Bit;
    ConvS32Float CONV_S32_FLOAT "conv_s32_float" S32 Float;
    ConvS32U32 CONV_S32_U32 "conv_s32_u32" S32 U32;
    ConvS32S64 CONV_S32_S64 "conv_s32_s64" S32 S64;
    ConvS32U64 CONV_S32_U64 "conv_s32_u64" S32 U64;
    ConvS64Bit CONV_S64_BIT "conv_s64_bit" S64 Bit;
    ConvS64Float CONV_S64_FLOAT "conv_s64_float" S64 Float;
    ConvS64S32 CONV_S64_S32 "conv_s64_s32" S64 S32;
    ConvS64U32 CONV_S64_U32 "conv_s64_u32" S64 U32;
    ConvS64U64 CONV_S64_U64 "conv_s64_u64" S64 U64;
    ConvU32Bit CONV_U32_BIT "conv_u32_bit" U32 Bit;
    ConvU32Float CONV_U32_FLOAT "conv_u32_float" U32 Float;
    ConvU32S32 CONV_U32_S32 "conv_u32_s32" U32 S32;
    ConvU32S64 CONV_U32_S64 "conv_u32_s64" U32 S64;
    ConvU32U64 CONV_U32_U64 "conv_u32_u64" U32 U64;
    ConvU64Bit CONV_U64_BIT "conv_u64_bit" U64 Bit;
    ConvU64Float CONV_U64_FLOAT "conv_u64_float" U64 Float;
    ConvU64S32 CONV_U64_S32 "conv_u64_s32" U64 S32;
    ConvU64U32 CONV_U64_U32 "conv_u64_u32" U64 U32;
    ConvU64S64 CONV_U64_S64 "conv_u64_s64" U64 S64;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One conversion of `v` to `to`.
    fn step(v: Value, to: HalType, clamp: bool) -> (Value, Option<bool>) {
        Conversion::new(v.hal_type(), to).step(v, clamp)
    }

    #[test]
    fn bounds_follow_the_reference_table() {
        use HalType::*;
        assert_eq!(tested_bounds(Float, S32), (true, true));
        assert_eq!(tested_bounds(S32, U32), (false, true));
        assert_eq!(tested_bounds(S32, U64), (false, true));
        assert_eq!(tested_bounds(S64, U64), (false, true));
        assert_eq!(tested_bounds(U32, S32), (true, false));
        assert_eq!(tested_bounds(U64, S64), (true, false));
        assert_eq!(tested_bounds(U32, S64), (false, false));
        assert_eq!(tested_bounds(Bit, U64), (false, false));
        assert_eq!(tested_bounds(S64, Float), (false, false));
        assert_eq!(modules().len(), 29);
    }

    #[test]
    fn wrap_mode_flags_lost_information_and_is_sticky() {
        use HalType::*;
        assert_eq!(
            step(Value::Float(1.5), S32, false),
            (Value::S32(1), Some(true))
        );
        assert_eq!(step(Value::Float(2.0), S32, false), (Value::S32(2), None));
        assert_eq!(
            step(Value::S32(-1), U32, false),
            (Value::U32(u32::MAX), None)
        );
        assert_eq!(
            step(Value::U64(2), Bit, false),
            (Value::Bit(true), Some(true))
        );
        assert_eq!(
            step(Value::S64(1 << 40), S32, false),
            (Value::S32(0), Some(true))
        );
    }

    #[test]
    fn clamp_mode_saturates_and_clears() {
        use HalType::*;
        assert_eq!(
            step(Value::Float(3e9), S32, true),
            (Value::S32(i32::MAX), Some(true))
        );
        assert_eq!(
            step(Value::Float(-1.0), U32, true),
            (Value::U32(0), Some(true))
        );
        assert_eq!(
            step(Value::Float(5.7), U32, true),
            (Value::U32(5), Some(false))
        );
        assert_eq!(step(Value::S32(-5), U64, true), (Value::U64(0), Some(true)));
        assert_eq!(
            step(Value::U64(u64::MAX), S64, true),
            (Value::S64(i64::MAX), Some(true))
        );
        // Exactly 2^63 is not above the comparison constant.
        assert_eq!(
            step(Value::Float(9_223_372_036_854_775_808.0), S64, true),
            (Value::S64(i64::MIN), Some(false))
        );
        assert_eq!(
            step(Value::Float(f64::NAN), S32, true),
            (Value::S32(i32::MIN), Some(false))
        );
    }
}
