//! `joyhandle`: shapes a joystick axis: a dead band around zero, a
//! power curve (`power`, progressive or with `inverse` degressive) from
//! the dead band edge to full deflection, then `scale` and `offset`;
//! symmetric for negative deflection.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The params.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JoyParams {
    /// `power` (at least 1).
    pub power: f64,
    /// `deadband` (0 to 0.99).
    pub deadband: f64,
    /// `scale`.
    pub scale: f64,
    /// `offset`.
    pub offset: f64,
    /// `inverse`.
    pub inverse: bool,
}

impl Default for JoyParams {
    /// The params' defaults.
    fn default() -> Self {
        JoyParams {
            power: 2.0,
            deadband: 0.0,
            scale: 1.0,
            offset: 0.0,
            inverse: false,
        }
    }
}

impl JoyParams {
    /// Limits `power` and `deadband` to their valid ranges (the
    /// component writes the limited values back to the params).
    pub fn limited(mut self) -> JoyParams {
        if self.power < 1.0 {
            self.power = 1.0;
        }
        self.deadband = self.deadband.clamp(0.0, 0.99);
        self
    }
}

/// The output for deflection `x`, with already limited params.
pub fn joyhandle(x: f64, p: &JoyParams) -> f64 {
    let (db, scale, offset) = (p.deadband, p.scale, p.offset);
    let a = -1.0 / (db.powf(p.power - 1.0) - 1.0);
    let b = 1.0 - a;
    let alin = -scale / (db - 1.0);
    let clin = 1.0 * (scale + offset - alin);
    let curve = |x: f64| scale * (a * x.powf(p.power) + b * x) + offset;
    let mirrored = |x: f64| {
        let xm = (db + 1.0) / 2.0;
        let ym = alin * xm + clin;
        (ym, curve(2.0 * xm - x))
    };
    if x >= 1.0 {
        scale + offset
    } else if x <= db && x >= -db {
        0.0
    } else if x <= -1.0 {
        -scale - offset
    } else if x > db && x < 1.0 {
        if p.power == 1.0 {
            alin * x + clin
        } else if !p.inverse {
            curve(x)
        } else {
            let (ym, yinv) = mirrored(x);
            2.0 * ym - yinv
        }
    } else if x < -db && x > -1.0 {
        if p.power == 1.0 {
            -(-alin * x + clin)
        } else if !p.inverse {
            -(scale * (a * (-x).powf(p.power) - b * x) + offset)
        } else {
            let xm = (db + 1.0) / 2.0;
            let ym = alin * xm + clin;
            let yinv = curve(2.0 * xm + x);
            -2.0 * ym - yinv
        }
    } else {
        0.0
    }
}

/// The `joyhandle` component.
pub struct Joyhandle;
impl HalComp for Joyhandle {
    const NAME: &'static str = "joyhandle";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<f64>("in")?;
        let out = inst.pin_out::<f64>("out")?;
        let d = JoyParams::default();
        let power = inst.param_rw::<f64>("power", d.power)?;
        let deadband = inst.param_rw::<f64>("deadband", d.deadband)?;
        let scale = inst.param_rw::<f64>("scale", d.scale)?;
        let offset = inst.param_rw::<f64>("offset", d.offset)?;
        let inverse = inst.param_rw::<bool>("inverse", d.inverse)?;
        inst.funct("_", true, move |_| {
            let given = JoyParams {
                power: power.get(),
                deadband: deadband.get(),
                scale: scale.get(),
                offset: offset.get(),
                inverse: inverse.get(),
            };
            let p = given.limited();
            if p.power != given.power {
                power.set(p.power);
            }
            if p.deadband != given.deadband {
                deadband.set(p.deadband);
            }
            out.set(joyhandle(input.get(), &p));
        })
    }
}
halcomp_module!(pub MODULE, Joyhandle, "sets nonlinear joypad movements, deadbands and scales");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Float;

    #[test]
    fn curve_dead_band_ends_and_symmetry() {
        let p = JoyParams {
            deadband: 0.1,
            ..Default::default()
        };
        assert_eq!(joyhandle(0.05, &p), 0.0);
        assert_eq!(joyhandle(1.5, &p), 1.0);
        assert_eq!(joyhandle(-1.5, &p), -1.0);
        // Starts at 0 just past the dead band and reaches 1 at the end.
        assert!(joyhandle(0.1000001, &p).abs() < 1e-5);
        assert!((joyhandle(0.9999999, &p) - 1.0).abs() < 1e-5);
        assert_eq!(joyhandle(-0.5, &p), -joyhandle(0.5, &p));
        // Progressive: below the straight line in the middle.
        let lin = JoyParams { power: 1.0, ..p };
        assert!(joyhandle(0.5, &p) < joyhandle(0.5, &lin));
        let inv = JoyParams { inverse: true, ..p };
        assert!(joyhandle(0.5, &inv) > joyhandle(0.5, &lin));
    }

    #[test]
    fn params_are_limited() {
        let p = JoyParams {
            power: 0.5,
            deadband: 2.0,
            ..Default::default()
        }
        .limited();
        assert_eq!((p.power, p.deadband), (1.0, 0.99));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("joyhandle");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins("joyhandle.0", &["in float in 0", "out float out 0"]);
        h.check_params(
            "joyhandle.0",
            &[
                "power float rw 2",
                "deadband float rw 0",
                "scale float rw 1",
                "offset float rw 0",
                "inverse bit rw 0",
            ],
        );
        h.thread(&["joyhandle.0"]);
        h.setp("joyhandle.0.power", Float(0.0));
        h.expect(
            &[("joyhandle.0.in", Float(0.5))],
            "joyhandle.0.out",
            Float(0.5),
        );
        assert_eq!(h.getp("joyhandle.0.power"), Float(1.0));
    }
}
