//! Logic gates (reference section 4): the fixed two-input gates and2,
//! or2, xor2 and the inverter not, and `logic`, a configurable gate of up
//! to 16 inputs whose personality picks the number of inputs and which of
//! the and/or/xor/nand/nor outputs exist. In their own files: match8,
//! lut5, maj3, tristate_bit and tristate_float.

pub mod lut5;
pub mod maj3;
pub mod match8;
pub mod tristate;

use hal_core::{HalError, In, Out, Pin, Result};

use crate::error::CompError;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// A two-input gate. `op` is generic, not a function pointer, so that each
/// gate's operation is inlined into its function body.
fn gate2(inst: &mut Inst<'_, '_>, op: impl Fn(bool, bool) -> bool + Send + 'static) -> Result<()> {
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

/// Most inputs one gate may have.
pub const MAX_INPUTS: usize = 16;
/// Personality bits holding the number of inputs.
pub const INPUT_MASK: i64 = 0xff;
/// Personality bit creating the `and` output.
pub const AND: i64 = 0x100;
/// Personality bit creating the `or` output.
pub const OR: i64 = 0x200;
/// Personality bit creating the `xor` output.
pub const XOR: i64 = 0x400;
/// Personality bit creating the `nand` output.
pub const NAND: i64 = 0x800;
/// Personality bit creating the `nor` output.
pub const NOR: i64 = 0x1000;

/// The three reductions every output is derived from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reduced {
    /// Every input TRUE (TRUE for no inputs).
    pub and: bool,
    /// Any input TRUE.
    pub or: bool,
    /// Odd number of TRUE inputs.
    pub xor: bool,
}

/// Reduces the inputs in order.
pub fn reduce(inputs: impl IntoIterator<Item = bool>) -> Reduced {
    let mut r = Reduced {
        and: true,
        or: false,
        xor: false,
    };
    for i in inputs {
        if i {
            r.or = true;
            r.xor = !r.xor;
        } else {
            r.and = false;
        }
    }
    r
}

/// The number of inputs a personality asks for, checked.
pub fn input_count(personality: i64) -> std::result::Result<usize, CompError> {
    let n = (personality & INPUT_MASK) as usize;
    if n > MAX_INPUTS {
        Err(CompError::TooManyInputs {
            personality,
            inputs: n,
            max: MAX_INPUTS,
        })
    } else {
        Ok(n)
    }
}

/// `logic`: and/or/xor/nand/nor of `personality & 0xff` bit inputs.
pub struct Logic;
impl HalComp for Logic {
    const NAME: &'static str = "logic";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let p = inst.personality;
        let n = input_count(p).map_err(|reason| HalError::ModuleParam {
            module: Self::NAME.into(),
            param: "personality".into(),
            reason: format!("instance {}: {reason}", inst.prefix),
        })?;
        let inputs: Vec<Pin<bool, In>> = (0..n)
            .map(|i| inst.pin_in(&format!("in-{i:02}")))
            .collect::<Result<_>>()?;
        let mut out = |bit: i64, item: &str| -> Result<Option<Pin<bool, Out>>> {
            if p & bit != 0 {
                inst.pin_out(item).map(Some)
            } else {
                Ok(None)
            }
        };
        let and = out(AND, "and")?;
        let or = out(OR, "or")?;
        let xor = out(XOR, "xor")?;
        let nand = out(NAND, "nand")?;
        let nor = out(NOR, "nor")?;
        inst.funct("_", false, move |_| {
            let r = reduce(inputs.iter().map(Pin::get));
            for (pin, v) in [
                (&and, r.and),
                (&or, r.or),
                (&xor, r.xor),
                (&nand, !r.and),
                (&nor, !r.or),
            ] {
                if let Some(pin) = pin {
                    pin.set(v);
                }
            }
        })
    }
}
halcomp_module!(
    pub LOGIC,
    Logic,
    "general logic function: and/or/xor/nand/nor of up to 16 inputs"
);

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &AND2,
        &OR2,
        &XOR2,
        &NOT,
        &LOGIC,
        &match8::MODULE,
        &lut5::MODULE,
        &maj3::MODULE,
        &tristate::TRISTATE_BIT,
        &tristate::TRISTATE_FLOAT,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Bit;

    #[test]
    fn reductions() {
        assert_eq!(
            reduce([]),
            Reduced {
                and: true,
                or: false,
                xor: false
            }
        );
        assert_eq!(
            reduce([true, true, true]),
            Reduced {
                and: true,
                or: true,
                xor: true
            }
        );
        assert_eq!(
            reduce([true, false, true]),
            Reduced {
                and: false,
                or: true,
                xor: false
            }
        );
        assert_eq!(
            reduce([false; 16]),
            Reduced {
                and: false,
                or: false,
                xor: false
            }
        );
    }

    #[test]
    fn input_count_limits() {
        assert_eq!(input_count(0).ok(), Some(0));
        assert_eq!(input_count(0x1f10).ok(), Some(16));
        assert!(input_count(0x111).is_err());
        assert!(input_count(0xff).is_err());
    }

    #[test]
    fn personality_selects_pins() {
        let h = TestHost::new("logic-names");
        h.load(&LOGIC, &["names=l1,l2,l3", "personality=0x102,0x203"])
            .unwrap();
        assert_eq!(
            h.pins(),
            ["l1.and", "l1.in-00", "l1.in-01", "l2.in-00", "l2.in-01", "l2.in-02", "l2.or"]
        );
        assert_eq!(h.functs(), ["l1", "l2", "l3"]);
        assert!(h.params().is_empty());
    }

    #[test]
    fn too_many_inputs_fails_the_load() {
        let h = TestHost::new("logic-bad");
        let e = h
            .load(&LOGIC, &["count=2", "personality=0x102,0x111"])
            .unwrap_err();
        assert!(
            matches!(&e, HalError::ModuleParam { param, .. } if param == "personality"),
            "{e}"
        );
        assert!(h.pins().is_empty() && h.functs().is_empty());
        // The module can be loaded afterwards.
        h.load(&LOGIC, &["personality=0x1f10"]).unwrap();
        assert_eq!(h.pins().len(), 21);
    }

    #[test]
    fn outputs_follow_inputs() {
        let mut h = TestHost::new("logic-run");
        h.load(&LOGIC, &["personality=0x1f03"]).unwrap();
        h.thread(&["logic.0"]);
        let outs = ["and", "or", "xor", "nand", "nor"];
        for bits in 0..8u8 {
            let ins: Vec<(String, hal_core::Value)> = (0..3)
                .map(|i| (format!("logic.0.in-{i:02}"), Bit(bits >> i & 1 == 1)))
                .collect();
            for (p, v) in &ins {
                h.set(p, *v);
            }
            h.run(2);
            let ones = bits.count_ones();
            let want = [ones == 3, ones > 0, ones % 2 == 1, ones != 3, ones == 0];
            for (o, w) in outs.iter().zip(want) {
                assert_eq!(h.get(&format!("logic.0.{o}")), Bit(w), "{o} for {bits:03b}");
            }
        }
    }

    #[test]
    fn no_inputs_gives_and_true() {
        let mut h = TestHost::new("logic-zero");
        h.load(&LOGIC, &["personality=0x1f00"]).unwrap();
        h.thread(&["logic.0"]);
        h.run(2);
        assert_eq!(h.get("logic.0.and"), Bit(true));
        assert_eq!(h.get("logic.0.nor"), Bit(true));
        assert_eq!(h.get("logic.0.or"), Bit(false));
        assert_eq!(h.get("logic.0.nand"), Bit(false));
    }
}
