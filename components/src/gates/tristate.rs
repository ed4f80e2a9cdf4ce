//! `tristate_bit` and `tristate_float`: drive an I/O pin with `in` only
//! while `enable` is TRUE, like a tristate buffer; otherwise leave it to
//! whatever else drives the signal.

use hal_core::{PinValue, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Builds one tristate buffer of value type `T`.
fn tristate<T: PinValue>(inst: &mut Inst<'_, '_>, uses_fp: bool) -> Result<()> {
    let input = inst.pin_in::<T>("in")?;
    let out = inst.pin_io::<T>("out", T::from_bits(0))?;
    let enable = inst.pin_in::<bool>("enable")?;
    inst.funct("_", uses_fp, move |_| {
        if enable.get() {
            out.set(input.get())
        }
    })
}

/// The `tristate_bit` component.
pub struct TristateBit;
impl HalComp for TristateBit {
    const NAME: &'static str = "tristate_bit";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        tristate::<bool>(inst, false)
    }
}
halcomp_module!(pub TRISTATE_BIT, TristateBit, "place a bit on an I/O pin only when enabled");

/// The `tristate_float` component.
pub struct TristateFloat;
impl HalComp for TristateFloat {
    const NAME: &'static str = "tristate_float";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        tristate::<f64>(inst, true)
    }
}
halcomp_module!(pub TRISTATE_FLOAT, TristateFloat, "place a float on an I/O pin only when enabled");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn drives_only_while_enabled() {
        let mut h = TestHost::new("tristate");
        h.load(&TRISTATE_BIT, &[]).unwrap();
        h.load(&TRISTATE_FLOAT, &["names=tf"]).unwrap();
        h.check_pins(
            "tristate-bit.0",
            &["in bit in 0", "out bit io 0", "enable bit in 0"],
        );
        h.check_pins(
            "tf",
            &["in float in 0", "out float io 0", "enable bit in 0"],
        );
        h.thread(&["tristate-bit.0", "tf"]);
        h.set("tf.in", Float(2.5));
        h.set("tf.out", Float(-1.0));
        h.expect(&[("tristate-bit.0.in", Bit(true))], "tf.out", Float(-1.0));
        assert_eq!(h.get("tristate-bit.0.out"), Bit(false));
        h.expect(&[("tf.enable", Bit(true))], "tf.out", Float(2.5));
        h.expect(
            &[("tristate-bit.0.enable", Bit(true))],
            "tristate-bit.0.out",
            Bit(true),
        );
        // Disabled again: someone else may write the pin.
        h.set("tf.enable", Bit(false));
        h.expect(&[("tf.out", Float(7.0))], "tf.out", Float(7.0));
    }
}
