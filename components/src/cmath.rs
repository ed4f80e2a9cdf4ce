//! C arithmetic as LinuxCNC's components get it from gcc on x86-64, where
//! it differs from Rust's: float-to-integer conversions of values out of
//! range (Rust saturates; x86-64 gives the "integer indefinite" value).
//! Also the cached reciprocal of a scale pin or param ([`ScaleCache`]),
//! which several components compute the same way.

const TWO_63: f64 = 9_223_372_036_854_775_808.0;

/// `(int32_t)x`: truncation; out of range or NaN gives `i32::MIN`.
pub fn f64_to_i32(x: f64) -> i32 {
    let t = x.trunc();
    if (-2_147_483_648.0..=2_147_483_647.0).contains(&t) {
        t as i32
    } else {
        i32::MIN
    }
}

/// `(int64_t)x`: truncation; out of range or NaN gives `i64::MIN`.
pub fn f64_to_i64(x: f64) -> i64 {
    let t = x.trunc();
    if (-TWO_63..TWO_63).contains(&t) {
        t as i64
    } else {
        i64::MIN
    }
}

/// `(uint32_t)x`: through a 64-bit conversion, keeping the low 32 bits.
pub fn f64_to_u32(x: f64) -> u32 {
    f64_to_i64(x) as u32
}

/// `(uint64_t)x`: below 2^63 (and NaN) through `int64_t`; from 2^63 up,
/// `(int64_t)(x - 2^63)` with the top bit flipped.
pub fn f64_to_u64(x: f64) -> u64 {
    if x >= TWO_63 {
        (f64_to_i64(x - TWO_63) as u64) ^ (1 << 63)
    } else {
        f64_to_i64(x) as u64
    }
}

/// The reciprocal of a `position-scale`-like value, recomputed only when
/// the value changes, as LinuxCNC's encoder, counter, stepgen, pwmgen and
/// sim_encoder do: on a change the new value is remembered *before* any
/// correction, a magnitude below 1e-20 is replaced by 1.0 (written back to
/// the pin or param), and the reciprocal is recomputed from the corrected
/// value.
///
/// Each component starts from its own "old" value and reciprocal, and
/// those are quirks to keep: a first value equal to the initial old one is
/// never examined, so (for instance) stepgen's exact 0.0 is never
/// corrected and its reciprocal stays 0.0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaleCache {
    /// The value last seen (as it was before any correction).
    pub old_scale: f64,
    /// `unit / scale` as last computed.
    pub recip: f64,
}

impl ScaleCache {
    /// A cache in a component's load-time state.
    pub const fn new(old_scale: f64, recip: f64) -> ScaleCache {
        ScaleCache { old_scale, recip }
    }

    /// Checks `scale` (corrected in place if it changed to a near-zero
    /// value) and returns `unit / scale`, recomputed only on a change.
    /// `unit` is 1.0 for a plain reciprocal; stepgen folds its fixed-point
    /// factor in, computing `(1 / 2^28) / scale` as LinuxCNC does.
    #[inline]
    pub fn check(&mut self, scale: &mut f64, unit: f64) -> f64 {
        if *scale != self.old_scale {
            self.old_scale = *scale;
            if *scale > -1e-20 && *scale < 1e-20 {
                *scale = 1.0;
            }
            self.recip = unit / *scale;
        }
        self.recip
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_results_match_x86_64() {
        assert_eq!(f64_to_i32(1.9), 1);
        assert_eq!(f64_to_i32(-1.9), -1);
        assert_eq!(f64_to_i32(3e9), i32::MIN);
        assert_eq!(f64_to_i32(f64::NAN), i32::MIN);
        assert_eq!(f64_to_i64(1e19), i64::MIN);
        assert_eq!(f64_to_u32(-1.5), 4_294_967_295);
        assert_eq!(f64_to_u32(5e9), 705_032_704);
        assert_eq!(f64_to_u32(f64::NAN), 0);
        assert_eq!(f64_to_u64(-1.0), u64::MAX);
        assert_eq!(f64_to_u64(f64::NAN), 1 << 63);
        assert_eq!(f64_to_u64(1e19), 10_000_000_000_000_000_000);
        assert_eq!(f64_to_u64(2e19), 0);
    }

    #[test]
    fn scale_cache_recomputes_on_change_and_corrects_tiny_scales() {
        let mut c = ScaleCache::new(1.0, 1.0);
        let mut s = 1.0;
        assert_eq!(c.check(&mut s, 1.0), 1.0);
        s = 4.0;
        assert_eq!(c.check(&mut s, 1.0), 0.25);
        // A tiny scale is remembered as given, then replaced by 1.0; the
        // next call sees 1.0 as a change and recomputes the same value.
        s = -1e-21;
        assert_eq!(c.check(&mut s, 1.0), 1.0);
        assert_eq!((s, c.old_scale), (1.0, -1e-21));
        assert_eq!(c.check(&mut s, 1.0), 1.0);
        assert_eq!(c.old_scale, 1.0);
        // The first value is only examined if it differs from the initial
        // old one.
        let mut c = ScaleCache::new(0.0, 0.0);
        let mut s = 0.0;
        assert_eq!(c.check(&mut s, 0.5), 0.0);
        assert_eq!(s, 0.0);
    }
}
