//! Reading the carousel position from its sensors, per encoding.

use super::config::{Config, Encoding};
use crate::bits::gray::gray2bin;

/// What one call reads from the sensors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Reading {
    /// The position the sensors show (0: none).
    pub position: i32,
    /// XOR of the sense bits (binary, gray, bcd only).
    pub parity: bool,
    /// The signal the slow alignment move stops on.
    pub align: bool,
}

/// Sense pin `i`, FALSE for a pin the instance does not have.
pub fn sense(bits: &[bool], i: i64) -> bool {
    usize::try_from(i)
        .ok()
        .and_then(|i| bits.get(i))
        .copied()
        .unwrap_or(false)
}

/// The sense bits as a binary number (pin i is bit i) and their parity.
fn binary(bits: &[bool]) -> (i32, bool) {
    bits.iter()
        .enumerate()
        .fold((0i32, false), |(n, p), (i, &b)| {
            (n.wrapping_add((b as i32) << i), p ^ b)
        })
}

/// Reads a gray, binary, bcd or single encoder (the absolute ones).
/// `current` is the position shown so far (single mode aligns on its
/// sensor).
pub fn absolute(c: &Config, bits: &[bool], strobe: bool, current: i32) -> Reading {
    match c.encoding {
        Encoding::Gray => {
            let (n, parity) = binary(bits);
            Reading {
                position: gray2bin(n as u32) as i32,
                parity,
                align: strobe,
            }
        }
        Encoding::Binary => {
            let (position, parity) = binary(bits);
            Reading {
                position,
                parity,
                align: strobe,
            }
        }
        Encoding::Bcd => {
            let mut position = 0i32;
            let mut parity = false;
            let mut scale = 1i32;
            for digit in bits.chunks(4) {
                let d = digit
                    .iter()
                    .enumerate()
                    .fold(0i32, |d, (i, &b)| d + ((b as i32) << i));
                parity ^= digit.iter().fold(false, |p, &b| p ^ b);
                position = position.wrapping_add(d.wrapping_mul(scale));
                scale = scale.wrapping_mul(10);
            }
            Reading {
                position,
                parity,
                align: strobe,
            }
        }
        Encoding::Single => {
            // The highest sensor that is on (sensor i is pocket i+1).
            let position = (0..bits.len())
                .rev()
                .find(|&i| bits[i])
                .map_or(0, |i| i as i32 + 1);
            Reading {
                position,
                parity: false,
                align: sense(bits, i64::from(current) - 1),
            }
        }
        Encoding::Index | Encoding::Edge | Encoding::Counts => {
            unreachable!("relative encodings are read by the state machine")
        }
    }
}

/// Reads a `counts` carousel: `c` counts past home, `scale` counts per
/// pocket, a pocket shown within `width/2` counts of its centre. The
/// arithmetic is LinuxCNC's, single precision included. `scale` 0
/// (which crashes LinuxCNC with a division by zero) shows no pocket.
pub fn counts(pockets: i32, c: i32, scale: i32, width: i32, current: i32) -> Reading {
    if scale == 0 {
        return Reading {
            position: current,
            ..Reading::default()
        };
    }
    let w = width / 2;
    let t = crate::cmath::f64_to_i32(f64::from((c as f32 + w as f32) / scale as f32).floor());
    let centre = t.wrapping_mul(scale);
    let position = if c >= centre.wrapping_sub(w) && c <= centre.wrapping_add(w) {
        let turns = f64::from(t as f32 / pockets as f32).floor();
        crate::cmath::f64_to_i32(f64::from(1i32.wrapping_add(t)) - f64::from(pockets) * turns)
    } else {
        current
    };
    let r = c.wrapping_rem(scale);
    Reading {
        position,
        parity: false,
        align: (-2..=2).contains(&r),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(encoding: Encoding, sense: usize) -> Config {
        Config {
            pockets: 8,
            encoding,
            bidirectional: true,
            sense,
            parity: 0,
        }
    }

    fn bits(n: u32, width: usize) -> Vec<bool> {
        (0..width).map(|i| n & (1 << i) != 0).collect()
    }

    #[test]
    fn gray_binary_and_bcd() {
        let g = cfg(Encoding::Gray, 4);
        // Gray code 0b0110 is 4.
        let r = absolute(&g, &bits(0b0110, 4), true, 0);
        assert_eq!((r.position, r.parity, r.align), (4, false, true));
        let b = cfg(Encoding::Binary, 4);
        let r = absolute(&b, &bits(0b0111, 4), false, 0);
        assert_eq!((r.position, r.parity, r.align), (7, true, false));
        let d = cfg(Encoding::Bcd, 6);
        // Digits 2 (bits 0-3) and 1 (bits 4-5): 12.
        let r = absolute(&d, &bits(0b01_0010, 6), true, 0);
        assert_eq!((r.position, r.parity), (12, false));
    }

    #[test]
    fn single_sensors() {
        let s = cfg(Encoding::Single, 8);
        let r = absolute(&s, &bits(0b0010_0100, 8), true, 3);
        assert_eq!(r.position, 6, "the highest sensor on");
        assert!(r.align, "aligns on the sensor of the current pocket (3)");
        assert_eq!(absolute(&s, &bits(0, 8), true, 0).position, 0);
        assert!(!absolute(&s, &bits(0xff, 8), true, 0).align, "no pocket 0");
    }

    #[test]
    fn counts_mode_windows_and_wraps() {
        // 100 counts per pocket, width 20: pocket shown within +-10.
        assert_eq!(counts(8, 0, 100, 20, 5).position, 1);
        assert_eq!(counts(8, 209, 100, 20, 5).position, 3);
        assert_eq!(
            counts(8, 250, 100, 20, 5).position,
            5,
            "between pockets: kept"
        );
        assert_eq!(counts(8, 800, 100, 20, 5).position, 1, "one turn on");
        assert_eq!(
            counts(8, -100, 100, 20, 5).position,
            8,
            "one back from home"
        );
        assert!(counts(8, 302, 100, 20, 5).align);
        assert!(!counts(8, 303, 100, 20, 5).align);
        assert_eq!(
            counts(8, 303, 0, 20, 5),
            Reading {
                position: 5,
                ..Reading::default()
            }
        );
    }
}
