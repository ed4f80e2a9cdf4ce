//! `maj3`: TRUE when at least two of three inputs are TRUE (inverted
//! when the `invert` param is set).

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The majority of three inputs, inverted if `invert`.
pub fn maj3(a: bool, b: bool, c: bool, invert: bool) -> bool {
    let n = a as u8 + b as u8 + c as u8;
    (n >= 2) != invert
}

/// The `maj3` component.
pub struct Maj3;
impl HalComp for Maj3 {
    const NAME: &'static str = "maj3";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in1 = inst.pin_in::<bool>("in1")?;
        let in2 = inst.pin_in::<bool>("in2")?;
        let in3 = inst.pin_in::<bool>("in3")?;
        let out = inst.pin_out::<bool>("out")?;
        let invert = inst.param_rw::<bool>("invert", false)?;
        inst.funct("_", false, move |_| {
            out.set(maj3(in1.get(), in2.get(), in3.get(), invert.get()))
        })
    }
}
halcomp_module!(pub MODULE, Maj3, "compute the majority of 3 inputs");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Bit;

    #[test]
    fn truth_table() {
        for n in 0u8..8 {
            let (a, b, c) = (n & 1 != 0, n & 2 != 0, n & 4 != 0);
            let want = n.count_ones() >= 2;
            assert_eq!(maj3(a, b, c, false), want, "{n}");
            assert_eq!(maj3(a, b, c, true), !want, "{n}");
        }
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("maj3");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "maj3.0",
            &[
                "in1 bit in 0",
                "in2 bit in 0",
                "in3 bit in 0",
                "out bit out 0",
            ],
        );
        h.check_params("maj3.0", &["invert bit rw 0"]);
        h.thread(&["maj3.0"]);
        h.expect(
            &[("maj3.0.in1", Bit(true)), ("maj3.0.in3", Bit(true))],
            "maj3.0.out",
            Bit(true),
        );
        h.setp("maj3.0.invert", Bit(true));
        h.expect(&[], "maj3.0.out", Bit(false));
    }
}
