//! Process data on the wire (hostmot2-more.md 2.7): records are packed
//! in table order from bit 0 of interface register 0 upward, one stream
//! per direction; numbers are scaled to the record's ParmMax.
//!
//! * unsigned, `len` bits: value = raw × scalemax / (2^len − 1);
//!   raw = clamp(value, minlim, maxlim) / scalemax × (2^len − 1).
//! * signed, `len` bits: the raw bits are the top `len` bits of a 32-bit
//!   fraction of full scale: value = (raw << (32 − len)) / (2^31 − 1) ×
//!   scalemax, and back.
//! * boolean: any bit set. Bit fields: one bit each.
//!
//! Both the driver and the simulated remotes use these, so a value goes
//! through the link and comes back as it left, to the resolution of the
//! field.

/// Reads `len` bits (at most 64) from bit `at` of `words`.
#[inline]
pub fn get_bits(words: &[u32], at: usize, len: usize) -> u64 {
    let mut v = 0u64;
    for i in 0..len.min(64) {
        let bit = at + i;
        let w = words.get(bit / 32).copied().unwrap_or(0);
        if w >> (bit % 32) & 1 != 0 {
            v |= 1 << i;
        }
    }
    v
}

/// Writes the low `len` bits (at most 64) of `v` at bit `at` of `words`.
#[inline]
pub fn put_bits(words: &mut [u32], at: usize, len: usize, v: u64) {
    for i in 0..len.min(64) {
        let bit = at + i;
        if let Some(w) = words.get_mut(bit / 32) {
            let mask = 1u32 << (bit % 32);
            if v >> i & 1 != 0 {
                *w |= mask;
            } else {
                *w &= !mask;
            }
        }
    }
}

/// The largest raw value of `len` bits (len 1..=32).
#[inline]
fn full(len: u8) -> f64 {
    ((1u64 << len.clamp(1, 32)) - 1) as f64
}

/// `value` clamped to `min..=max` (NaN as 0), or `None` when `scalemax`
/// cannot scale it (0 or not finite: the field is sent as 0).
#[inline]
fn limited(value: f64, scalemax: f64, min: f64, max: f64) -> Option<f64> {
    if scalemax == 0.0 || !scalemax.is_finite() {
        return None;
    }
    Some(if value.is_nan() {
        0.0
    } else {
        value.max(min).min(max)
    })
}

/// An unsigned field's value.
#[inline]
pub fn unsigned_value(raw: u64, len: u8, scalemax: f64) -> f64 {
    raw as f64 * scalemax / full(len)
}

/// An unsigned field's raw bits for `value`, clamped to `min..=max`.
#[inline]
pub fn unsigned_raw(value: f64, len: u8, scalemax: f64, min: f64, max: f64) -> u64 {
    let Some(v) = limited(value, scalemax, min, max) else {
        return 0;
    };
    (v / scalemax * full(len)).round().clamp(0.0, full(len)) as u64
}

/// A signed field's value.
#[inline]
pub fn signed_value(raw: u64, len: u8, scalemax: f64) -> f64 {
    let len = len.clamp(1, 32) as u32;
    let top = ((raw as u32) << (32 - len)) as i32;
    top as f64 / i32::MAX as f64 * scalemax
}

/// A signed field's raw bits for `value`, clamped to `min..=max`.
#[inline]
pub fn signed_raw(value: f64, len: u8, scalemax: f64, min: f64, max: f64) -> u64 {
    let len = len.clamp(1, 32) as u32;
    let Some(v) = limited(value, scalemax, min, max) else {
        return 0;
    };
    let x = (v / scalemax * i32::MAX as f64).clamp(i32::MIN as f64, i32::MAX as f64) as i32;
    let mask = if len == 32 {
        u32::MAX
    } else {
        (1u32 << len) - 1
    };
    ((x >> (32 - len)) as u32 & mask) as u64
}

/// Sign-extends the low `len` bits of `raw`.
#[inline]
pub fn sign_extend(raw: u64, len: u8) -> i64 {
    let len = len.clamp(1, 64) as u32;
    ((raw << (64 - len)) as i64) >> (64 - len)
}

/// An encoder counter of `len` bits followed across wraps.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Unwrap {
    last: Option<u64>,
    /// Counts accumulated since the start.
    pub total: i64,
}

impl Unwrap {
    /// Takes the counter's new raw value; returns the accumulated count.
    #[inline]
    pub fn update(&mut self, raw: u64, len: u8) -> i64 {
        let len = len.clamp(1, 32);
        let mask = (1u64 << len) - 1;
        let raw = raw & mask;
        if let Some(last) = self.last {
            self.total += sign_extend(raw.wrapping_sub(last) & mask, len);
        } else {
            self.total = sign_extend(raw, len);
        }
        self.last = Some(raw);
        self.total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_pack_across_words() {
        let mut w = [0u32; 3];
        put_bits(&mut w, 30, 4, 0b1011);
        assert_eq!(w, [0b11 << 30, 0b10, 0]);
        assert_eq!(get_bits(&w, 30, 4), 0b1011);
        put_bits(&mut w, 64, 32, 0xDEAD_BEEF);
        assert_eq!(w[2], 0xDEAD_BEEF);
        put_bits(&mut w, 90, 10, 0x3FF);
        assert_eq!(get_bits(&w, 64, 32), 0xFC00_0000 | 0xDEAD_BEEF);
    }

    #[test]
    fn numbers_survive_the_link() {
        for v in [0.0, 2.5, 7.1, 10.0] {
            let raw = unsigned_raw(v, 16, 10.0, 0.0, 10.0);
            assert!((unsigned_value(raw, 16, 10.0) - v).abs() < 1e-3, "{v}");
        }
        assert_eq!(unsigned_raw(12.0, 16, 10.0, 0.0, 10.0), 0xFFFF, "clamped");
        assert_eq!(unsigned_raw(-1.0, 8, 10.0, 0.0, 10.0), 0);
        for v in [-10.0, -3.3, 0.0, 4.75, 10.0] {
            let raw = signed_raw(v, 13, 10.0, -10.0, 10.0);
            assert!(raw < 1 << 13);
            assert!((signed_value(raw, 13, 10.0) - v).abs() < 3e-3, "{v}");
        }
        assert_eq!(signed_raw(f64::NAN, 16, 10.0, -10.0, 10.0), 0);
        assert_eq!(unsigned_raw(5.0, 16, 0.0, 0.0, 10.0), 0);
    }

    #[test]
    fn counters_unwrap() {
        let mut u = Unwrap::default();
        assert_eq!(u.update(250, 8), -6);
        assert_eq!(u.update(4, 8), 4);
        assert_eq!(u.update(200, 8), -56);
        assert_eq!(sign_extend(0x80, 8), -128);
    }
}
