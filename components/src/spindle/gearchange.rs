//! `gearchange`: the motor speed for a spindle with several gear ranges.
//! The gear comes from `sel` (gear 2, for the old two-gear version),
//! `gear-number`, or the highest `gear-N-sel` set (gear 0 when none); the
//! absolute requested speed is clamped to that gear's `minN`/`maxN`,
//! multiplied by its `scaleN`, given back its sign, and ramped at `accN`
//! (rpm/s, 0 for no limit). `personality` is the number of gears (2 when
//! not given, at most 31).

use hal_core::{In, Param, Pin, Result, Rw};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most gears an instance may have (gears 0..=31 make 32 array entries).
pub const MAX_GEARS: i64 = 31;

/// The parameters of one gear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear {
    /// `minN`: lowest absolute speed.
    pub min: f64,
    /// `maxN`: highest absolute speed.
    pub max: f64,
    /// `accN`: acceleration limit, 0 for none.
    pub acc: f64,
    /// `scaleN`: the ratio; 0 counts as 1, negative reverses `dir-out`.
    pub scale: f64,
}

impl Default for Gear {
    /// The params' defaults.
    fn default() -> Self {
        Gear {
            min: 0.0,
            max: 100000.0,
            acc: 0.0,
            scale: 1.0,
        }
    }
}

/// The gear selected by `sel`, `gear-number` and the `gear-N-sel` bits
/// (`sel_bits[n]` is gear-n-sel). LinuxCNC reads past its arrays when
/// `gear-number` (or `sel` with a single gear) names a gear that does not
/// exist; here that selects gear 0.
pub fn select_gear(sel: bool, gear_number: u32, sel_bits: &[bool]) -> usize {
    let gears = sel_bits.len() - 1;
    let gear = if sel {
        2
    } else if gear_number != 0 {
        gear_number as usize
    } else {
        (1..=gears).rev().find(|&g| sel_bits[g]).unwrap_or(0)
    };
    if gear > gears {
        0
    } else {
        gear
    }
}

/// The outputs of one call.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearOut {
    /// `speed-out`.
    pub speed_out: f64,
    /// `speed-filtered`: the clamped absolute requested speed.
    pub speed_filtered: f64,
    /// `min-lim`.
    pub min_lim: bool,
    /// `max-lim`.
    pub max_lim: bool,
    /// `dir-out`.
    pub dir_out: bool,
    /// `accel-limit`.
    pub accel_limit: f64,
}

/// Per-instance state: the last speed sent, kept in single precision as
/// LinuxCNC's `float` variable is.
#[derive(Debug, Clone, Default)]
pub struct Gearchange {
    old_speed: f32,
}

impl Gearchange {
    /// One call for gear number `gear` with parameters `g`.
    pub fn step(
        &mut self,
        speed_in: f64,
        dir_in: bool,
        reverse: bool,
        gear: usize,
        g: Gear,
        fperiod: f64,
    ) -> GearOut {
        let mut speed_filtered = speed_in.abs();
        let (min_lim, max_lim) = if speed_filtered > g.max {
            speed_filtered = g.max;
            (false, true)
        } else if speed_filtered < g.min {
            speed_filtered = g.min;
            (true, false)
        } else {
            (false, false)
        };
        let scale = if g.scale != 0.0 { g.scale } else { 1.0 };
        let sign = if speed_in < 0.0 { -1.0 } else { 1.0 };
        let target = speed_filtered * scale * sign;
        let old = f64::from(self.old_speed);
        let delta = g.acc * fperiod * if target > old { 1.0 } else { -1.0 };
        self.old_speed = if g.acc != 0.0 && (target - old).abs() > delta.abs() {
            (old + delta) as f32
        } else {
            target as f32
        };
        let mut dir_out = if g.scale < 0.0 { !dir_in } else { dir_in };
        if reverse && gear == 2 {
            dir_out = !dir_out;
        }
        GearOut {
            speed_out: f64::from(self.old_speed),
            speed_filtered,
            min_lim,
            max_lim,
            dir_out,
            accel_limit: g.acc,
        }
    }
}

/// The params of one gear.
struct GearParams {
    min: Param<f64, Rw>,
    max: Param<f64, Rw>,
    acc: Param<f64, Rw>,
    scale: Param<f64, Rw>,
}

/// The `gearchange` component.
pub struct GearchangeComp;
impl HalComp for GearchangeComp {
    const NAME: &'static str = "gearchange";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let gears = if inst.personality == 0 {
            2
        } else {
            inst.personality
        };
        let n = inst.array_len(MAX_GEARS as usize + 1, gears + 1)?;
        let speed_in = inst.pin_in::<f64>("speed-in")?;
        let speed_out = inst.pin_out::<f64>("speed-out")?;
        let sel_bits: Vec<Pin<bool, In>> = (0..n)
            .map(|g| inst.pin_in(&format!("gear-{g}-sel")))
            .collect::<Result<_>>()?;
        let sel = inst.pin_in::<bool>("sel")?;
        let dir_in = inst.pin_in::<bool>("dir-in")?;
        let dir_out = inst.pin_out::<bool>("dir-out")?;
        let min_lim = inst.pin_out::<bool>("min-lim")?;
        let max_lim = inst.pin_out::<bool>("max-lim")?;
        let gear_number = inst.pin_in::<u32>("gear-number")?;
        let speed_filtered = inst.pin_out::<f64>("speed-filtered")?;
        let accel_limit = inst.pin_out::<f64>("accel-limit")?;
        let d = Gear::default();
        let mut params = Vec::with_capacity(n);
        for g in 0..n {
            params.push(GearParams {
                min: inst.param_rw(&format!("min{g}"), d.min)?,
                max: inst.param_rw(&format!("max{g}"), d.max)?,
                acc: inst.param_rw(&format!("acc{g}"), d.acc)?,
                scale: inst.param_rw(&format!("scale{g}"), d.scale)?,
            });
        }
        let reverse = inst.param_rw::<bool>("reverse", false)?;
        let mut bits = vec![false; n];
        let mut state = Gearchange::default();
        inst.funct("_", true, move |ctx| {
            for (b, p) in bits.iter_mut().zip(&sel_bits) {
                *b = p.get();
            }
            let gear = select_gear(sel.get(), gear_number.get(), &bits);
            let p = &params[gear];
            let g = Gear {
                min: p.min.get(),
                max: p.max.get(),
                acc: p.acc.get(),
                scale: p.scale.get(),
            };
            let o = state.step(
                speed_in.get(),
                dir_in.get(),
                reverse.get(),
                gear,
                g,
                ctx.fperiod(),
            );
            speed_filtered.set(o.speed_filtered);
            max_lim.set(o.max_lim);
            min_lim.set(o.min_lim);
            speed_out.set(o.speed_out);
            dir_out.set(o.dir_out);
            accel_limit.set(o.accel_limit);
        })
    }
}
halcomp_module!(pub MODULE, GearchangeComp, "select from several speed ranges");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, U32};

    #[test]
    fn gear_selection_priorities() {
        let bits = [false, true, false, true];
        assert_eq!(select_gear(false, 0, &bits), 3, "highest set bit wins");
        assert_eq!(select_gear(false, 1, &bits), 1, "gear-number beats bits");
        assert_eq!(select_gear(true, 1, &bits), 2, "sel beats everything");
        assert_eq!(select_gear(false, 0, &[false; 4]), 0);
        assert_eq!(select_gear(false, 9, &bits), 0, "no such gear");
        assert_eq!(
            select_gear(true, 0, &[false, false]),
            0,
            "one gear: no gear 2"
        );
    }

    #[test]
    fn clamps_scales_and_keeps_sign() {
        let mut s = Gearchange::default();
        let g = Gear {
            min: 100.0,
            max: 1000.0,
            acc: 0.0,
            scale: 2.5,
        };
        let o = s.step(-50.0, false, false, 1, g, 0.001);
        assert_eq!(
            (o.speed_filtered, o.min_lim, o.max_lim),
            (100.0, true, false)
        );
        assert_eq!(o.speed_out, -250.0);
        let o = s.step(5000.0, true, false, 1, g, 0.001);
        assert_eq!(
            (o.speed_filtered, o.min_lim, o.max_lim),
            (1000.0, false, true)
        );
        assert_eq!((o.speed_out, o.dir_out), (2500.0, true));
        // A negative scale reverses the direction; scale 0 counts as 1.
        let o = s.step(500.0, true, false, 1, Gear { scale: -1.0, ..g }, 0.001);
        assert_eq!((o.speed_out, o.dir_out), (-500.0, false));
        let o = s.step(500.0, true, false, 1, Gear { scale: 0.0, ..g }, 0.001);
        assert_eq!((o.speed_out, o.dir_out), (500.0, true));
        // `reverse` flips gear 2 only.
        assert!(!s.step(500.0, true, true, 2, g, 0.001).dir_out);
        assert!(s.step(500.0, true, true, 1, g, 0.001).dir_out);
    }

    #[test]
    fn ramps_at_the_gear_acceleration_in_single_precision() {
        let mut s = Gearchange::default();
        let g = Gear {
            acc: 1000.0,
            ..Gear::default()
        };
        let o = s.step(10.0, false, false, 1, g, 0.001);
        assert_eq!((o.speed_out, o.accel_limit), (1.0, 1000.0));
        assert_eq!(s.step(10.0, false, false, 1, g, 0.001).speed_out, 2.0);
        // Within one step of the target: jumps to it.
        for _ in 0..7 {
            s.step(10.0, false, false, 1, g, 0.001);
        }
        assert_eq!(s.step(10.0, false, false, 1, g, 0.001).speed_out, 10.0);
        // The remembered speed is an f32.
        let o = s.step(0.1, false, false, 1, Gear::default(), 0.001);
        assert_eq!(o.speed_out, f64::from(0.1f32));
    }

    #[test]
    fn pins_params_and_personality() {
        let mut h = TestHost::new("gearchange");
        h.load(&MODULE, &["count=2", "personality=0,3"]).unwrap();
        h.check_pins(
            "gearchange.0",
            &[
                "speed-in float in 0",
                "speed-out float out 0",
                "gear-0-sel bit in 0",
                "gear-1-sel bit in 0",
                "gear-2-sel bit in 0",
                "sel bit in 0",
                "dir-in bit in 0",
                "dir-out bit out 0",
                "min-lim bit out 0",
                "max-lim bit out 0",
                "gear-number u32 in 0",
                "speed-filtered float out 0",
                "accel-limit float out 0",
            ],
        );
        let mut want = vec!["reverse bit rw 0".to_string()];
        for g in 0..3 {
            want.push(format!("min{g} float rw 0"));
            want.push(format!("max{g} float rw 100000"));
            want.push(format!("acc{g} float rw 0"));
            want.push(format!("scale{g} float rw 1"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_params("gearchange.0", &want);
        assert!(h.items("gearchange.1.gear-3-sel").len() == 1);
        assert!(h.items("gearchange.1.gear-4-sel").is_empty());
        let h2 = TestHost::new("gearchange-max");
        h2.check_load_fails(&MODULE, &["names=big", "personality=32"]);
        h2.load(&MODULE, &["names=most", "personality=31"]).unwrap();
        assert_eq!(h2.items("most.gear-31-sel").len(), 1);

        h.thread(&["gearchange.1"]);
        h.setp("gearchange.1.scale3", Float(0.5));
        h.set("gearchange.1.gear-3-sel", Bit(true));
        h.expect(
            &[("gearchange.1.speed-in", Float(800.0))],
            "gearchange.1.speed-out",
            Float(400.0),
        );
        h.expect(
            &[("gearchange.1.gear-number", U32(1))],
            "gearchange.1.speed-out",
            Float(800.0),
        );
    }
}
