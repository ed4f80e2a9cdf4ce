//! C arithmetic as LinuxCNC's components get it from gcc on x86-64, where
//! it differs from Rust's: float-to-integer conversions of values out of
//! range (Rust saturates; x86-64 gives the "integer indefinite" value).

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
}
