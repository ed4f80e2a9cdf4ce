//! Arithmetic on floats: mult2, sum2.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// `mult2`: out = in0 * in1.
pub struct Mult2;
impl HalComp for Mult2 {
    const NAME: &'static str = "mult2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let out = inst.pin_out::<f64>("out")?;
        inst.funct("_", true, move |_| out.set(in0.get() * in1.get()))
    }
}
halcomp_module!(pub MULT2, Mult2, "product of two inputs");

/// `sum2`: out = (in0 * gain0 + in1 * gain1) + offset.
pub struct Sum2;
impl HalComp for Sum2 {
    const NAME: &'static str = "sum2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<f64>("in0")?;
        let in1 = inst.pin_in::<f64>("in1")?;
        let out = inst.pin_out::<f64>("out")?;
        let gain0 = inst.param_rw::<f64>("gain0", 1.0)?;
        let gain1 = inst.param_rw::<f64>("gain1", 1.0)?;
        let offset = inst.param_rw::<f64>("offset", 0.0)?;
        inst.funct("_", true, move |_| {
            out.set((in0.get() * gain0.get() + in1.get() * gain1.get()) + offset.get())
        })
    }
}
halcomp_module!(pub SUM2, Sum2, "weighted sum of two inputs");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&MULT2, &SUM2]
}
