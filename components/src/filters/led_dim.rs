//! `led_dim`: maps a brightness (0 to 1) to LED luminance by the CIE 1931
//! lightness curve, so equal steps of `in` look like equal steps of
//! brightness.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The luminance for brightness `input` (clamped to [0, 1]).
pub fn luminance(input: f64) -> f64 {
    let x = if input > 0.0 { input } else { 0.0 };
    let x = if x < 1.0 { x } else { 1.0 };
    if x < 0.079996 {
        x / 9.033
    } else {
        ((x + 0.16) / 1.16).powf(3.0)
    }
}

/// The `led_dim` component. The output is recomputed only when the
/// input changes.
pub struct LedDim;
impl HalComp for LedDim {
    const NAME: &'static str = "led_dim";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let mut last_in = 0.0;
        inst.funct("_", true, move |_| {
            let x = input.get();
            if last_in != x {
                out.set(luminance(x));
                last_in = x;
            }
        })
    }
}
halcomp_module!(pub MODULE, LedDim, "HAL component for dimming LEDs");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Float;

    #[test]
    fn cie_curve() {
        assert_eq!(luminance(0.0), 0.0);
        assert_eq!(luminance(0.05), 0.05 / 9.033);
        assert_eq!(luminance(1.0), 1.0);
        assert_eq!(luminance(5.0), 1.0);
        assert_eq!(luminance(-1.0), 0.0);
        assert_eq!(luminance(0.5), (0.66f64 / 1.16).powf(3.0));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("led-dim");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins("led-dim.0", &["in float in 0", "out float out 0"]);
        h.thread(&["led-dim.0"]);
        h.expect(&[("led-dim.0.in", Float(1.0))], "led-dim.0.out", Float(1.0));
    }
}
