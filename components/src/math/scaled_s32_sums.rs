//! `scaled_s32_sums`: the sum of four s32 inputs, each times a float
//! scale, as a float and truncated to an s32.

use hal_core::Result;

use crate::cmath::f64_to_i32;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// `(in0*scale0 + in1*scale1) + in2*scale2) + in3*scale3`, summed left to
/// right in f64, and that sum truncated toward zero to an s32 (C's
/// conversion: out of range or NaN gives `i32::MIN`).
pub fn scaled_sum(inputs: [i32; 4], scales: [f64; 4]) -> (f64, i32) {
    let f = inputs
        .iter()
        .zip(scales)
        .map(|(&i, s)| f64::from(i) * s)
        .fold(None, |acc: Option<f64>, t| Some(acc.map_or(t, |a| a + t)))
        .unwrap_or(0.0);
    (f, f64_to_i32(f))
}

/// The `scaled_s32_sums` component.
pub struct ScaledS32Sums;
impl HalComp for ScaledS32Sums {
    const NAME: &'static str = "scaled_s32_sums";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let ins = (0..4)
            .map(|i| inst.pin_in::<i32>(&format!("in{i}")))
            .collect::<Result<Vec<_>>>()?;
        let scales = (0..4)
            .map(|i| inst.pin_in_init::<f64>(&format!("scale{i}"), 1.0))
            .collect::<Result<Vec<_>>>()?;
        let out_s = inst.pin_out::<i32>("out-s")?;
        let out_f = inst.pin_out::<f64>("out-f")?;
        inst.funct("_", true, move |_| {
            let (f, s) = scaled_sum(
                std::array::from_fn(|i| ins[i].get()),
                std::array::from_fn(|i| scales[i].get()),
            );
            out_f.set(f);
            out_s.set(s);
        })
    }
}
halcomp_module!(pub MODULE, ScaledS32Sums, "sum of four inputs (each with a scale)");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Float, S32};

    #[test]
    fn sums_left_to_right_and_truncates() {
        assert_eq!(scaled_sum([1, 2, 3, 4], [1.0; 4]), (10.0, 10));
        assert_eq!(scaled_sum([3, 0, 0, 0], [-0.5, 1.0, 1.0, 1.0]), (-1.5, -1));
        let (f, s) = scaled_sum([i32::MAX, i32::MAX, 0, 0], [1.0; 4]);
        assert_eq!(f, 2.0 * i32::MAX as f64);
        assert_eq!(s, i32::MIN, "out of range converts as C does on x86-64");
        let (f, _) = scaled_sum([1, 1, 1, 0], [1e16, 1.0, -1e16, 0.0]);
        assert_eq!(f, (1e16 + 1.0) - 1e16, "grouped left to right");
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("s32sums");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "scaled-s32-sums.0",
            &[
                "in0 s32 in 0",
                "in1 s32 in 0",
                "in2 s32 in 0",
                "in3 s32 in 0",
                "scale0 float in 1",
                "scale1 float in 1",
                "scale2 float in 1",
                "scale3 float in 1",
                "out-s s32 out 0",
                "out-f float out 0",
            ],
        );
        h.thread(&["scaled-s32-sums.0"]);
        h.set("scaled-s32-sums.0.in1", S32(5));
        h.set("scaled-s32-sums.0.scale1", Float(0.7));
        h.expect(&[], "scaled-s32-sums.0.out-f", Float(5.0 * 0.7));
        assert_eq!(h.get("scaled-s32-sums.0.out-s"), S32(3));
    }
}
