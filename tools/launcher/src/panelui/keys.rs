//! The keycodes a Mesa 7I73 keypad (or `sim_matrix_kb`) reports, read
//! as LinuxCNC's panelui reads them from the sampler: `0xC0 | row*8 +
//! col` when a key goes down, `0x80 | ...` when it goes up, 0x40 for no
//! change and 0 with every key up. At most two keys count as down at
//! once (further presses are passed over); anything else is noise.

/// The key-down flags.
const KEYDOWN: u32 = 0xC0;
/// The key-up flag.
const KEYUP: u32 = 0x80;
/// "No change".
const NO_CHANGE: u32 = 0x40;
/// Rows and columns of the matrix.
const SIZE: u32 = 8;
/// Keys that may be down at once.
const ROLLOVER: u32 = 2;

/// A key going down or up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KeyEvent {
    /// Its row (0..7).
    pub row: usize,
    /// Its column (0..7).
    pub col: usize,
    /// Down (true) or up.
    pub pressed: bool,
}

/// Reads keycodes, counting the keys down.
#[derive(Debug, Clone, Default)]
pub struct KeyDecoder {
    down: u32,
}

impl KeyDecoder {
    /// The event a keycode reports, if any.
    pub fn decode(&mut self, raw: u32) -> Option<KeyEvent> {
        let code = raw & !KEYDOWN;
        let (row, col) = (code / SIZE, code % SIZE);
        if row >= SIZE || raw == NO_CHANGE || raw == 0 {
            return None;
        }
        let pressed = if raw & KEYDOWN == KEYDOWN {
            if self.down >= ROLLOVER {
                return None;
            }
            self.down += 1;
            true
        } else if raw & KEYUP == KEYUP {
            self.down = self.down.saturating_sub(1);
            false
        } else {
            return None;
        };
        Some(KeyEvent {
            row: row as usize,
            col: col as usize,
            pressed,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(row: usize, col: usize, pressed: bool) -> Option<KeyEvent> {
        Some(KeyEvent { row, col, pressed })
    }

    #[test]
    fn codes_give_row_column_and_direction() {
        let mut d = KeyDecoder::default();
        assert_eq!(d.decode(0), None);
        assert_eq!(d.decode(0x40), None);
        assert_eq!(d.decode(0xC0 | (6 * 8 + 2)), ev(6, 2, true));
        assert_eq!(d.decode(0x80 | (6 * 8 + 2)), ev(6, 2, false));
        assert_eq!(d.decode(0x05), None, "no flag: noise");
        assert_eq!(d.decode(0x1C0), None, "row 8 is beyond the matrix");
    }

    #[test]
    fn a_third_key_down_is_passed_over() {
        let mut d = KeyDecoder::default();
        assert!(d.decode(0xC0 | 1).is_some());
        assert!(d.decode(0xC0 | 2).is_some());
        assert_eq!(d.decode(0xC0 | 3), None);
        assert_eq!(d.decode(0x80 | 1), ev(0, 1, false));
        assert_eq!(d.decode(0xC0 | 3), ev(0, 3, true));
    }
}
