//! `anglejog`: jogs two axes (or joints) at an angle from one MPG. The
//! wheel counts drive a one-dimensional planner (that of simple_tp)
//! along the vector at `angle-degrees-in`; its position comes out as
//! cosine and sine counts for the two axes' jog-counts pins, with
//! `current-scale-out` as their jog-scale. Angle and scale are taken only
//! while disabled.
//!
//! LinuxCNC keeps the planner state in function-static variables shared
//! by every instance; here each instance has its own.

use hal_core::Result;

use crate::cmath::{f64_to_i32, f64_to_i64};
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;

/// Smallest accepted `iscale-factor`.
pub const MIN_ISCALE_FACTOR: i32 = 10;
/// Largest accepted `iscale-factor`.
pub const MAX_ISCALE_FACTOR: i32 = 100000;

/// What anglejog writes to stderr.
pub static TEXTS: &[&str] = &["anglejog: BOGUS iscale-factor (allowed 10 to 100000)\n"];

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AngleJogVars {
    /// Pin `enable-in`.
    pub enable_in: bool,
    /// Pin `counts-in`.
    pub counts_in: i32,
    /// Pin `angle-degrees-in`.
    pub angle_degrees_in: f64,
    /// Pin `iscale-factor`.
    pub iscale_factor: i32,
    /// Pin `scale-in`.
    pub scale_in: f64,
    /// Pin `max-vel`.
    pub max_vel: f64,
    /// Pin `max-accel`.
    pub max_accel: f64,
    /// Pin `accel-fraction-in`.
    pub accel_fraction_in: f64,
    /// Pin `enable-out`.
    pub enable_out: bool,
    /// Pin `current-scale`.
    pub current_scale: f64,
    /// Pin `current-scale-out`.
    pub current_scale_out: f64,
    /// Pin `coscounts`.
    pub coscounts: i32,
    /// Pin `sincounts`.
    pub sincounts: i32,
    /// Pin `cos-accel-fraction`.
    pub cos_accel_fraction: f64,
    /// Pin `sin-accel-fraction`.
    pub sin_accel_fraction: f64,
    /// Pin `active`.
    pub active: bool,
    /// Pin `current-angle-degrees`.
    pub current_angle_degrees: f64,
    /// Pin `current-mag`.
    pub current_mag: f64,
    /// Pin `current-vel`.
    pub current_vel: f64,
}

/// The planner state.
#[derive(Debug, Clone)]
pub struct AngleJog {
    once: bool,
    wait_for_count_change: bool,
    tot_counts: i64,
    old_enable_in: bool,
    old_counts_in: i64,
    ifactor: i32,
    gave_msg: bool,
}

impl Default for AngleJog {
    fn default() -> Self {
        AngleJog {
            once: true,
            wait_for_count_change: false,
            tot_counts: 0,
            old_enable_in: false,
            old_counts_in: 0,
            ifactor: 0,
            gave_msg: false,
        }
    }
}

/// Degrees to radians as LinuxCNC's macro expands: `x * PI / 180`.
fn rad(x: f64) -> f64 {
    x * std::f64::consts::PI / 180.0
}

impl AngleJog {
    /// One call, `fperiod` seconds after the last; TRUE when the bogus
    /// iscale-factor message is to be printed.
    pub fn step(&mut self, v: &mut AngleJogVars, fperiod: f64) -> bool {
        let mut msg = false;
        if self.once {
            v.current_angle_degrees = v.angle_degrees_in;
            v.current_scale = v.scale_in;
            v.current_scale_out = v.scale_in / f64::from(v.iscale_factor);
            self.ifactor = v.iscale_factor;
            self.once = false;
        }
        let newcounts = i64::from(self.ifactor.wrapping_mul(v.counts_in));
        if v.enable_in && !self.old_enable_in {
            self.old_counts_in = newcounts;
            self.wait_for_count_change = true;
            self.tot_counts = f64_to_i64(v.current_mag / v.current_scale_out);
        }
        let delta = newcounts - self.old_counts_in;
        self.old_enable_in = v.enable_in;
        self.old_counts_in = newcounts;
        v.enable_out = v.enable_in;
        if delta != 0 {
            self.wait_for_count_change = false;
        }
        if v.enable_in {
            self.tot_counts = self.tot_counts.wrapping_add(delta);
        }
        let mag_cmd = self.tot_counts as f64 * v.current_scale_out;

        v.active = false;
        let max_dv = v.max_accel * fperiod;
        let tiny_dp = v.max_accel * fperiod * fperiod * 0.001;
        let mut vel_req = 0.0;
        if v.enable_in && !self.wait_for_count_change {
            let err = mag_cmd - v.current_mag;
            if err > tiny_dp {
                vel_req = -max_dv + (2.0 * v.max_accel * err + max_dv * max_dv).sqrt();
                v.active = true;
            } else if err < -tiny_dp {
                vel_req = max_dv - (-2.0 * v.max_accel * err + max_dv * max_dv).sqrt();
                v.active = true;
            }
        } else {
            if !v.enable_in {
                let mut new_ifactor = false;
                if self.ifactor != v.iscale_factor {
                    if (MIN_ISCALE_FACTOR..=MAX_ISCALE_FACTOR).contains(&v.iscale_factor) {
                        self.ifactor = v.iscale_factor;
                        new_ifactor = true;
                        self.gave_msg = false;
                    } else if !self.gave_msg {
                        msg = true;
                        self.gave_msg = true;
                    }
                }
                v.current_angle_degrees = v.angle_degrees_in;
                if v.current_scale_out != v.scale_in || new_ifactor {
                    v.current_scale = v.scale_in;
                    v.current_scale_out = v.scale_in / f64::from(self.ifactor);
                    self.tot_counts = f64_to_i64(v.current_mag / v.current_scale_out);
                }
            }
            if self.wait_for_count_change {
                return msg;
            }
        }
        if vel_req > v.max_vel {
            vel_req = v.max_vel;
        } else if vel_req < -v.max_vel {
            vel_req = -v.max_vel;
        }
        if vel_req > v.current_vel + max_dv {
            v.current_vel += max_dv;
        } else if vel_req < v.current_vel - max_dv {
            v.current_vel -= max_dv;
        } else {
            v.current_vel = vel_req;
        }
        if v.current_vel != 0.0 {
            v.active = true;
        }
        v.current_mag += v.current_vel * fperiod;
        let (s, c) = (
            rad(v.current_angle_degrees).sin(),
            rad(v.current_angle_degrees).cos(),
        );
        v.coscounts = f64_to_i32(v.current_mag * c / v.current_scale_out);
        v.sincounts = f64_to_i32(v.current_mag * s / v.current_scale_out);
        v.cos_accel_fraction = v.accel_fraction_in * c;
        v.sin_accel_fraction = v.accel_fraction_in * s;
        msg
    }
}

/// The `anglejog` component.
pub struct AngleJogComp;
impl HalComp for AngleJogComp {
    const NAME: &'static str = "anglejog";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let enable_in = inst.pin_in::<bool>("enable-in")?;
        let counts_in = inst.pin_in::<i32>("counts-in")?;
        let angle_degrees_in = inst.pin_in::<f64>("angle-degrees-in")?;
        let iscale_factor = inst.pin_in_init::<i32>("iscale-factor", 10000)?;
        let scale_in = inst.pin_in::<f64>("scale-in")?;
        let max_vel = inst.pin_in::<f64>("max-vel")?;
        let max_accel = inst.pin_in::<f64>("max-accel")?;
        let accel_fraction_in = inst.pin_in_init::<f64>("accel-fraction-in", 1.0)?;
        let enable_out = inst.pin_out::<bool>("enable-out")?;
        let current_scale = inst.pin_out::<f64>("current-scale")?;
        let current_scale_out = inst.pin_out::<f64>("current-scale-out")?;
        let coscounts = inst.pin_out::<i32>("coscounts")?;
        let sincounts = inst.pin_out::<i32>("sincounts")?;
        let cos_accel_fraction = inst.pin_out::<f64>("cos-accel-fraction")?;
        let sin_accel_fraction = inst.pin_out::<f64>("sin-accel-fraction")?;
        let active = inst.pin_out::<bool>("active")?;
        let current_angle_degrees = inst.pin_out::<f64>("current-angle-degrees")?;
        let current_mag = inst.pin_out::<f64>("current-mag")?;
        let current_vel = inst.pin_out::<f64>("current-vel")?;
        let notice = Notice::new(TEXTS);
        let mut j = AngleJog::default();
        inst.funct("_", true, move |ctx| {
            let mut v = AngleJogVars {
                enable_in: enable_in.get(),
                counts_in: counts_in.get(),
                angle_degrees_in: angle_degrees_in.get(),
                iscale_factor: iscale_factor.get(),
                scale_in: scale_in.get(),
                max_vel: max_vel.get(),
                max_accel: max_accel.get(),
                accel_fraction_in: accel_fraction_in.get(),
                enable_out: enable_out.get(),
                current_scale: current_scale.get(),
                current_scale_out: current_scale_out.get(),
                coscounts: coscounts.get(),
                sincounts: sincounts.get(),
                cos_accel_fraction: cos_accel_fraction.get(),
                sin_accel_fraction: sin_accel_fraction.get(),
                active: active.get(),
                current_angle_degrees: current_angle_degrees.get(),
                current_mag: current_mag.get(),
                current_vel: current_vel.get(),
            };
            if j.step(&mut v, ctx.fperiod()) {
                notice.post(0);
            }
            enable_out.set(v.enable_out);
            current_scale.set(v.current_scale);
            current_scale_out.set(v.current_scale_out);
            coscounts.set(v.coscounts);
            sincounts.set(v.sincounts);
            cos_accel_fraction.set(v.cos_accel_fraction);
            sin_accel_fraction.set(v.sin_accel_fraction);
            active.set(v.active);
            current_angle_degrees.set(v.current_angle_degrees);
            current_mag.set(v.current_mag);
            current_vel.set(v.current_vel);
        })
    }
}
halcomp_module!(pub MODULE, AngleJogComp, "jog two axes (or joints) at an angle");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, S32};

    fn jog() -> AngleJogVars {
        AngleJogVars {
            angle_degrees_in: 30.0,
            iscale_factor: 10000,
            scale_in: 0.01,
            max_vel: 10.0,
            max_accel: 100.0,
            accel_fraction_in: 1.0,
            ..Default::default()
        }
    }

    #[test]
    fn wheel_counts_move_along_the_angle() {
        let mut j = AngleJog::default();
        let mut v = jog();
        j.step(&mut v, 0.001);
        assert_eq!(v.current_scale_out, 0.01 / 10000.0);
        v.enable_in = true;
        j.step(&mut v, 0.001);
        assert!(v.enable_out && !v.active, "waits for the wheel to turn");
        v.counts_in = 10; // 0.1 units along 30 degrees
        for _ in 0..500 {
            j.step(&mut v, 0.001);
        }
        assert!((v.current_mag - 0.1).abs() < 1e-6, "{}", v.current_mag);
        assert!(!v.active);
        // Within the planner's stopping tolerance of 0.1 along the angle.
        let c = 0.1 * rad(30.0).cos() / v.current_scale_out;
        assert!((f64::from(v.coscounts) - c).abs() <= 2.0);
        assert!((f64::from(v.sincounts) - 0.1 * 0.5 / v.current_scale_out).abs() <= 2.0);
        assert!((v.sin_accel_fraction - 0.5).abs() < 1e-12);
    }

    #[test]
    fn scale_factor_changes_only_while_disabled() {
        let mut j = AngleJog::default();
        let mut v = jog();
        j.step(&mut v, 0.001);
        v.iscale_factor = 5;
        assert!(j.step(&mut v, 0.001), "out of range: reported");
        assert!(!j.step(&mut v, 0.001), "once");
        v.iscale_factor = 100;
        j.step(&mut v, 0.001);
        assert_eq!(v.current_scale_out, 0.01 / 100.0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("anglejog");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "anglejog.0",
            &[
                "enable-in bit in 0",
                "counts-in s32 in 0",
                "angle-degrees-in float in 0",
                "iscale-factor s32 in 10000",
                "scale-in float in 0",
                "max-vel float in 0",
                "max-accel float in 0",
                "accel-fraction-in float in 1",
                "enable-out bit out 0",
                "current-scale float out 0",
                "current-scale-out float out 0",
                "coscounts s32 out 0",
                "sincounts s32 out 0",
                "cos-accel-fraction float out 0",
                "sin-accel-fraction float out 0",
                "active bit out 0",
                "current-angle-degrees float out 0",
                "current-mag float out 0",
                "current-vel float out 0",
            ],
        );
        h.thread(&["anglejog.0"]);
        h.set("anglejog.0.angle-degrees-in", Float(90.0));
        h.set("anglejog.0.scale-in", Float(0.001));
        h.expect(&[], "anglejog.0.current-angle-degrees", Float(90.0));
        h.expect(
            &[("anglejog.0.enable-in", Bit(true))],
            "anglejog.0.enable-out",
            Bit(true),
        );
        assert_eq!(h.get("anglejog.0.coscounts"), S32(0));
    }
}
