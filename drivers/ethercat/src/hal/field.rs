//! Bit fields of the process image and the codings of lcec's
//! `halType`s: how a pin's value becomes the bits of its entry and back.

use crate::lcec::conf::HalType;
use crate::lcec::pins::{Coding, PinType};

/// Where a pin's bits are in its slave's inputs or outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Field {
    /// First bit.
    pub bit: usize,
    /// Bits (1..=64).
    pub bits: u8,
}

impl Field {
    /// The field's bits, zero-extended (0 where the image is short).
    ///
    /// Runs for every input entry every period, so the common shapes
    /// are quick: a field inside one byte (a digital input, a byte) is
    /// one load, and the rest take the 8 bytes from its first at once
    /// where the image has them (a byte at a time near its end), plus
    /// a ninth for a 64-bit field that does not start on a byte.
    #[inline]
    pub(crate) fn read(self, img: &[u8]) -> u64 {
        let bits = u32::from(self.bits.min(64));
        let (first, shift) = (self.bit / 8, (self.bit % 8) as u32);
        let mask = if bits >= 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        if shift + bits <= 8 {
            return img
                .get(first)
                .map_or(0, |&b| (u64::from(b) >> shift) & mask);
        }
        let low = match img.get(first..first.saturating_add(8)) {
            Some(b) => <[u8; 8]>::try_from(b).map_or(0, u64::from_le_bytes),
            // Fewer than 8 bytes from `first` to the end: they fit.
            None => img
                .get(first..)
                .unwrap_or(&[])
                .iter()
                .rev()
                .fold(0u64, |v, &b| v << 8 | u64::from(b)),
        };
        let mut v = low >> shift;
        if shift + bits > 64 {
            if let Some(&b) = img.get(first.saturating_add(8)) {
                v |= u64::from(b) << (64 - shift);
            }
        }
        v & mask
    }

    /// Writes the low bits of `v` into the field (nothing past the
    /// image). As [`Field::read`], a field inside one byte and one with
    /// 8 bytes of image from its first are written without a byte loop.
    #[inline]
    pub(crate) fn write(self, img: &mut [u8], v: u64) {
        let bits = u32::from(self.bits.min(64));
        let (first, shift) = (self.bit / 8, (self.bit % 8) as u32);
        let mask = if bits >= 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        if shift + bits <= 8 {
            if let Some(b) = img.get_mut(first) {
                let m = (mask << shift) as u8;
                *b = (*b & !m) | ((v << shift) as u8 & m);
            }
            return;
        }
        let (mask, v) = (u128::from(mask) << shift, u128::from(v & mask) << shift);
        if let Some(word) = img.get_mut(first..first.saturating_add(8)) {
            if let Ok(word) = <&mut [u8; 8]>::try_from(word) {
                let (m, low) = (mask as u64, v as u64);
                *word = ((u64::from_le_bytes(*word) & !m) | low).to_le_bytes();
            }
            if shift + bits > 64 {
                if let Some(b) = img.get_mut(first.saturating_add(8)) {
                    let m = (mask >> 64) as u8;
                    *b = (*b & !m) | ((v >> 64) as u8 & m);
                }
            }
            return;
        }
        for i in 0..(shift + bits).div_ceil(8) as usize {
            if let Some(b) = img.get_mut(first + i) {
                let m = (mask >> (8 * i)) as u8;
                *b = (*b & !m) | ((v >> (8 * i)) as u8 & m);
            }
        }
    }

    /// The field's bits, sign-extended.
    #[inline]
    pub(crate) fn read_signed(self, img: &[u8]) -> i64 {
        let bits = u32::from(self.bits.clamp(1, 64));
        let shift = 64 - bits;
        ((self.read(img) << shift) as i64) >> shift
    }
}

/// The coding a catalogue pin of type `ty` has: its HAL type, unscaled.
pub(crate) fn plain(ty: PinType) -> Coding {
    Coding {
        hal_type: match ty {
            PinType::Bit => HalType::Bit,
            PinType::S32 => HalType::S32,
            PinType::U32 => HalType::U32,
            PinType::Float => HalType::Float,
        },
        scale: 1.0,
        offset: 0.0,
    }
}

/// The value of the bits `raw` of a `bits`-wide entry: `raw × scale +
/// offset` for the float types, as lcec's generic slave computes it.
#[inline]
pub(crate) fn decode(c: &Coding, raw: u64, bits: u8) -> f64 {
    let shift = 64 - u32::from(bits.clamp(1, 64));
    let signed = ((raw << shift) as i64) >> shift;
    match c.hal_type {
        HalType::Bit => f64::from(u8::from(raw != 0)),
        HalType::S32 => signed.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as f64,
        HalType::U32 | HalType::Complex => raw.min(u64::from(u32::MAX)) as f64,
        HalType::Float => signed as f64 * c.scale + c.offset,
        HalType::FloatUnsigned => raw as f64 * c.scale + c.offset,
        HalType::FloatIeee => f64::from(f32::from_bits(raw as u32)) * c.scale + c.offset,
        HalType::FloatDoubleIeee => f64::from_bits(raw) * c.scale + c.offset,
    }
}

/// The bits a `bits`-wide entry gets for `value`: the float types send
/// `value × scale + offset`, rounded and saturated to the entry's range.
#[inline]
pub(crate) fn encode(c: &Coding, value: f64, bits: u8) -> u64 {
    let bits = bits.clamp(1, 64);
    let (lo, hi) = if bits == 64 {
        (i64::MIN as f64, i64::MAX as f64)
    } else {
        (
            -((1u64 << (bits - 1)) as f64),
            ((1u64 << (bits - 1)) - 1) as f64,
        )
    };
    let umax = if bits == 64 {
        u64::MAX as f64
    } else {
        ((1u64 << bits) - 1) as f64
    };
    let scaled = value * c.scale + c.offset;
    match c.hal_type {
        HalType::Bit => u64::from(value != 0.0),
        HalType::S32 => value.round().clamp(lo, hi) as i64 as u64,
        HalType::U32 | HalType::Complex => value.round().clamp(0.0, umax) as u64,
        HalType::Float => scaled.round().clamp(lo, hi) as i64 as u64,
        HalType::FloatUnsigned => scaled.round().clamp(0.0, umax) as u64,
        HalType::FloatIeee => u64::from((scaled as f32).to_bits()),
        HalType::FloatDoubleIeee => scaled.to_bits(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_round_trip_at_any_bit() {
        let mut img = [0u8; 4];
        let f = Field { bit: 3, bits: 12 };
        f.write(&mut img, 0xABC);
        assert_eq!(f.read(&img), 0xABC);
        assert_eq!(img, [0xE0, 0x55, 0, 0]);
        Field { bit: 3, bits: 12 }.write(&mut img, 0xFFF);
        assert_eq!(f.read_signed(&img), -1);
        assert_eq!(
            Field { bit: 30, bits: 8 }.read(&img),
            0,
            "past the end reads 0"
        );
    }

    /// The fields read and write exactly the bits a bit-at-a-time walk
    /// does, at every offset and width, the image's end included.
    #[test]
    fn byte_wise_access_matches_the_bits() {
        let bit_of =
            |img: &[u8], at: usize| img.get(at / 8).is_some_and(|b| b >> (at % 8) & 1 != 0);
        let pattern: Vec<u8> = (0..12u32).map(|i| (i * 0x9D + 0x35) as u8).collect();
        for bit in 0..40 {
            for bits in 1..=64u8 {
                let f = Field { bit, bits };
                let mut want = 0u64;
                for k in 0..usize::from(bits) {
                    if bit_of(&pattern, bit + k) {
                        want |= 1 << k;
                    }
                }
                assert_eq!(f.read(&pattern), want, "read {f:?}");
                let mut img = pattern.clone();
                let v = 0xA5C3_0F96_5AE1_7B2Du64;
                f.write(&mut img, v);
                for at in 0..img.len() * 8 {
                    let inside = at >= bit && at < bit + usize::from(bits);
                    let expect = if inside {
                        v >> (at - bit) & 1 != 0
                    } else {
                        bit_of(&pattern, at)
                    };
                    assert_eq!(bit_of(&img, at), expect, "write {f:?} bit {at}");
                }
            }
        }
    }

    #[test]
    fn codings_scale_sign_and_saturate() {
        let c = |hal_type, scale, offset| Coding {
            hal_type,
            scale,
            offset,
        };
        let f = c(HalType::Float, 0.5, 1.0);
        assert_eq!(decode(&f, 0xFFFE, 16), 0.0);
        assert_eq!(encode(&f, 10.0, 16), 6);
        assert_eq!(
            encode(&c(HalType::S32, 1.0, 0.0), -70000.0, 16) as u16,
            0x8000
        );
        assert_eq!(decode(&c(HalType::S32, 1.0, 0.0), 0x8000, 16), -32768.0);
        let ieee = c(HalType::FloatIeee, 1.0, 0.0);
        assert_eq!(decode(&ieee, encode(&ieee, 2.5, 32), 32), 2.5);
        assert_eq!(encode(&c(HalType::U32, 1.0, 0.0), 300.0, 8), 255);
    }
}
