//! `sim_matrix_kb`: turns 64 button pins (8 columns by 8 rows) into the
//! keycodes a Mesa 7I73 keypad reports, for testing `matrix_kb`: each
//! call reports the first button that changed (`0xC0 | row*8 + col` when
//! pressed, `0x80 | ...` when released), else 0 with no button down or
//! 0x40 (no change).

use hal_core::{In, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The key-down flag.
pub const KEYDOWN: u32 = 0xC0;
/// The key-up flag.
pub const KEYUP: u32 = 0x80;
/// The "no change" code.
pub const NO_KEY_CHANGE: u32 = 0x40;

/// The buttons seen last.
#[derive(Debug, Clone, Default)]
pub struct SimKeypad {
    last: [[bool; 8]; 8],
}

impl SimKeypad {
    /// One call; `button(r, c)` reads row `r` of column `c`.
    pub fn step(&mut self, button: impl Fn(usize, usize) -> bool) -> u32 {
        let mut all_up = true;
        for r in 0..8 {
            for c in 0..8 {
                let b = button(r, c);
                if b {
                    all_up = false;
                }
                if b != self.last[r][c] {
                    self.last[r][c] = b;
                    let num = (r * 8 + c) as u32;
                    return num | if b { KEYDOWN } else { KEYUP };
                }
            }
        }
        if all_up {
            0
        } else {
            NO_KEY_CHANGE
        }
    }
}

/// The `sim_matrix_kb` component.
pub struct SimMatrixKb;
impl HalComp for SimMatrixKb {
    const NAME: &'static str = "sim_matrix_kb";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let out = inst.pin_out::<u32>("out")?;
        let mut buttons: Vec<Vec<Pin<bool, In>>> = Vec::with_capacity(8);
        for c in 0..8 {
            buttons.push(
                (0..8)
                    .map(|r| inst.pin_in(&format!("button.c{c:02}.r{r:02}")))
                    .collect::<Result<_>>()?,
            );
        }
        let mut pad = SimKeypad::default();
        inst.funct("_", true, move |_| {
            out.set(pad.step(|r, c| buttons[c][r].get()))
        })
    }
}
halcomp_module!(pub MODULE, SimMatrixKb, "convert HAL pin inputs to keycodes");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    #[test]
    fn reports_one_change_per_call() {
        let mut p = SimKeypad::default();
        assert_eq!(p.step(|_, _| false), 0);
        let two = |r: usize, c: usize| (r, c) == (1, 2) || (r, c) == (3, 0);
        assert_eq!(p.step(two), KEYDOWN | 10);
        assert_eq!(p.step(two), KEYDOWN | 24);
        assert_eq!(p.step(two), NO_KEY_CHANGE);
        assert_eq!(p.step(|_, _| false), KEYUP | 10);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("sim-matrix-kb");
        h.load(&MODULE, &[]).unwrap();
        let mut want = vec!["out u32 out 0".to_string()];
        for c in 0..8 {
            for r in 0..8 {
                want.push(format!("button.c{c:02}.r{r:02} bit in 0"));
            }
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("sim-matrix-kb.0", &want);
        h.thread(&["sim-matrix-kb.0"]);
        h.set("sim-matrix-kb.0.button.c03.r01", Bit(true));
        h.run(1);
        h.expect(&[], "sim-matrix-kb.0.out", U32(NO_KEY_CHANGE));
    }
}
