//! `lut5`: any logic function of five inputs, given as a 32-bit truth
//! table in the `function` param: the output is bit `n` of `function`,
//! where `n` has bit k set when input `in-k` is TRUE.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The output for truth table `function` and the five inputs.
pub fn lut5(function: u32, inputs: [bool; 5]) -> bool {
    let n = inputs
        .iter()
        .enumerate()
        .fold(0u32, |n, (k, &b)| n | ((b as u32) << k));
    function & (1 << n) != 0
}

/// The `lut5` component.
pub struct Lut5;
impl HalComp for Lut5 {
    const NAME: &'static str = "lut5";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let ins = (0..5)
            .map(|k| inst.pin_in::<bool>(&format!("in-{k}")))
            .collect::<Result<Vec<_>>>()?;
        let out = inst.pin_out::<bool>("out")?;
        let function = inst.param_rw::<u32>("function", 0)?;
        inst.funct("_", false, move |_| {
            let v = std::array::from_fn(|k| ins[k].get());
            out.set(lut5(function.get(), v))
        })
    }
}
halcomp_module!(pub MODULE, Lut5, "arbitrary 5-input logic function based on a look-up table");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    fn inputs(n: u32) -> [bool; 5] {
        std::array::from_fn(|k| n & (1 << k) != 0)
    }

    #[test]
    fn documented_functions() {
        for n in 0..32 {
            let i = inputs(n);
            assert_eq!(lut5(0x8000_0000, i), n == 31, "5-input and, {n}");
            assert_eq!(lut5(0xffff_fffe, i), n != 0, "5-input or, {n}");
            assert_eq!(lut5(0xe, i), n == 1 || n == 2 || n == 3, "2-input or, {n}");
            assert_eq!(lut5(0x6, i), n == 1 || n == 2, "2-input xor, {n}");
            assert!(!lut5(0, i));
        }
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("lut5");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "lut5.0",
            &[
                "in-0 bit in 0",
                "in-1 bit in 0",
                "in-2 bit in 0",
                "in-3 bit in 0",
                "in-4 bit in 0",
                "out bit out 0",
            ],
        );
        h.check_params("lut5.0", &["function u32 rw 0"]);
        h.thread(&["lut5.0"]);
        h.setp("lut5.0.function", U32(0x6));
        h.expect(&[("lut5.0.in-1", Bit(true))], "lut5.0.out", Bit(true));
        h.expect(&[("lut5.0.in-0", Bit(true))], "lut5.0.out", Bit(false));
    }
}
