//! `bitmerge`: packs `personality` bit inputs (`in-00` is the least
//! significant) into a u32; the inverse of bitslice.

use hal_core::{In, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most inputs.
pub const MAX_BITS: usize = 32;

/// The u32 whose bit i is `bits[i]`.
pub fn merge(bits: impl Iterator<Item = bool>) -> u32 {
    bits.enumerate().fold(0, |v, (i, b)| v | ((b as u32) << i))
}

/// The `bitmerge` component.
pub struct Bitmerge;
impl HalComp for Bitmerge {
    const NAME: &'static str = "bitmerge";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let n = inst.array_len(MAX_BITS, inst.personality)?;
        let out = inst.pin_out::<u32>("out")?;
        let ins: Vec<Pin<bool, In>> = (0..n)
            .map(|i| inst.pin_in(&format!("in-{i:02}")))
            .collect::<Result<_>>()?;
        inst.funct("_", true, move |_| out.set(merge(ins.iter().map(Pin::get))))
    }
}
halcomp_module!(pub MODULE, Bitmerge, "converts individual bits into an unsigned-32");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    #[test]
    fn packs_lsb_first() {
        assert_eq!(merge([true, false, true].into_iter()), 5);
        assert_eq!(merge(std::iter::repeat_n(true, 32)), u32::MAX);
        assert_eq!(merge(std::iter::empty()), 0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("bitmerge");
        h.load(&MODULE, &["personality=3"]).unwrap();
        h.check_pins(
            "bitmerge.0",
            &[
                "out u32 out 0",
                "in-00 bit in 0",
                "in-01 bit in 0",
                "in-02 bit in 0",
            ],
        );
        h.check_load_fails(&MODULE, &["names=b", "personality=33"]);
        h.thread(&["bitmerge.0"]);
        h.expect(&[("bitmerge.0.in-02", Bit(true))], "bitmerge.0.out", U32(4));
    }
}
