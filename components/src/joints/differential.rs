//! `differential`: kinematics of a differential (bevel) transmission:
//! the motors take roll + pitch and roll - pitch; the feedback is split
//! back into roll and pitch.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Motor commands for (roll, pitch).
pub fn to_motors(roll: f64, pitch: f64) -> (f64, f64) {
    (roll + pitch, roll - pitch)
}

/// (roll, pitch) from the motor feedbacks.
pub fn from_motors(m0: f64, m1: f64) -> (f64, f64) {
    ((m0 + m1) / 2.0, (m0 - m1) / 2.0)
}

/// The `differential` component.
pub struct Differential;
impl HalComp for Differential {
    const NAME: &'static str = "differential";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let roll_cmd = inst.pin_in::<f64>("roll-cmd")?;
        let pitch_cmd = inst.pin_in::<f64>("pitch-cmd")?;
        let roll_fb = inst.pin_out::<f64>("roll-fb")?;
        let pitch_fb = inst.pin_out::<f64>("pitch-fb")?;
        let motor0_cmd = inst.pin_out::<f64>("motor0-cmd")?;
        let motor1_cmd = inst.pin_out::<f64>("motor1-cmd")?;
        let motor0_fb = inst.pin_in::<f64>("motor0-fb")?;
        let motor1_fb = inst.pin_in::<f64>("motor1-fb")?;
        inst.funct("_", true, move |_| {
            let (m0, m1) = to_motors(roll_cmd.get(), pitch_cmd.get());
            motor0_cmd.set(m0);
            motor1_cmd.set(m1);
            let (r, p) = from_motors(motor0_fb.get(), motor1_fb.get());
            roll_fb.set(r);
            pitch_fb.set(p);
        })
    }
}
halcomp_module!(pub MODULE, Differential, "kinematics for a differential transmission");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Float;

    #[test]
    fn round_trip() {
        let (m0, m1) = to_motors(30.0, 10.0);
        assert_eq!((m0, m1), (40.0, 20.0));
        assert_eq!(from_motors(m0, m1), (30.0, 10.0));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("differential");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "differential.0",
            &[
                "roll-cmd float in 0",
                "pitch-cmd float in 0",
                "roll-fb float out 0",
                "pitch-fb float out 0",
                "motor0-cmd float out 0",
                "motor1-cmd float out 0",
                "motor0-fb float in 0",
                "motor1-fb float in 0",
            ],
        );
        h.thread(&["differential.0"]);
        h.set("differential.0.pitch-cmd", Float(5.0));
        h.expect(&[], "differential.0.motor1-cmd", Float(-5.0));
        h.expect(
            &[("differential.0.motor0-fb", Float(4.0))],
            "differential.0.pitch-fb",
            Float(2.0),
        );
    }
}
