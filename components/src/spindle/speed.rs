//! `spindle`: speed control of a spindle driven through forward/reverse
//! inputs (inverter, DC drive), with per-gear scale, speed limits,
//! acceleration and deceleration, at-speed and zero-speed detection.
//! Without an encoder (`simulate-encoder`) the speed is modelled; with
//! one, acceleration is relative to the measured speed.
//!
//! `numgears=` (one entry per instance, 1 to 16, default 1) sets each
//! instance's gears; the gear pins are `<prefix>.<item>.<gear>`. Like
//! LinuxCNC, the arithmetic is in single precision.

use hal_core::module::{ParamDecl, ParamKind};
use hal_core::{In, Pin, Result};

use crate::halcomp::Inst;

/// Most gears.
pub const MAX_GEARS: usize = 16;

/// One gear's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear {
    /// `scale.N`.
    pub scale: f64,
    /// `min.N` (RPM; 0 for none).
    pub min: f64,
    /// `max.N` (RPM; 0 for none).
    pub max: f64,
    /// `accel.N`.
    pub accel: f64,
    /// `decel.N`.
    pub decel: f64,
    /// `speed-tolerance.N`.
    pub speed_tolerance: f64,
    /// `zero-tolerance.N`.
    pub zero_tolerance: f64,
    /// `offset.N`.
    pub offset: f64,
}

impl Default for Gear {
    /// The pins' defaults.
    fn default() -> Self {
        Gear {
            scale: 1.0,
            min: 0.0,
            max: 0.0,
            accel: 0.0,
            decel: 0.0,
            speed_tolerance: 20.0,
            zero_tolerance: 20.0,
            offset: 0.0,
        }
    }
}

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpindleVars {
    /// Pin `commanded-speed` (RPM).
    pub commanded_speed: f64,
    /// Pin `actual-speed` (RPS).
    pub actual_speed: f64,
    /// Pin `simulate-encoder`.
    pub simulate_encoder: bool,
    /// Pin `enable`.
    pub enable: bool,
    /// Pin `spindle-lpf`.
    pub spindle_lpf: f64,
    /// Pin `spindle-rpm` (read back).
    pub spindle_rpm: f64,
    /// Pin `spindle-rpm-abs` (read back).
    pub spindle_rpm_abs: f64,
    /// Pin `output`.
    pub output: f64,
    /// Pin `at-speed` (read back).
    pub at_speed: bool,
    /// Pin `forward` (read back).
    pub forward: bool,
    /// Pin `reverse`.
    pub reverse: bool,
    /// Pin `zero-speed`.
    pub zero_speed: bool,
    /// Pin `limited`.
    pub limited: bool,
}

/// The gear in use: `select-gear` if non-zero (LinuxCNC caps it at 15
/// and reads past its gears beyond the configured ones; here it is
/// capped at the last gear), else the highest `select.N` set, else 0.
pub fn current_gear(select_gear: u32, selects: &[bool]) -> usize {
    if select_gear != 0 {
        (select_gear as usize).min(15).min(selects.len() - 1)
    } else {
        (0..selects.len()).rev().find(|&g| selects[g]).unwrap_or(0)
    }
}

/// One call with gear `g`, `fperiod` seconds after the last.
pub fn spindle_step(v: &mut SpindleVars, g: &Gear, fperiod: f64) {
    if !v.simulate_encoder {
        v.spindle_rpm = v.actual_speed * 60.0;
    }
    let mut curspeed = v.spindle_rpm as f32;
    let mut cmdspeed = if v.enable {
        v.commanded_speed as f32
    } else {
        0.0
    };
    let abs = curspeed.abs();
    v.zero_speed = f64::from(abs) <= g.zero_tolerance;
    if v.spindle_lpf > 0.0 && v.at_speed {
        v.spindle_rpm_abs += (f64::from(abs) - v.spindle_rpm_abs) * v.spindle_lpf * fperiod;
    } else {
        v.spindle_rpm_abs = f64::from(abs);
    }
    let reversing = (cmdspeed > 0.0 && curspeed < 0.0) || (cmdspeed < 0.0 && curspeed > 0.0);

    let tol = g.speed_tolerance as f32;
    v.at_speed = tol > 0.0 && tol >= (cmdspeed - curspeed).abs() && !reversing;

    let mut limit = false;
    let min = g.min as f32;
    if min > 0.0 {
        if cmdspeed > 0.0 {
            if cmdspeed < min {
                cmdspeed = min;
                limit = true;
            }
        } else if cmdspeed < 0.0 && cmdspeed > -min {
            cmdspeed = -min;
            limit = true;
        }
    }
    let max = g.max as f32;
    if max > 0.0 {
        if cmdspeed > 0.0 && cmdspeed > max {
            cmdspeed = max;
            limit = true;
        }
        if cmdspeed < 0.0 && cmdspeed < -max {
            cmdspeed = -max;
            limit = true;
        }
    }

    let mut diff = cmdspeed - curspeed;
    // Never cross zero in one step.
    if curspeed > 0.0 && diff < -curspeed {
        diff = -curspeed;
    }
    if curspeed < 0.0 && diff > -curspeed {
        diff = -curspeed;
    }
    let per_step = |rate: f32| {
        if v.simulate_encoder {
            (f64::from(rate) * fperiod) as f32
        } else {
            rate
        }
    };
    let accel = g.accel as f32;
    if accel > 0.0 && !reversing {
        let a = per_step(accel);
        if cmdspeed > 0.0 && diff > a {
            diff = a;
        }
        if cmdspeed < 0.0 && diff < -a {
            diff = -a;
        }
    }
    let decel = g.decel as f32;
    if decel > 0.0 {
        let d = per_step(decel);
        if reversing {
            if cmdspeed >= 0.0 && diff > d {
                diff = d;
            }
            if cmdspeed <= 0.0 && diff < -d {
                diff = -d;
            }
        } else {
            if cmdspeed >= 0.0 && diff < -d {
                diff = -d;
            }
            if cmdspeed <= 0.0 && diff > d {
                diff = d;
            }
        }
    }
    if v.at_speed {
        curspeed = cmdspeed;
    } else {
        curspeed += diff;
    }
    if v.simulate_encoder {
        v.spindle_rpm = f64::from(curspeed);
    }
    if cmdspeed != 0.0 {
        v.forward = curspeed > 0.0;
        v.reverse = curspeed < 0.0;
    } else {
        // Once stopped, stay stopped. (LinuxCNC tests `forward` for
        // `reverse` too, so reverse drops as soon as the command is 0.)
        v.forward = curspeed > 0.0 && v.forward;
        v.reverse = curspeed < 0.0 && v.forward;
    }
    v.output = (f64::from(curspeed.abs()) + g.offset) * g.scale;
    v.limited = limit;
}

/// `numgears=`: gears of each instance.
const NUMGEARS: ParamDecl = ParamDecl {
    name: "numgears",
    kind: ParamKind::IntArray(16),
    help: "number of gears of each spindle (1 to 16)",
};

/// The module parameters: halcompile's `count=`/`names=` and
/// `numgears=`.
pub const PARAMS: &[ParamDecl] = &[
    crate::halcomp::PARAMS[0],
    crate::halcomp::PARAMS[1],
    NUMGEARS,
];

/// The pins of one gear.
struct GearPins {
    scale: Pin<f64, In>,
    min: Pin<f64, In>,
    max: Pin<f64, In>,
    accel: Pin<f64, In>,
    decel: Pin<f64, In>,
    speed_tolerance: Pin<f64, In>,
    zero_tolerance: Pin<f64, In>,
    offset: Pin<f64, In>,
    select: Pin<bool, In>,
}

/// The `spindle` component (its module takes `numgears=`, so it is
/// loaded by hand below rather than through `HalComp`).
pub struct SpindleComp;
impl SpindleComp {
    fn build_gears(inst: &mut Inst<'_, '_>, n: usize) -> Result<Vec<GearPins>> {
        let d = Gear::default();
        (0..n)
            .map(|g| {
                Ok(GearPins {
                    scale: inst.pin_in_init(&format!("scale.{g}"), d.scale)?,
                    min: inst.pin_in_init(&format!("min.{g}"), d.min)?,
                    max: inst.pin_in_init(&format!("max.{g}"), d.max)?,
                    accel: inst.pin_in_init(&format!("accel.{g}"), d.accel)?,
                    decel: inst.pin_in_init(&format!("decel.{g}"), d.decel)?,
                    speed_tolerance: inst
                        .pin_in_init(&format!("speed-tolerance.{g}"), d.speed_tolerance)?,
                    zero_tolerance: inst
                        .pin_in_init(&format!("zero-tolerance.{g}"), d.zero_tolerance)?,
                    offset: inst.pin_in_init(&format!("offset.{g}"), d.offset)?,
                    select: inst.pin_in_init(&format!("select.{g}"), n == 1)?,
                })
            })
            .collect()
    }

    fn build_with(inst: &mut Inst<'_, '_>, ngears: i64) -> Result<()> {
        if !(1..=MAX_GEARS as i64).contains(&ngears) {
            return Err(inst.bad_param(
                "numgears",
                format!("{}: {ngears} gears, 1 to {MAX_GEARS} allowed", inst.prefix),
            ));
        }
        let gears = Self::build_gears(inst, ngears as usize)?;
        let select_gear = inst.pin_in::<u32>("select-gear")?;
        let commanded_speed = inst.pin_in::<f64>("commanded-speed")?;
        let actual_speed = inst.pin_in::<f64>("actual-speed")?;
        let simulate_encoder = inst.pin_in::<bool>("simulate-encoder")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let spindle_lpf = inst.pin_in::<f64>("spindle-lpf")?;
        let spindle_rpm = inst.pin_out::<f64>("spindle-rpm")?;
        let spindle_rpm_abs = inst.pin_out::<f64>("spindle-rpm-abs")?;
        let output = inst.pin_out::<f64>("output")?;
        let current = inst.pin_out::<u32>("current-gear")?;
        let at_speed = inst.pin_out::<bool>("at-speed")?;
        let forward = inst.pin_out::<bool>("forward")?;
        let reverse = inst.pin_out::<bool>("reverse")?;
        // Declared by LinuxCNC but never driven.
        let _brake = inst.pin_out::<bool>("brake")?;
        let zero_speed = inst.pin_out::<bool>("zero-speed")?;
        let limited = inst.pin_out::<bool>("limited")?;
        let mut selects = vec![false; gears.len()];
        inst.funct("_", true, move |ctx| {
            for (s, g) in selects.iter_mut().zip(&gears) {
                *s = g.select.get();
            }
            let k = current_gear(select_gear.get(), &selects);
            current.set(k as u32);
            let gp = &gears[k];
            let g = Gear {
                scale: gp.scale.get(),
                min: gp.min.get(),
                max: gp.max.get(),
                accel: gp.accel.get(),
                decel: gp.decel.get(),
                speed_tolerance: gp.speed_tolerance.get(),
                zero_tolerance: gp.zero_tolerance.get(),
                offset: gp.offset.get(),
            };
            let mut v = SpindleVars {
                commanded_speed: commanded_speed.get(),
                actual_speed: actual_speed.get(),
                simulate_encoder: simulate_encoder.get(),
                enable: enable.get(),
                spindle_lpf: spindle_lpf.get(),
                spindle_rpm: spindle_rpm.get(),
                spindle_rpm_abs: spindle_rpm_abs.get(),
                output: output.get(),
                at_speed: at_speed.get(),
                forward: forward.get(),
                reverse: reverse.get(),
                zero_speed: zero_speed.get(),
                limited: limited.get(),
            };
            spindle_step(&mut v, &g, ctx.fperiod());
            spindle_rpm.set(v.spindle_rpm);
            spindle_rpm_abs.set(v.spindle_rpm_abs);
            zero_speed.set(v.zero_speed);
            at_speed.set(v.at_speed);
            forward.set(v.forward);
            reverse.set(v.reverse);
            output.set(v.output);
            limited.set(v.limited);
        })
    }
}

/// The `spindle` module.
pub static MODULE: hal_core::ModuleDef = hal_core::ModuleDef {
    name: "spindle",
    params: PARAMS,
    help: "control a spindle with acceleration, deceleration and gear scaling",
    load,
};

fn load(host: &hal_core::Host, args: &hal_core::ModuleArgs) -> Result<()> {
    let names = crate::halcomp::instance_names(MODULE.name, args)?;
    let numgears = args.int_array("numgears");
    let instances = names.into_iter().map(|n| (n, 0)).collect();
    crate::halcomp::load_instances(host, MODULE.name, instances, |inst, i| {
        SpindleComp::build_with(inst, numgears.get(i).copied().unwrap_or(1))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, U32};

    fn sim() -> SpindleVars {
        SpindleVars {
            simulate_encoder: true,
            enable: true,
            ..Default::default()
        }
    }

    #[test]
    fn gear_choice() {
        assert_eq!(current_gear(0, &[false, true, true]), 2);
        assert_eq!(current_gear(0, &[false; 3]), 0);
        assert_eq!(current_gear(1, &[false, false, true]), 1);
        assert_eq!(current_gear(9, &[false; 3]), 2, "capped at the last gear");
    }

    #[test]
    fn simulated_spindle_ramps_to_speed() {
        let g = Gear {
            accel: 1000.0,
            decel: 2000.0,
            ..Gear::default()
        };
        let mut v = sim();
        v.commanded_speed = 100.0;
        spindle_step(&mut v, &g, 0.001);
        assert_eq!(v.spindle_rpm, 1.0);
        assert!(v.forward && !v.reverse && !v.at_speed);
        for _ in 0..200 {
            spindle_step(&mut v, &g, 0.001);
        }
        assert!(v.at_speed && !v.zero_speed);
        assert_eq!(v.spindle_rpm, 100.0);
        assert_eq!(v.output, 100.0);
        // Stopping decelerates twice as fast, forward stays on meanwhile.
        v.enable = false;
        spindle_step(&mut v, &g, 0.001);
        assert_eq!(v.spindle_rpm, 98.0);
        assert!(v.forward);
    }

    #[test]
    fn limits_flag_and_reverse_through_zero() {
        let g = Gear {
            min: 50.0,
            max: 500.0,
            scale: 0.01,
            offset: 1.0,
            ..Gear::default()
        };
        let mut v = sim();
        v.commanded_speed = 10.0;
        spindle_step(&mut v, &g, 0.001);
        assert!(v.limited);
        assert_eq!(v.spindle_rpm, 50.0, "no accel limit: jumps to the minimum");
        assert_eq!(v.output, (50.0 + 1.0) * 0.01);
        // Reversing: first down to zero, never across it in one step.
        v.commanded_speed = -100.0;
        spindle_step(&mut v, &g, 0.001);
        assert_eq!(v.spindle_rpm, 0.0);
        spindle_step(&mut v, &g, 0.001);
        assert_eq!(v.spindle_rpm, -100.0);
        assert!(v.reverse && !v.forward);
    }

    #[test]
    fn encoder_feedback_drives_at_speed() {
        let g = Gear::default();
        let mut v = SpindleVars {
            enable: true,
            commanded_speed: 600.0,
            actual_speed: 9.9, // 594 RPM
            ..Default::default()
        };
        spindle_step(&mut v, &g, 0.001);
        assert!(v.at_speed, "within the 20 RPM tolerance");
        assert_eq!(v.spindle_rpm, 9.9 * 60.0);
    }

    #[test]
    fn pins_per_gear() {
        let h = TestHost::new("spindle");
        h.load(&MODULE, &["count=2", "numgears=2"]).unwrap();
        let mut want: Vec<String> = [
            "select-gear u32 in 0",
            "commanded-speed float in 0",
            "actual-speed float in 0",
            "simulate-encoder bit in 0",
            "enable bit in 0",
            "spindle-lpf float in 0",
            "spindle-rpm float out 0",
            "spindle-rpm-abs float out 0",
            "output float out 0",
            "current-gear u32 out 0",
            "at-speed bit out 0",
            "forward bit out 0",
            "reverse bit out 0",
            "brake bit out 0",
            "zero-speed bit out 0",
            "limited bit out 0",
        ]
        .map(String::from)
        .to_vec();
        for g in 0..2 {
            for p in [
                "scale float in 1",
                "min float in 0",
                "max float in 0",
                "accel float in 0",
                "decel float in 0",
                "speed-tolerance float in 20",
                "zero-tolerance float in 20",
                "offset float in 0",
                "select bit in 0",
            ] {
                let (name, rest) = p.split_once(' ').unwrap();
                want.push(format!("{name}.{g} {rest}"));
            }
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("spindle.0", &want);
        // One gear (the default for the second instance) is selected.
        assert_eq!(h.get("spindle.1.select.0"), Bit(true));
        assert!(h.items("spindle.1.scale.1").is_empty());
        let h = TestHost::new("spindle-bad");
        for bad in [
            &["numgears=17"][..],
            &["numgears=0"],
            &["count=1", "names=a"],
        ] {
            h.check_load_fails(&MODULE, bad);
        }
    }

    #[test]
    fn runs_in_a_thread() {
        let mut h = TestHost::new("spindle-run");
        h.load(&MODULE, &["names=sp"]).unwrap();
        h.thread(&["sp"]);
        h.set("sp.simulate-encoder", Bit(true));
        h.set("sp.enable", Bit(true));
        h.expect(
            &[("sp.commanded-speed", Float(300.0))],
            "sp.spindle-rpm",
            Float(300.0),
        );
        assert_eq!(h.get("sp.current-gear"), U32(0));
        assert_eq!(h.get("sp.at-speed"), Bit(true));
    }
}
