//! Just enough x87 extended precision (`long double`, 64-bit mantissa)
//! to compute the angle conversions of G-code functions the way
//! LinuxCNC does: `sin[90]` is `sinl(90 * M_PIl / 180)` rounded to a
//! double, so `sin[180]` is a tiny positive number, `cos[60]` is 0.5
//! exactly, and `acos[0.5]` is 60 exactly. Plain double arithmetic gives
//! other last bits (and other signs of zero in printed output). Cutter
//! compensation adds and subtracts `M_PIl` multiples the same way.

/// A finite extended-precision number: `mant * 2^(exp - 63)`, with the
/// top bit of `mant` set (or `mant == 0` for zero).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ext {
    neg: bool,
    exp: i32,
    mant: u64,
}

/// `M_PIl`: π rounded to 64 bits of mantissa.
const PI_L: Ext = Ext {
    neg: false,
    exp: 1,
    mant: 0xC90F_DAA2_2168_C235,
};

/// π in three doubles (exact sum to about 160 bits) for reduction.
const PI_1: f64 = std::f64::consts::PI;
const PI_2: f64 = 1.2246467991473532e-16;
const PI_3: f64 = -2.9947698097183397e-33;

impl Ext {
    const ZERO: Ext = Ext {
        neg: false,
        exp: 0,
        mant: 0,
    };

    fn from_f64(x: f64) -> Ext {
        if x == 0.0 || !x.is_finite() {
            return Ext {
                neg: x.is_sign_negative(),
                ..Ext::ZERO
            };
        }
        let bits = x.to_bits();
        let neg = bits >> 63 != 0;
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let frac = bits & ((1 << 52) - 1);
        let (mut mant, mut exp) = if biased == 0 {
            (frac, -1022)
        } else {
            (frac | (1 << 52), biased - 1023)
        };
        // value = mant * 2^(exp - 52); normalise the top bit to bit 63.
        let shift = mant.leading_zeros();
        mant <<= shift;
        exp -= shift as i32 - 11;
        Ext { neg, exp, mant }
    }

    /// Round a 128-bit magnitude `m * 2^(e - 127)` to 64 bits.
    fn round(neg: bool, m: u128, e: i32) -> Ext {
        if m == 0 {
            return Ext { neg, ..Ext::ZERO };
        }
        let lz = m.leading_zeros();
        let m = m << lz;
        let e = e - lz as i32;
        let hi = (m >> 64) as u64;
        let lo = m as u64;
        let half = 1u64 << 63;
        let round_up = lo > half || (lo == half && hi & 1 == 1);
        let (mant, exp) = match hi.checked_add(round_up as u64) {
            Some(v) => (v, e),
            None => (half, e + 1),
        };
        Ext { neg, exp, mant }
    }

    fn mul(self, b: Ext) -> Ext {
        let m = self.mant as u128 * b.mant as u128;
        // (ma 2^(ea-63)) (mb 2^(eb-63)) = m 2^(ea+eb-126) = m 2^((ea+eb+1) - 127)
        Ext::round(self.neg != b.neg, m, self.exp + b.exp + 1)
    }

    /// The sum, rounded once to 64 bits of mantissa.
    fn add(self, b: Ext) -> Ext {
        if self.mant == 0 {
            return b;
        }
        if b.mant == 0 {
            return self;
        }
        let (big, small) = if (self.exp, self.mant) >= (b.exp, b.mant) {
            (self, b)
        } else {
            (b, self)
        };
        // Both mantissas at bits 126..63 of 128, the smaller shifted
        // right by the exponent difference with a sticky bit for what
        // falls off (63 guard bits are plenty to round correctly).
        let mb = (big.mant as u128) << 63;
        let ms = (small.mant as u128) << 63;
        let shift = (big.exp - small.exp) as u32;
        let ms = if shift >= 127 {
            1
        } else {
            (ms >> shift) | u128::from(ms & ((1u128 << shift) - 1) != 0)
        };
        let m = if big.neg == small.neg {
            mb + ms
        } else {
            mb - ms
        };
        if m == 0 {
            return Ext::ZERO;
        }
        // m 2^(eb - 126) = m 2^((eb + 1) - 127)
        Ext::round(big.neg, m, big.exp + 1)
    }

    fn div(self, b: Ext) -> Ext {
        if self.mant == 0 {
            return Ext {
                neg: self.neg != b.neg,
                ..Ext::ZERO
            };
        }
        let num = (self.mant as u128) << 64;
        let d = b.mant as u128;
        let q = num / d;
        let r = num % d;
        let guard = (r << 1) / d;
        let sticky = ((r << 1) % d != 0) as u128;
        let m = (q << 2) | (guard << 1) | sticky;
        // a/b = m 2^(ea - eb - 66) = m 2^((ea - eb + 61) - 127)
        Ext::round(self.neg != b.neg, m, self.exp - b.exp + 61)
    }

    /// Round to the nearest double (ties to even).
    fn to_f64(self) -> f64 {
        if self.mant == 0 {
            return if self.neg { -0.0 } else { 0.0 };
        }
        let top = (self.mant >> 11) as f64; // 53 bits, exact
        let rest = self.mant & 0x7ff;
        let half = 0x400;
        let mut m = top;
        if rest > half || (rest == half && (self.mant >> 11) & 1 == 1) {
            m += 1.0;
        }
        // Scale in two steps so that subnormal results do not flush.
        let e = self.exp - 52;
        let v = m * 2f64.powi(e / 2) * 2f64.powi(e - e / 2);
        if self.neg {
            -v
        } else {
            v
        }
    }

    /// The value as a head double and the exact remainder.
    fn to_pair(self) -> (f64, f64) {
        let hi = self.to_f64();
        let h = Ext::from_f64(hi);
        if h.mant == 0 || self.mant == 0 {
            return (hi, 0.0);
        }
        let base = self.exp.min(h.exp) - 63;
        let (sa, sb) = (self.exp - 63 - base, h.exp - 63 - base);
        if sa > 60 || sb > 60 {
            return (hi, 0.0);
        }
        let signed = |e: Ext, shift: i32| {
            let v = (e.mant as i128) << shift;
            if e.neg {
                -v
            } else {
                v
            }
        };
        let diff = signed(self, sa) - signed(h, sb);
        (hi, diff as f64 * 2f64.powi(base))
    }
}

/// A double-double: `hi + lo` with `|lo| <= ulp(hi) / 2`.
#[derive(Debug, Clone, Copy)]
struct Dd {
    hi: f64,
    lo: f64,
}

impl Dd {
    fn new(hi: f64, lo: f64) -> Dd {
        let s = hi + lo;
        Dd {
            hi: s,
            lo: lo - (s - hi),
        }
    }

    fn add(self, b: Dd) -> Dd {
        let s = self.hi + b.hi;
        let v = s - self.hi;
        let e = (self.hi - (s - v)) + (b.hi - v);
        Dd::new(s, e + self.lo + b.lo)
    }

    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    fn mul(self, b: Dd) -> Dd {
        let p = self.hi * b.hi;
        let e = self.hi.mul_add(b.hi, -p);
        Dd::new(p, e + self.hi * b.lo + self.lo * b.hi)
    }

    fn mul_f(self, b: f64) -> Dd {
        self.mul(Dd { hi: b, lo: 0.0 })
    }

    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self.add(b.mul_f(q1).neg());
        let q2 = r.hi / b.hi;
        let r = r.add(b.mul_f(q2).neg());
        let q3 = r.hi / b.hi;
        Dd::new(q1, q2).add(Dd { hi: q3, lo: 0.0 })
    }

    fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

/// sin and cos of `|r| <= π/4` by their series, in double-double.
fn sin_cos_small(r: Dd) -> (Dd, Dd) {
    let r2 = r.mul(r);
    let (mut sin, mut term) = (r, r);
    for n in 1..16 {
        let d = f64::from(2 * n * (2 * n + 1));
        term = term.mul(r2).div(Dd { hi: -d, lo: 0.0 });
        sin = sin.add(term);
    }
    let one = Dd { hi: 1.0, lo: 0.0 };
    let (mut cos, mut term) = (one, one);
    for n in 1..16 {
        let d = f64::from((2 * n - 1) * (2 * n));
        term = term.mul(r2).div(Dd { hi: -d, lo: 0.0 });
        cos = cos.add(term);
    }
    (sin, cos)
}

/// sin, cos or tan of an extended-precision angle, rounded to double.
fn trig(a: Ext, f: Trig) -> f64 {
    trig_dd(a, f).to_f64()
}

/// sin, cos or tan of an extended-precision angle in double-double.
fn trig_dd(a: Ext, f: Trig) -> Dd {
    let (hi, lo) = a.to_pair();
    if !hi.is_finite() || hi.abs() > 1e15 {
        let v = match f {
            Trig::Sin => hi.sin(),
            Trig::Cos => hi.cos(),
            Trig::Tan => hi.tan(),
        };
        return Dd { hi: v, lo: 0.0 };
    }
    let k = (hi / (PI_1 / 2.0)).round();
    // r = a - k π/2, with π/2 in three parts (each product exact in Dd).
    let mut r = Dd::new(hi, lo);
    for part in [PI_1 / 2.0, PI_2 / 2.0, PI_3 / 2.0] {
        r = r.add(Dd { hi: part, lo: 0.0 }.mul_f(-k));
    }
    let (s, c) = sin_cos_small(r);
    let (sin, cos) = match (k as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, s.neg()),
        2 => (s.neg(), c.neg()),
        _ => (c.neg(), s),
    };
    match f {
        Trig::Sin => sin,
        Trig::Cos => cos,
        Trig::Tan => sin.div(cos),
    }
}

#[derive(Clone, Copy)]
enum Trig {
    Sin,
    Cos,
    Tan,
}

fn degrees_to_radians(x: f64) -> Ext {
    Ext::from_f64(x).mul(PI_L).div(Ext::from_f64(180.0))
}

/// `sin(x * M_PIl / 180)` as LinuxCNC evaluates `SIN[x]`.
pub fn sin_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    trig(degrees_to_radians(x), Trig::Sin)
}

/// `cos(x * M_PIl / 180)`.
pub fn cos_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    trig(degrees_to_radians(x), Trig::Cos)
}

/// `tan(x * M_PIl / 180)`.
pub fn tan_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    trig(degrees_to_radians(x), Trig::Tan)
}

/// `(r * 180.0) / M_PIl` rounded to double (ACOS, ASIN, ATAN results):
/// the product is a double, the quotient a `long double`.
pub fn rad_to_deg(r: f64) -> f64 {
    if !r.is_finite() {
        return r;
    }
    Ext::from_f64(r * 180.0).div(PI_L).to_f64()
}

/// `a + k * M_PIl / 2` rounded to double, as C evaluates a double plus
/// a `long double` multiple of π and stores the result in a double
/// (cutter compensation's angles). `k` must be a power of two or its
/// negative (±1, ±2, ±4).
pub fn add_half_pis(a: f64, k: i32) -> f64 {
    if !a.is_finite() {
        return a + f64::from(k) * std::f64::consts::FRAC_PI_2;
    }
    let m = k.unsigned_abs();
    debug_assert!(m.is_power_of_two());
    let step = Ext {
        neg: k < 0,
        exp: PI_L.exp - 1 + m.trailing_zeros() as i32,
        mant: PI_L.mant,
    };
    Ext::from_f64(a).add(step).to_f64()
}

/// `((a + M_PIl) + b)` in `long double`, rounded to double.
pub fn sum_with_pi(a: f64, b: f64) -> f64 {
    if !a.is_finite() || !b.is_finite() {
        return a + std::f64::consts::PI + b;
    }
    Ext::from_f64(a).add(PI_L).add(Ext::from_f64(b)).to_f64()
}

/// `r * sinl(b - M_PIl / 2)` rounded to double: the `long double`
/// angle keeps its sine in extended precision until the product is
/// stored.
pub fn scaled_sin_less_half_pi(r: f64, b: f64) -> f64 {
    if !r.is_finite() || !b.is_finite() {
        return r * (b - std::f64::consts::FRAC_PI_2).sin();
    }
    let half = Ext {
        neg: true,
        exp: PI_L.exp - 1,
        mant: PI_L.mant,
    };
    trig_dd(Ext::from_f64(b).add(half), Trig::Sin)
        .mul_f(r)
        .to_f64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip() {
        for x in [1.0, -2.5, 0.1, 1e-300, 123456.789] {
            assert_eq!(Ext::from_f64(x).to_f64(), x);
        }
        assert_eq!(PI_L.to_f64(), std::f64::consts::PI);
        let q = Ext::from_f64(1.0).div(Ext::from_f64(3.0)).to_f64();
        assert_eq!(q, 1.0 / 3.0);
        let p = Ext::from_f64(3.0).mul(Ext::from_f64(7.0)).to_f64();
        assert_eq!(p, 21.0);
        let one = Ext::from_f64(1.0);
        assert_eq!(one.add(Ext::from_f64(2.0)).to_f64(), 3.0);
        assert_eq!(one.add(Ext::from_f64(-1.0)).to_f64(), 0.0);
        assert_eq!(one.add(Ext::from_f64(-0.25)).to_f64(), 0.75);
        assert_eq!(Ext::from_f64(1e300).add(one).to_f64(), 1e300);
    }

    #[test]
    fn half_pis_carry_the_long_double_remainder() {
        use std::f64::consts::{FRAC_PI_2, PI};
        assert_eq!(add_half_pis(0.0, 2), PI);
        assert_eq!(add_half_pis(0.0, -1), -FRAC_PI_2);
        // M_PIl is a little more than the double π: what is left is the
        // part of π a double drops (about 1.22e-16), cut to 64 bits.
        let rest = add_half_pis(PI, -2);
        assert!(rest < -1.2e-16 && rest > -1.3e-16, "{rest}");
        let rest = add_half_pis(-FRAC_PI_2, 1);
        assert!(rest > 6.0e-17 && rest < 6.2e-17, "{rest}");
        assert!((add_half_pis(1.0, 4) - (1.0 + 2.0 * PI)).abs() <= 1e-15);
        assert!(add_half_pis(f64::NAN, 1).is_nan());
        assert_eq!(sum_with_pi(-PI, 0.0), add_half_pis(-PI, 2));
        assert!((sum_with_pi(0.5, -0.25) - (PI + 0.25)).abs() < 1e-15);
        assert_eq!(
            scaled_sin_less_half_pi(2.0, FRAC_PI_2),
            2.0 * add_half_pis(FRAC_PI_2, -1)
        );
        assert_eq!(scaled_sin_less_half_pi(3.0, PI), 3.0);
        assert!(scaled_sin_less_half_pi(f64::NAN, 1.0).is_nan());
    }

    #[test]
    fn angles_match_long_double_results() {
        assert_eq!(cos_deg(60.0), 0.5);
        assert_eq!(sin_deg(30.0), 0.5);
        assert_eq!(rad_to_deg(0.5f64.acos()), 60.0);
        // M_PIl is a little more than π, so sin[180] is slightly below
        // zero and sin[-180] slightly above.
        assert!(sin_deg(180.0) < 0.0 && sin_deg(180.0) > -1e-18);
        assert!(sin_deg(-180.0) > 0.0);
        assert_eq!(sin_deg(90.0), 1.0);
        assert_eq!(cos_deg(0.0), 1.0);
        assert!(sin_deg(f64::NAN).is_nan() && sin_deg(f64::INFINITY).is_nan());
        assert!(rad_to_deg(f64::NAN).is_nan());
        assert_eq!(rad_to_deg(f64::INFINITY), f64::INFINITY);
    }
}
