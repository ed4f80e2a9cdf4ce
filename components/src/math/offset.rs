//! `offset`: adds `offset` to a command on its way out and subtracts it
//! from the feedback on its way back, so the rest of the loop never sees
//! it. Two functions: `update-output` and `update-feedback`.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The `offset` component.
pub struct Offset;
impl HalComp for Offset {
    const NAME: &'static str = "offset";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let offset = std::sync::Arc::new(inst.pin_in::<f64>("offset")?);
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let fb_in = inst.pin_in::<f64>("fb-in")?;
        let fb_out = inst.pin_out::<f64>("fb-out")?;
        let off = offset.clone();
        inst.funct("update-output", true, move |_| {
            out.set(input.get() + off.get())
        })?;
        inst.funct("update-feedback", true, move |_| {
            fb_out.set(fb_in.get() - offset.get())
        })
    }
}
halcomp_module!(pub MODULE, Offset, "adds an offset to an input, and subtracts it from the feedback value");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Float;

    #[test]
    fn pins_functions_and_a_run() {
        let mut h = TestHost::new("offset");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "offset.0",
            &[
                "offset float in 0",
                "in float in 0",
                "out float out 0",
                "fb-in float in 0",
                "fb-out float out 0",
            ],
        );
        assert_eq!(
            h.functs(),
            ["offset.0.update-feedback", "offset.0.update-output"]
        );
        h.thread(&["offset.0.update-output", "offset.0.update-feedback"]);
        h.set("offset.0.offset", Float(0.5));
        h.set("offset.0.fb-in", Float(3.0));
        h.expect(&[("offset.0.in", Float(2.0))], "offset.0.out", Float(2.5));
        assert_eq!(h.get("offset.0.fb-out"), Float(2.5));
    }
}
