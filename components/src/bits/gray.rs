//! `bin2gray` and `gray2bin`: conversions between binary and Gray code
//! of u32 values.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The Gray code of `n`.
pub fn bin2gray(n: u32) -> u32 {
    n ^ (n >> 1)
}

/// The binary value of Gray code `g`.
pub fn gray2bin(g: u32) -> u32 {
    let mut n = g;
    let mut shift = g >> 1;
    while shift != 0 {
        n ^= shift;
        shift >>= 1;
    }
    n
}

/// Builds a u32 `in` to u32 `out` instance around `f`.
fn convert(inst: &mut Inst<'_, '_>, f: fn(u32) -> u32) -> Result<()> {
    let input = inst.pin_in::<u32>("in")?;
    let out = inst.pin_out::<u32>("out")?;
    inst.funct("_", false, move |_| out.set(f(input.get())))
}

/// The `bin2gray` component.
pub struct Bin2Gray;
impl HalComp for Bin2Gray {
    const NAME: &'static str = "bin2gray";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        convert(inst, bin2gray)
    }
}
halcomp_module!(pub BIN2GRAY, Bin2Gray, "convert a number to the gray-code representation");

/// The `gray2bin` component.
pub struct Gray2Bin;
impl HalComp for Gray2Bin {
    const NAME: &'static str = "gray2bin";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        convert(inst, gray2bin)
    }
}
halcomp_module!(pub GRAY2BIN, Gray2Bin, "convert a gray-code input to binary");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::U32;

    #[test]
    fn gray_sequence_and_round_trip() {
        let seq: Vec<u32> = (0..8).map(bin2gray).collect();
        assert_eq!(seq, [0, 1, 3, 2, 6, 7, 5, 4]);
        for n in (0..5000u32).chain([u32::MAX, u32::MAX - 1, 1 << 31, 0x5555_5555]) {
            assert_eq!(gray2bin(bin2gray(n)), n, "{n}");
            // Neighbours differ in exactly one bit.
            assert_eq!((bin2gray(n) ^ bin2gray(n.wrapping_add(1))).count_ones(), 1);
        }
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("gray");
        h.load(&BIN2GRAY, &[]).unwrap();
        h.load(&GRAY2BIN, &[]).unwrap();
        h.check_pins("bin2gray.0", &["in u32 in 0", "out u32 out 0"]);
        h.check_pins("gray2bin.0", &["in u32 in 0", "out u32 out 0"]);
        h.thread(&["bin2gray.0", "gray2bin.0"]);
        h.expect(&[("bin2gray.0.in", U32(7))], "bin2gray.0.out", U32(4));
        h.expect(&[("gray2bin.0.in", U32(4))], "gray2bin.0.out", U32(7));
    }
}
