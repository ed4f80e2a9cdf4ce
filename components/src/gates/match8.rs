//! `match8`: TRUE when the eight `a` bits equal the eight `b` bits and
//! the cascade input `in` is TRUE (chain instances through `in` to
//! compare wider words).

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The output for cascade input `cascade` and the two bytes (bit m of
/// each is pin `am` / `bm`).
pub fn match8(cascade: bool, a: u8, b: u8) -> bool {
    cascade && a == b
}

/// Packs eight bit pins, pin m into bit m.
fn byte(pins: &[hal_core::Pin<bool, hal_core::In>]) -> u8 {
    pins.iter()
        .enumerate()
        .fold(0, |acc, (m, p)| acc | ((p.get() as u8) << m))
}

/// The `match8` component.
pub struct Match8;
impl HalComp for Match8 {
    const NAME: &'static str = "match8";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let cascade = inst.pin_in_init::<bool>("in", true)?;
        let a = (0..8)
            .map(|m| inst.pin_in::<bool>(&format!("a{m}")))
            .collect::<Result<Vec<_>>>()?;
        let b = (0..8)
            .map(|m| inst.pin_in::<bool>(&format!("b{m}")))
            .collect::<Result<Vec<_>>>()?;
        let out = inst.pin_out::<bool>("out")?;
        inst.funct("_", false, move |_| {
            out.set(match8(cascade.get(), byte(&a), byte(&b)))
        })
    }
}
halcomp_module!(pub MODULE, Match8, "8-bit binary match detector");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Bit;

    #[test]
    fn matches_only_equal_bytes_with_cascade() {
        assert!(match8(true, 0, 0));
        assert!(match8(true, 0xa5, 0xa5));
        assert!(!match8(true, 0xa5, 0xa4));
        assert!(!match8(true, 0x80, 0x00));
        assert!(!match8(false, 0x12, 0x12));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("match8");
        h.load(&MODULE, &["count=2"]).unwrap();
        let mut want = vec!["in bit in 1".to_string(), "out bit out 0".to_string()];
        for m in 0..8 {
            want.push(format!("a{m} bit in 0"));
            want.push(format!("b{m} bit in 0"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("match8.1", &want);
        h.check_params("match8.1", &[]);
        h.thread(&["match8.0"]);
        h.expect(&[], "match8.0.out", Bit(true));
        h.expect(&[("match8.0.a7", Bit(true))], "match8.0.out", Bit(false));
        h.expect(&[("match8.0.b7", Bit(true))], "match8.0.out", Bit(true));
        h.expect(&[("match8.0.in", Bit(false))], "match8.0.out", Bit(false));
    }
}
