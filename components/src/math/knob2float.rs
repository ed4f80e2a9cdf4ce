//! `knob2float`: turns encoder counts into a float that changes by
//! `scale` per count while `enable` is TRUE, kept within
//! `[min-out, max-out]`; counts turned beyond a limit are lost, so
//! turning back moves the value at once.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The knob's state.
#[derive(Debug, Clone, Default)]
pub struct Knob {
    old_counts: i64,
    old_out: f64,
}

impl Knob {
    /// One call; returns `out`. `min_out` has already been limited to
    /// `max_out`.
    pub fn step(
        &mut self,
        counts: i32,
        enable: bool,
        scale: f64,
        min_out: f64,
        max_out: f64,
    ) -> f64 {
        let delta = i64::from(counts) - self.old_counts;
        if enable {
            let tmp = self.old_out + delta as f64 * scale;
            self.old_out = if tmp > max_out {
                max_out
            } else if tmp < min_out {
                min_out
            } else {
                tmp
            };
        }
        self.old_counts += delta;
        self.old_out
    }
}

/// The `knob2float` component.
pub struct Knob2Float;
impl HalComp for Knob2Float {
    const NAME: &'static str = "knob2float";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let counts = inst.pin_in::<i32>("counts")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let scale = inst.pin_in::<f64>("scale")?;
        let out = inst.pin_out::<f64>("out")?;
        let max_out = inst.param_rw::<f64>("max-out", 1.0)?;
        let min_out = inst.param_rw::<f64>("min-out", 0.0)?;
        let mut knob = Knob::default();
        inst.funct("_", true, move |_| {
            if min_out.get() > max_out.get() {
                min_out.set(max_out.get());
            }
            out.set(knob.step(
                counts.get(),
                enable.get(),
                scale.get(),
                min_out.get(),
                max_out.get(),
            ));
        })
    }
}
halcomp_module!(pub MODULE, Knob2Float, "convert counts (probably from an encoder) to a float value");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, S32};

    #[test]
    fn counts_scale_and_stop_at_the_limits() {
        let mut k = Knob::default();
        assert_eq!(k.step(4, true, 0.1, 0.0, 1.0), 0.4);
        assert_eq!(k.step(30, true, 0.1, 0.0, 1.0), 1.0, "clamped");
        // The counts past the limit are gone: one back moves at once.
        assert_eq!(k.step(29, true, 0.1, 0.0, 1.0), 0.9);
        // Disabled: counts are followed but the output holds.
        assert_eq!(k.step(0, false, 0.1, 0.0, 1.0), 0.9);
        assert_eq!(k.step(1, true, 0.1, 0.0, 1.0), 1.0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("knob2float");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "knob2float.0",
            &[
                "counts s32 in 0",
                "enable bit in 0",
                "scale float in 0",
                "out float out 0",
            ],
        );
        h.check_params(
            "knob2float.0",
            &["max-out float rw 1", "min-out float rw 0"],
        );
        h.thread(&["knob2float.0"]);
        h.set("knob2float.0.enable", Bit(true));
        h.set("knob2float.0.scale", Float(0.25));
        h.expect(
            &[("knob2float.0.counts", S32(2))],
            "knob2float.0.out",
            Float(0.5),
        );
        h.setp("knob2float.0.min-out", Float(5.0));
        h.run(2);
        assert_eq!(
            h.getp("knob2float.0.min-out"),
            Float(1.0),
            "limited to max-out"
        );
    }
}
