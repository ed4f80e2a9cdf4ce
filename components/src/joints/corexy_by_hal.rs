//! `corexy_by_hal`: CoreXY kinematics in HAL, for trivkins
//! configurations: joint 0/1 (x/y) commands become alpha/beta motor
//! commands, and the motor feedback becomes joint feedback.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Motor commands (alpha, beta) for joint commands (x, y).
pub fn to_motors(x: f64, y: f64) -> (f64, f64) {
    (0.5 * (x + y), 0.5 * (x - y))
}

/// Joint feedback (x, y) from the motor feedback.
pub fn from_motors(alpha: f64, beta: f64) -> (f64, f64) {
    (alpha + beta, alpha - beta)
}

/// The `corexy_by_hal` component.
pub struct CorexyByHal;
impl HalComp for CorexyByHal {
    const NAME: &'static str = "corexy_by_hal";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let alpha_fb = inst.pin_in::<f64>("alpha-fb")?;
        let beta_fb = inst.pin_in::<f64>("beta-fb")?;
        let j0_cmd = inst.pin_in::<f64>("j0-motor-pos-cmd")?;
        let j1_cmd = inst.pin_in::<f64>("j1-motor-pos-cmd")?;
        let j0_fb = inst.pin_out::<f64>("j0-motor-pos-fb")?;
        let j1_fb = inst.pin_out::<f64>("j1-motor-pos-fb")?;
        let alpha_cmd = inst.pin_out::<f64>("alpha-cmd")?;
        let beta_cmd = inst.pin_out::<f64>("beta-cmd")?;
        inst.funct("_", true, move |_| {
            let (x, y) = from_motors(alpha_fb.get(), beta_fb.get());
            j0_fb.set(x);
            j1_fb.set(y);
            let (a, b) = to_motors(j0_cmd.get(), j1_cmd.get());
            alpha_cmd.set(a);
            beta_cmd.set(b);
        })
    }
}
halcomp_module!(pub MODULE, CorexyByHal, "CoreXY kinematics in HAL");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Float;

    #[test]
    fn round_trip() {
        let (a, b) = to_motors(3.0, 1.0);
        assert_eq!((a, b), (2.0, 1.0));
        assert_eq!(from_motors(a, b), (3.0, 1.0));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("corexy");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "corexy-by-hal.0",
            &[
                "alpha-fb float in 0",
                "beta-fb float in 0",
                "j0-motor-pos-cmd float in 0",
                "j1-motor-pos-cmd float in 0",
                "j0-motor-pos-fb float out 0",
                "j1-motor-pos-fb float out 0",
                "alpha-cmd float out 0",
                "beta-cmd float out 0",
            ],
        );
        h.thread(&["corexy-by-hal.0"]);
        h.expect(
            &[("corexy-by-hal.0.j0-motor-pos-cmd", Float(2.0))],
            "corexy-by-hal.0.beta-cmd",
            Float(1.0),
        );
    }
}
