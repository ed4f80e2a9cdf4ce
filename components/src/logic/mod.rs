//! Logic gates: and2, or2, xor2, not.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

fn gate2(inst: &mut Inst<'_, '_>, op: fn(bool, bool) -> bool) -> Result<()> {
    let in0 = inst.pin_in::<bool>("in0")?;
    let in1 = inst.pin_in::<bool>("in1")?;
    let out = inst.pin_out::<bool>("out")?;
    inst.funct("_", false, move |_| out.set(op(in0.get(), in1.get())))
}

/// `and2`: out = in0 AND in1.
pub struct And2;
impl HalComp for And2 {
    const NAME: &'static str = "and2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        gate2(inst, |a, b| a && b)
    }
}
halcomp_module!(pub AND2, And2, "two-input AND gate");

/// `or2`: out = in0 OR in1.
pub struct Or2;
impl HalComp for Or2 {
    const NAME: &'static str = "or2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        gate2(inst, |a, b| a || b)
    }
}
halcomp_module!(pub OR2, Or2, "two-input OR gate");

/// `xor2`: out = in0 XOR in1.
pub struct Xor2;
impl HalComp for Xor2 {
    const NAME: &'static str = "xor2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        gate2(inst, |a, b| a != b)
    }
}
halcomp_module!(pub XOR2, Xor2, "two-input XOR gate");

/// `not`: out = NOT in (FALSE until the function first runs).
pub struct Not;
impl HalComp for Not {
    const NAME: &'static str = "not";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let out = inst.pin_out::<bool>("out")?;
        inst.funct("_", false, move |_| out.set(!input.get()))
    }
}
halcomp_module!(pub NOT, Not, "inverter");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&AND2, &OR2, &XOR2, &NOT]
}
