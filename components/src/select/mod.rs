//! Selectors: mux2, mux4, mux8.

use hal_core::{In, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Builds a mux with `sels` select bits and 2^sels float inputs.
fn mux(inst: &mut Inst<'_, '_>, sels: usize) -> Result<()> {
    let sel: Vec<Pin<bool, In>> = if sels == 1 {
        vec![inst.pin_in("sel")?]
    } else {
        (0..sels)
            .map(|i| inst.pin_in(&format!("sel{i}")))
            .collect::<Result<_>>()?
    };
    let inputs: Vec<Pin<f64, In>> = (0..1usize << sels)
        .map(|i| inst.pin_in(&format!("in{i}")))
        .collect::<Result<_>>()?;
    let out = inst.pin_out::<f64>("out")?;
    inst.funct("_", false, move |_| {
        let k = sel
            .iter()
            .enumerate()
            .map(|(i, s)| (s.get() as usize) << i)
            .sum::<usize>();
        out.set(inputs[k].get());
    })
}

macro_rules! muxes {
    ($($ty:ident $static:ident $name:literal $sels:literal;)*) => {$(
        #[doc = concat!("`", $name, "`: out = in<k>, k from the select bits.")]
        pub struct $ty;
        impl HalComp for $ty {
            const NAME: &'static str = $name;
            fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
                mux(inst, $sels)
            }
        }
        halcomp_module!(pub $static, $ty, "selects one of several float inputs");
    )*};
}

muxes! {
    Mux2 MUX2 "mux2" 1;
    Mux4 MUX4 "mux4" 2;
    Mux8 MUX8 "mux8" 3;
}

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&MUX2, &MUX4, &MUX8]
}
