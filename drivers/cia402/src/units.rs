//! Conversions between user units and drive counts.

/// `x` rounded to the nearest count, saturated into the i32 range
/// (NaN is 0): what a 32-bit position or velocity object can hold.
#[inline]
pub fn counts(x: f64) -> i32 {
    if x.is_nan() {
        0
    } else {
        x.round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    }
}

/// A scale to divide by: LinuxCNC's rule (as `canonical::usable_scale`),
/// a value within 1e-20 of 0, or NaN, counts as 1.0.
#[inline]
pub fn usable_scale(scale: f64) -> f64 {
    if scale.abs() < 1e-20 || scale.is_nan() {
        1.0
    } else {
        scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_and_limits() {
        assert_eq!(counts(2.5), 3);
        assert_eq!(counts(-2.4), -2);
        assert_eq!(counts(f64::NAN), 0);
        assert_eq!(counts(1e20), i32::MAX);
        assert_eq!(counts(-1e20), i32::MIN);
        assert_eq!(usable_scale(0.0), 1.0);
        assert_eq!(usable_scale(f64::NAN), 1.0);
        assert_eq!(usable_scale(-4.0), -4.0);
    }
}
