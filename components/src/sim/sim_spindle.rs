//! `sim_spindle`: a spindle model. The position (in revolutions)
//! integrates `velocity-cmd * scale`; while `index-enable` is set, the
//! first whole revolution crossed resets the position to its fraction
//! past the index and clears `index-enable`, as an encoder index does.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::timing::write_changed;

/// One call: the new position and `index-enable`. `fperiod` is the
/// period in seconds.
pub fn sim_spindle_step(
    position: f64,
    velocity_cmd: f64,
    scale: f64,
    index_enable: bool,
    fperiod: f64,
) -> (f64, bool) {
    let new = position + velocity_cmd * fperiod * scale;
    if index_enable && position.floor() != new.floor() {
        let past = if velocity_cmd < 0.0 {
            new - new.ceil()
        } else {
            new - new.floor()
        };
        (past, false)
    } else {
        (new, index_enable)
    }
}

/// The `sim_spindle` component.
pub struct SimSpindle;
impl HalComp for SimSpindle {
    const NAME: &'static str = "sim_spindle";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let velocity_cmd = inst.pin_in::<f64>("velocity-cmd")?;
        let position_fb = inst.pin_out::<f64>("position-fb")?;
        let index_enable = inst.pin_io::<bool>("index-enable", false)?;
        let scale = inst.param_rw::<f64>("scale", 1.0)?;
        inst.funct("_", true, move |ctx| {
            let old_index = index_enable.get();
            let (pos, index) = sim_spindle_step(
                position_fb.get(),
                velocity_cmd.get(),
                scale.get(),
                old_index,
                ctx.fperiod(),
            );
            write_changed(&index_enable, old_index, index);
            position_fb.set(pos);
        })
    }
}
halcomp_module!(pub MODULE, SimSpindle, "simulated spindle with index pulse");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn integrates_velocity_times_scale() {
        let (p, i) = sim_spindle_step(0.25, 600.0, 1.0 / 60.0, false, 0.001);
        assert_eq!(p, 0.25 + 600.0 * 0.001 * (1.0 / 60.0));
        assert!(!i);
    }

    #[test]
    fn index_resets_at_a_whole_revolution() {
        // Forward across 1.0: keeps the fraction past it.
        let (p, i) = sim_spindle_step(0.95, 100.0, 1.0, true, 0.001);
        assert!((p - 0.05).abs() < 1e-12 && !i);
        // No crossing: index-enable stays set.
        let (p, i) = sim_spindle_step(0.5, 100.0, 1.0, true, 0.001);
        assert!((p - 0.6).abs() < 1e-12 && i);
        // Backwards across -1.0: the (negative) fraction below it.
        let (p, i) = sim_spindle_step(-0.95, -100.0, 1.0, true, 0.001);
        assert!((p + 0.05).abs() < 1e-12 && !i);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("simspin");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "sim-spindle.0",
            &[
                "velocity-cmd float in 0",
                "position-fb float out 0",
                "index-enable bit io 0",
            ],
        );
        h.check_params("sim-spindle.0", &["scale float rw 1"]);
        h.thread(&["sim-spindle.0"]);
        h.set("sim-spindle.0.velocity-cmd", Float(100.0));
        h.set("sim-spindle.0.index-enable", Bit(true));
        // 0.1 rev per 1 ms cycle: the index is passed within 10 cycles.
        let n = h.run(12);
        assert_eq!(h.get("sim-spindle.0.index-enable"), Bit(false));
        let p = crate::testing::float(h.get("sim-spindle.0.position-fb"));
        assert!(p < n as f64 * 0.1 - 0.9, "position restarted at the index");
    }
}
