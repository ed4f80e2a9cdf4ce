//! `demux`: sets one of `personality` output bits (32 when not given),
//! chosen by `sel-u32` plus the binary number on `sel-bit-00..04`; with
//! the `bargraph` param, every output below the chosen one instead.

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most outputs.
pub const MAX_OUTPUTS: usize = 32;

/// The selected output for `sel_u32` and the select bits (bit k is
/// `sel-bit-0k`), as LinuxCNC computes it: an unsigned sum taken as a
/// signed int, limited to the last output (a sum past 2^31 is negative
/// and selects nothing).
pub fn selected(sel_u32: u32, bits: [bool; 5], outputs: usize) -> i32 {
    let b = bits
        .iter()
        .enumerate()
        .fold(0u32, |n, (k, &b)| n.wrapping_add((b as u32) << k));
    let sel = sel_u32.wrapping_add(b) as i32;
    if sel >= outputs as i32 {
        outputs as i32 - 1
    } else {
        sel
    }
}

/// Output `i` for selection `sel`.
pub fn output(i: usize, sel: i32, bargraph: bool) -> bool {
    if bargraph {
        sel > i as i32
    } else {
        sel == i as i32
    }
}

/// The `demux` component.
pub struct Demux;
impl HalComp for Demux {
    const NAME: &'static str = "demux";
    const PERSONALITY: bool = true;
    const DEFAULT_PERSONALITY: i64 = MAX_OUTPUTS as i64;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let n = inst.array_len(MAX_OUTPUTS, inst.personality)?;
        let sel_bits: Vec<Pin<bool, In>> = (0..5)
            .map(|k| inst.pin_in(&format!("sel-bit-{k:02}")))
            .collect::<Result<_>>()?;
        let sel_u32 = inst.pin_in::<u32>("sel-u32")?;
        let outs: Vec<Pin<bool, Out>> = (0..n)
            .map(|i| inst.pin_out(&format!("out-{i:02}")))
            .collect::<Result<_>>()?;
        let bargraph = inst.param_rw::<bool>("bargraph", false)?;
        inst.funct("_", true, move |_| {
            let sel = selected(sel_u32.get(), std::array::from_fn(|k| sel_bits[k].get()), n);
            let bar = bargraph.get();
            for (i, o) in outs.iter().enumerate() {
                o.set(output(i, sel, bar));
            }
        })
    }
}
halcomp_module!(pub MODULE, Demux, "select one of several output pins by integer and/or individual bits");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    #[test]
    fn selection_adds_bits_to_the_integer_and_is_capped() {
        assert_eq!(selected(0, [true, false, true, false, false], 32), 5);
        assert_eq!(selected(3, [true, false, false, false, false], 32), 4);
        assert_eq!(selected(40, [false; 5], 8), 7);
        assert_eq!(selected(u32::MAX, [false; 5], 8), -1, "wraps negative");
        assert!(output(3, 3, false) && !output(2, 3, false));
        assert!(output(2, 3, true) && !output(3, 3, true));
    }

    #[test]
    fn pins_personality_and_a_run() {
        let mut h = TestHost::new("demux");
        h.load(&MODULE, &["count=2", "personality=4"]).unwrap();
        h.check_pins(
            "demux.0",
            &[
                "sel-bit-00 bit in 0",
                "sel-bit-01 bit in 0",
                "sel-bit-02 bit in 0",
                "sel-bit-03 bit in 0",
                "sel-bit-04 bit in 0",
                "sel-u32 u32 in 0",
                "out-00 bit out 0",
                "out-01 bit out 0",
                "out-02 bit out 0",
                "out-03 bit out 0",
            ],
        );
        h.check_params("demux.0", &["bargraph bit rw 0"]);
        // The second instance takes the default personality: 32 outputs.
        assert_eq!(h.items("demux.1.out-31").len(), 1);
        h.check_load_fails(&MODULE, &["names=d", "personality=33"]);
        h.thread(&["demux.0"]);
        h.expect(&[("demux.0.sel-u32", U32(2))], "demux.0.out-02", Bit(true));
        h.setp("demux.0.bargraph", Bit(true));
        h.expect(&[], "demux.0.out-01", Bit(true));
        assert_eq!(h.get("demux.0.out-02"), Bit(false));
    }
}
