//! bldc's commutation tables.
//!
//! A *phase code* names the excitation: octal digit 1 (bits 040, 020,
//! 010) is the high-side (source) driver of phase A, B, C, digit 0 (004,
//! 002, 001) the low-side (sink) driver. So 024 drives current from B to A.

/// The six excitations in the order the man page's pattern table lists
/// them: B-A, C-A, C-B, A-B, A-C, B-C (source - sink).
pub const EXCITATIONS: [u8; 6] = [0o24, 0o14, 0o12, 0o42, 0o41, 0o21];

/// The forward sequence of excitations, one every sixth of an electrical
/// turn starting at B-C, with the first two repeated at the end.
pub const PHASES: [u8; 8] = [0o21, 0o24, 0o14, 0o12, 0o42, 0o41, 0o21, 0o24];

/// The rotor angle (electrical turns) of each entry of [`PHASES`].
pub const ANGLES: [f64; 8] = [
    0.0 / 36.0,
    6.0 / 36.0,
    12.0 / 36.0,
    18.0 / 36.0,
    24.0 / 36.0,
    30.0 / 36.0,
    1.0, // 36/36
    42.0 / 36.0,
];

/// The Fanuc "red cap" 4-bit Gray sequence (C1 is bit 0), one code per
/// sixteenth of an electrical turn, back to 0 at the end.
pub const GRAY_CODES: [u8; 17] = [
    0o0, 0o1, 0o3, 0o2, 0o6, 0o7, 0o5, 0o4, 0o14, 0o15, 0o17, 0o16, 0o12, 0o13, 0o11, 0o10, 0o0,
];

/// The angle of each entry of [`GRAY_CODES`]: i/16.
pub const GRAY_ANGLES: [f64; 17] = [
    0.0, 0.0625, 0.125, 0.1875, 0.25, 0.3125, 0.375, 0.4375, 0.5, 0.5625, 0.625, 0.6875, 0.75,
    0.8125, 0.875, 0.9375, 1.0,
];

/// Number of Hall patterns.
pub const PATTERNS: usize = 48;

/// The man page's Hall pattern table: for each pattern number, the Hall
/// state (H1 H2 H3, H1 the most significant bit) seen during each of the
/// [`EXCITATIONS`] in order.
const HALL_TABLE: [[u8; 6]; PATTERNS] = [
    [0b000, 0b001, 0b011, 0b111, 0b110, 0b100],
    [0b001, 0b000, 0b010, 0b110, 0b111, 0b101],
    [0b000, 0b010, 0b011, 0b111, 0b101, 0b100],
    [0b001, 0b011, 0b010, 0b110, 0b100, 0b101],
    [0b010, 0b011, 0b001, 0b101, 0b100, 0b110],
    [0b011, 0b010, 0b000, 0b100, 0b101, 0b111],
    [0b010, 0b000, 0b001, 0b101, 0b111, 0b110],
    [0b011, 0b001, 0b000, 0b100, 0b110, 0b111],
    [0b000, 0b001, 0b101, 0b111, 0b110, 0b010],
    [0b001, 0b000, 0b100, 0b110, 0b111, 0b011],
    [0b000, 0b010, 0b110, 0b111, 0b101, 0b001],
    [0b001, 0b011, 0b111, 0b110, 0b100, 0b000],
    [0b010, 0b011, 0b111, 0b101, 0b100, 0b000],
    [0b011, 0b010, 0b110, 0b100, 0b101, 0b001],
    [0b010, 0b000, 0b100, 0b101, 0b111, 0b011],
    [0b011, 0b001, 0b101, 0b100, 0b110, 0b010],
    [0b000, 0b100, 0b101, 0b111, 0b011, 0b010],
    [0b001, 0b101, 0b100, 0b110, 0b010, 0b011],
    [0b000, 0b100, 0b110, 0b111, 0b011, 0b001],
    [0b001, 0b101, 0b111, 0b110, 0b010, 0b000],
    [0b010, 0b110, 0b111, 0b101, 0b001, 0b000],
    [0b011, 0b111, 0b110, 0b100, 0b000, 0b001],
    [0b010, 0b110, 0b100, 0b101, 0b001, 0b011],
    [0b011, 0b111, 0b101, 0b100, 0b000, 0b010],
    [0b100, 0b101, 0b111, 0b011, 0b010, 0b000],
    [0b101, 0b100, 0b110, 0b010, 0b011, 0b001],
    [0b100, 0b110, 0b111, 0b011, 0b001, 0b000],
    [0b101, 0b111, 0b110, 0b010, 0b000, 0b001],
    [0b110, 0b111, 0b101, 0b001, 0b000, 0b010],
    [0b111, 0b110, 0b100, 0b000, 0b001, 0b011],
    [0b110, 0b100, 0b101, 0b001, 0b011, 0b010],
    [0b111, 0b101, 0b100, 0b000, 0b010, 0b011],
    [0b100, 0b101, 0b001, 0b011, 0b010, 0b110],
    [0b101, 0b100, 0b000, 0b010, 0b011, 0b111],
    [0b100, 0b110, 0b010, 0b011, 0b001, 0b101],
    [0b101, 0b111, 0b011, 0b010, 0b000, 0b100],
    [0b110, 0b111, 0b011, 0b001, 0b000, 0b100],
    [0b111, 0b110, 0b010, 0b000, 0b001, 0b101],
    [0b110, 0b100, 0b000, 0b001, 0b011, 0b111],
    [0b111, 0b101, 0b001, 0b000, 0b010, 0b110],
    [0b100, 0b000, 0b001, 0b011, 0b111, 0b110],
    [0b101, 0b001, 0b000, 0b010, 0b110, 0b111],
    [0b100, 0b000, 0b010, 0b011, 0b111, 0b101],
    [0b101, 0b001, 0b011, 0b010, 0b110, 0b100],
    [0b110, 0b010, 0b011, 0b001, 0b101, 0b100],
    [0b111, 0b011, 0b010, 0b000, 0b100, 0b101],
    [0b110, 0b010, 0b000, 0b001, 0b101, 0b111],
    [0b111, 0b011, 0b001, 0b000, 0b100, 0b110],
];

/// The excitation for forward rotation at each Hall state, per pattern:
/// entry `pattern * 8 + hall` (0 for the two Hall states a pattern never
/// shows).
pub const COMMUTATION: [u8; PATTERNS * 8] = commutation();

const fn commutation() -> [u8; PATTERNS * 8] {
    let mut t = [0u8; PATTERNS * 8];
    let mut p = 0;
    while p < PATTERNS {
        let mut e = 0;
        while e < 6 {
            t[p * 8 + HALL_TABLE[p][e] as usize] = EXCITATIONS[e];
            e += 1;
        }
        p += 1;
    }
    t
}

/// Where `code` first appears in `table` from `start` on, or
/// `table.len()` (one past the end) when it does not.
pub fn find(table: &[u8], start: usize, code: u8) -> usize {
    (start..table.len())
        .find(|&i| table[i] == code)
        .unwrap_or(table.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commutation_matches_known_patterns() {
        assert_eq!(
            COMMUTATION[..8],
            [0o24, 0o14, 0o00, 0o12, 0o21, 0o00, 0o41, 0o42]
        );
        assert_eq!(
            COMMUTATION[25 * 8..26 * 8],
            [0o00, 0o21, 0o42, 0o41, 0o14, 0o24, 0o12, 0o00]
        );
        assert_eq!(
            COMMUTATION[47 * 8..],
            [0o42, 0o12, 0o00, 0o14, 0o41, 0o00, 0o21, 0o24]
        );
    }

    #[test]
    fn every_pattern_uses_six_states_and_all_excitations() {
        for p in 0..PATTERNS {
            let row = &COMMUTATION[p * 8..p * 8 + 8];
            assert_eq!(row.iter().filter(|&&c| c == 0).count(), 2, "{p}");
            for e in EXCITATIONS {
                assert_eq!(row.iter().filter(|&&c| c == e).count(), 1, "{p}");
            }
        }
    }

    #[test]
    fn gray_codes_step_one_bit() {
        for i in 0..16 {
            assert_eq!((GRAY_CODES[i] ^ GRAY_CODES[i + 1]).count_ones(), 1);
        }
        assert_eq!(find(&GRAY_CODES, 0, 0o10), 15);
        assert_eq!(find(&PHASES, 1, 0o21), 6);
        assert_eq!(find(&PHASES, 0, 0), 8);
    }
}
