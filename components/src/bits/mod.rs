//! Integer and bit tools (reference section 10): bitslice, bitwise. In
//! their own files: bin2gray and gray2bin, bitmerge, weighted_sum.

pub mod bitmerge;
pub mod gray;
pub mod weighted_sum;

use hal_core::{HalError, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most output bits a bitslice instance may have.
pub const BITSLICE_MAX: i64 = 32;

/// Bit `i` (0..32) of `x`.
pub fn bit(x: u32, i: u32) -> bool {
    (x >> i) & 1 != 0
}

/// The number of outputs of a bitslice instance with `personality`:
/// above 32 fails the load; zero or negative gives none.
pub fn bitslice_width(personality: i64) -> Result<usize> {
    if personality > BITSLICE_MAX {
        return Err(HalError::ModuleParam {
            module: "bitslice".into(),
            param: "personality".into(),
            reason: format!(
                "{personality} output bits requested; bitslice has at most {BITSLICE_MAX}"
            ),
        });
    }
    Ok(personality.max(0) as usize)
}

/// `bitslice`: splits a u32 into `personality` bit outputs.
pub struct BitsliceComp;
impl HalComp for BitsliceComp {
    const NAME: &'static str = "bitslice";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let width = bitslice_width(inst.personality)?;
        let input = inst.pin_in::<u32>("in")?;
        let outs: Vec<Pin<bool, Out>> = (0..width)
            .map(|i| inst.pin_out(&format!("out-{i:02}")))
            .collect::<Result<_>>()?;
        inst.funct("_", false, move |_| {
            let x = input.get();
            for (i, o) in outs.iter().enumerate() {
                o.set(bit(x, i as u32));
            }
        })
    }
}
halcomp_module!(
    pub BITSLICE,
    BitsliceComp,
    "splits a u32 into bits; personality = number of output bits (up to 32)"
);

/// The six results of `bitwise`, in the order
/// and, or, xor, nand, nor, xnor.
pub fn bitwise(in0: u32, in1: u32) -> [u32; 6] {
    let a = in0 & in1;
    let o = in0 | in1;
    let x = in0 ^ in1;
    [a, o, x, !a, !o, !x]
}

/// `bitwise`: and, or, xor and their complements of two u32 inputs.
pub struct BitwiseComp;
impl HalComp for BitwiseComp {
    const NAME: &'static str = "bitwise";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let in0 = inst.pin_in::<u32>("in0")?;
        let in1 = inst.pin_in::<u32>("in1")?;
        let outs: [Pin<u32, Out>; 6] = [
            inst.pin_out("out-and")?,
            inst.pin_out("out-or")?,
            inst.pin_out("out-xor")?,
            inst.pin_out("out-nand")?,
            inst.pin_out("out-nor")?,
            inst.pin_out("out-xnor")?,
        ];
        inst.funct("_", false, move |_| {
            for (o, v) in outs.iter().zip(bitwise(in0.get(), in1.get())) {
                o.set(v);
            }
        })
    }
}
halcomp_module!(pub BITWISE, BitwiseComp, "bitwise and, or, xor and complements of two u32");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &BITSLICE,
        &BITWISE,
        &gray::BIN2GRAY,
        &gray::GRAY2BIN,
        &bitmerge::MODULE,
        &weighted_sum::MODULE,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    #[test]
    fn bits_of_a_u32() {
        let x = 0x8000_0005;
        assert!(bit(x, 0) && !bit(x, 1) && bit(x, 2) && bit(x, 31));
        assert!(!bit(0, 31));
    }

    #[test]
    fn bitwise_results_are_32_bit_complements() {
        assert_eq!(
            bitwise(0b1100, 0b1010),
            [0b1000, 0b1110, 0b0110, !0b1000, !0b1110, !0b0110]
        );
        assert_eq!(bitwise(0, 0), [0, 0, 0, u32::MAX, u32::MAX, u32::MAX]);
        assert_eq!(bitwise(u32::MAX, u32::MAX)[2], 0);
    }

    #[test]
    fn bitslice_width_limits() {
        assert_eq!(bitslice_width(0).unwrap(), 0);
        assert_eq!(bitslice_width(-3).unwrap(), 0);
        assert_eq!(bitslice_width(32).unwrap(), 32);
        assert!(bitslice_width(33).is_err());
    }

    #[test]
    fn bitslice_pins_follow_personality_and_bad_ones_fail() {
        let host = testing::host();
        let err = testing::load(&host, &BITSLICE, &["count=2", "personality=3,33"]).unwrap_err();
        assert!(
            matches!(&err, HalError::ModuleParam { param, .. } if param == "personality"),
            "{err}"
        );
        assert!(testing::pin_names(&host).is_empty());
        testing::load(&host, &BITSLICE, &["count=3", "personality=3,12"]).unwrap();
        let pins = testing::pin_names(&host);
        assert!(pins.contains(&"bitslice.0.out-02".to_string()));
        assert!(!pins.contains(&"bitslice.0.out-03".to_string()));
        assert!(pins.contains(&"bitslice.1.out-11".to_string()));
        // Instance 2 has the default personality 0: only `in`.
        assert!(pins.contains(&"bitslice.2.in".to_string()));
        assert!(!pins.iter().any(|p| p.starts_with("bitslice.2.out")));
    }

    #[test]
    fn bitwise_loads() {
        let host = testing::host();
        testing::load(&host, &BITWISE, &[]).unwrap();
        assert!(testing::pin_names(&host).contains(&"bitwise.0.out-xnor".to_string()));
    }
}
