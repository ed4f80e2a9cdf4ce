//! `feedcomp`: scales `in` by the ratio of the current velocity to the
//! `feed` reference while enabled (laser power following the feed rate,
//! for example); passes it through otherwise.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// `in * (vel / feed)` when enabled, else `in`.
pub fn feedcomp(input: f64, enable: bool, vel: f64, feed: f64) -> f64 {
    if enable {
        input * (vel / feed)
    } else {
        input
    }
}

/// The `feedcomp` component.
pub struct Feedcomp;
impl HalComp for Feedcomp {
    const NAME: &'static str = "feedcomp";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let out = inst.pin_out::<f64>("out")?;
        let input = inst.pin_in::<f64>("in")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let vel = inst.pin_in::<f64>("vel")?;
        let feed = inst.param_rw::<f64>("feed", 0.0)?;
        inst.funct("_", true, move |_| {
            out.set(feedcomp(input.get(), enable.get(), vel.get(), feed.get()))
        })
    }
}
halcomp_module!(pub MODULE, Feedcomp, "multiply the input by the ratio of current velocity to the feed rate");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn ratio_of_velocities() {
        assert_eq!(feedcomp(10.0, true, 50.0, 100.0), 5.0);
        assert_eq!(feedcomp(10.0, false, 50.0, 100.0), 10.0);
        assert!(feedcomp(10.0, true, 50.0, 0.0).is_infinite());
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("feedcomp");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "feedcomp.0",
            &[
                "out float out 0",
                "in float in 0",
                "enable bit in 0",
                "vel float in 0",
            ],
        );
        h.check_params("feedcomp.0", &["feed float rw 0"]);
        h.thread(&["feedcomp.0"]);
        h.setp("feedcomp.0.feed", Float(4.0));
        h.set("feedcomp.0.vel", Float(1.0));
        h.set("feedcomp.0.in", Float(8.0));
        h.expect(
            &[("feedcomp.0.enable", Bit(true))],
            "feedcomp.0.out",
            Float(2.0),
        );
    }
}
