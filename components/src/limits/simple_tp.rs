//! `simple_tp`: a single-axis trajectory planner (the one LinuxCNC jogs
//! with): moves `current-pos` to `target-pos` within `maxvel` and
//! `maxaccel`, braking so as not to overshoot.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The planner's inputs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TpInputs {
    /// Pin `target-pos`.
    pub target_pos: f64,
    /// Pin `maxvel`.
    pub maxvel: f64,
    /// Pin `maxaccel`.
    pub maxaccel: f64,
    /// Pin `enable`: when FALSE the planner stops at full deceleration.
    pub enable: bool,
}

/// One step of `fperiod` seconds from (`pos`, `vel`): returns the new
/// position, velocity and whether the planner is moving.
pub fn simple_tp(i: &TpInputs, pos: f64, vel: f64, fperiod: f64) -> (f64, f64, bool) {
    let max_dv = i.maxaccel * fperiod;
    let tiny_dp = max_dv * fperiod * 0.001;
    let mut active = false;
    let mut vel_req = 0.0;
    if i.enable {
        let pos_err = i.target_pos - pos;
        if pos_err > tiny_dp {
            vel_req = -max_dv + (2.0 * i.maxaccel * pos_err + max_dv * max_dv).sqrt();
            active = true;
        } else if pos_err < -tiny_dp {
            vel_req = max_dv - (-2.0 * i.maxaccel * pos_err + max_dv * max_dv).sqrt();
            active = true;
        }
    }
    if vel_req > i.maxvel {
        vel_req = i.maxvel;
    } else if vel_req < -i.maxvel {
        vel_req = -i.maxvel;
    }
    let vel = if vel_req > vel + max_dv {
        vel + max_dv
    } else if vel_req < vel - max_dv {
        vel - max_dv
    } else {
        vel_req
    };
    if vel != 0.0 {
        active = true;
    }
    (pos + vel * fperiod, vel, active)
}

/// The `simple_tp` component.
pub struct SimpleTp;
impl HalComp for SimpleTp {
    const NAME: &'static str = "simple_tp";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let target_pos = inst.pin_in::<f64>("target-pos")?;
        let maxvel = inst.pin_in::<f64>("maxvel")?;
        let maxaccel = inst.pin_in::<f64>("maxaccel")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let current_pos = inst.pin_out::<f64>("current-pos")?;
        let current_vel = inst.pin_out::<f64>("current-vel")?;
        let active = inst.pin_out::<bool>("active")?;
        inst.funct("update", true, move |ctx| {
            let i = TpInputs {
                target_pos: target_pos.get(),
                maxvel: maxvel.get(),
                maxaccel: maxaccel.get(),
                enable: enable.get(),
            };
            let (p, v, a) = simple_tp(&i, current_pos.get(), current_vel.get(), ctx.fperiod());
            active.set(a);
            current_vel.set(v);
            current_pos.set(p);
        })
    }
}
halcomp_module!(pub MODULE, SimpleTp, "single axis simple trajectory planner");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn reaches_the_target_within_the_limits_without_overshoot() {
        let i = TpInputs {
            target_pos: 1.0,
            maxvel: 2.0,
            maxaccel: 10.0,
            enable: true,
        };
        let (mut p, mut v) = (0.0, 0.0);
        let mut steps = 0;
        loop {
            let (np, nv, active) = simple_tp(&i, p, v, 0.001);
            assert!(nv.abs() <= 2.0 && (nv - v).abs() <= 10.0 * 0.001 + 1e-12);
            assert!(np <= 1.0 + 1e-9, "overshoot {np}");
            (p, v) = (np, nv);
            steps += 1;
            if !active {
                break;
            }
            assert!(steps < 10_000);
        }
        assert!((p - 1.0).abs() < 1e-6, "{p}");
    }

    #[test]
    fn disabling_brakes_to_a_stop() {
        let i = TpInputs {
            maxvel: 2.0,
            maxaccel: 10.0,
            ..Default::default()
        };
        let (_, v, active) = simple_tp(&i, 0.0, 1.0, 0.001);
        assert_eq!(v, 1.0 - 0.01);
        assert!(active);
        let (_, v, active) = simple_tp(&i, 0.0, 0.005, 0.001);
        assert_eq!((v, active), (0.0, false));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("simple-tp");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "simple-tp.0",
            &[
                "target-pos float in 0",
                "maxvel float in 0",
                "maxaccel float in 0",
                "enable bit in 0",
                "current-pos float out 0",
                "current-vel float out 0",
                "active bit out 0",
            ],
        );
        assert_eq!(h.functs(), ["simple-tp.0.update"]);
        h.thread(&["simple-tp.0.update"]);
        h.set("simple-tp.0.maxvel", Float(1.0));
        h.set("simple-tp.0.maxaccel", Float(100.0));
        h.set("simple-tp.0.target-pos", Float(1.0));
        h.expect(
            &[("simple-tp.0.enable", Bit(true))],
            "simple-tp.0.active",
            Bit(true),
        );
    }
}
