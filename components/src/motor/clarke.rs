//! Clarke transforms between three-phase and two-axis (Cartesian)
//! quantities: `clarke3` (general, with the homopolar part), `clarke2`
//! (phases known to sum to zero, so two inputs suffice) and `clarkeinv`
//! (the inverse, with a rotation first). The constants are LinuxCNC's
//! 15-digit decimals, for identical results.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// 2/3.
const TWO_THIRDS: f64 = 0.666666666666667;
/// 1/3.
const ONE_THIRD: f64 = 0.333333333333333;
/// 1/sqrt(3).
const INV_SQRT3: f64 = 0.577350269189626;
/// 2/sqrt(3).
const TWO_INV_SQRT3: f64 = 1.15470053837925;
/// sqrt(2)/3.
const SQRT2_THIRD: f64 = 0.471404520791032;
/// sqrt(3)/2.
const SQRT3_HALF: f64 = 0.866025403784439;
/// 1/sqrt(2), to LinuxCNC's 15 digits (not the closest double).
#[allow(clippy::approx_constant)]
const INV_SQRT2: f64 = 0.707106781186547;
/// LinuxCNC's (slightly long) 2*pi for revolutions to radians.
const REV_TO_RAD: f64 = 6.283185308;

/// `clarke3`: (x, y, h) of phases a, b, c.
pub fn clarke3(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    (
        TWO_THIRDS * a - ONE_THIRD * (b + c),
        INV_SQRT3 * (b - c),
        SQRT2_THIRD * (a + b + c),
    )
}

/// `clarke2`: (x, y) of phases a and b when a + b + c = 0.
pub fn clarke2(a: f64, b: f64) -> (f64, f64) {
    (a, INV_SQRT3 * a + TWO_INV_SQRT3 * b)
}

/// `clarkeinv`: phases (a, b, c) of (x, y, h) rotated by `theta`
/// revolutions.
pub fn clarkeinv(x: f64, y: f64, h: f64, theta: f64) -> (f64, f64, f64) {
    let rads = theta * REV_TO_RAD;
    let (s, c) = (rads.sin(), rads.cos());
    let xr = x * c - y * s;
    let yr = x * s + y * c;
    (
        xr + INV_SQRT2 * h,
        -0.5 * xr + SQRT3_HALF * yr + INV_SQRT2 * h,
        -0.5 * xr - SQRT3_HALF * yr + INV_SQRT2 * h,
    )
}

/// The `clarke3` component.
pub struct Clarke3;
impl HalComp for Clarke3 {
    const NAME: &'static str = "clarke3";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let a = inst.pin_in::<f64>("a")?;
        let b = inst.pin_in::<f64>("b")?;
        let c = inst.pin_in::<f64>("c")?;
        let x = inst.pin_out::<f64>("x")?;
        let y = inst.pin_out::<f64>("y")?;
        let h = inst.pin_out::<f64>("h")?;
        inst.funct("_", true, move |_| {
            let (vx, vy, vh) = clarke3(a.get(), b.get(), c.get());
            x.set(vx);
            y.set(vy);
            h.set(vh);
        })
    }
}
halcomp_module!(pub CLARKE3, Clarke3, "Clarke (3 phase to cartesian) transform");

/// The `clarke2` component.
pub struct Clarke2;
impl HalComp for Clarke2 {
    const NAME: &'static str = "clarke2";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let a = inst.pin_in::<f64>("a")?;
        let b = inst.pin_in::<f64>("b")?;
        let x = inst.pin_out::<f64>("x")?;
        let y = inst.pin_out::<f64>("y")?;
        inst.funct("_", true, move |_| {
            let (vx, vy) = clarke2(a.get(), b.get());
            x.set(vx);
            y.set(vy);
        })
    }
}
halcomp_module!(pub CLARKE2, Clarke2, "two input version of Clarke transform");

/// The `clarkeinv` component.
pub struct ClarkeInv;
impl HalComp for ClarkeInv {
    const NAME: &'static str = "clarkeinv";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let x = inst.pin_in::<f64>("x")?;
        let y = inst.pin_in::<f64>("y")?;
        let h = inst.pin_in::<f64>("h")?;
        let theta = inst.pin_in::<f64>("theta")?;
        let a = inst.pin_out::<f64>("a")?;
        let b = inst.pin_out::<f64>("b")?;
        let c = inst.pin_out::<f64>("c")?;
        inst.funct("_", true, move |_| {
            let (va, vb, vc) = clarkeinv(x.get(), y.get(), h.get(), theta.get());
            a.set(va);
            b.set(vb);
            c.set(vc);
        })
    }
}
halcomp_module!(pub CLARKEINV, ClarkeInv, "inverse Clarke transform");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Float;

    #[test]
    fn forward_and_inverse_agree() {
        // A balanced three-phase vector at 30 degrees.
        let t = 30f64.to_radians();
        let ph = |k: f64| (t - k * 2.0 * std::f64::consts::PI / 3.0).cos();
        let (a, b, c) = (ph(0.0), ph(1.0), ph(2.0));
        let (x, y, h) = clarke3(a, b, c);
        assert!((x - t.cos()).abs() < 1e-9 && (y - t.sin()).abs() < 1e-9);
        assert!(h.abs() < 1e-9);
        let (x2, y2) = clarke2(a, b);
        assert!((x2 - x).abs() < 1e-9 && (y2 - y).abs() < 1e-9);
        let (ra, rb, rc) = clarkeinv(x, y, 0.0, 0.0);
        assert!((ra - a).abs() < 1e-9 && (rb - b).abs() < 1e-9 && (rc - c).abs() < 1e-9);
        // A quarter turn of rotation moves x onto y.
        let (a, _, _) = clarkeinv(1.0, 0.0, 0.0, 0.25);
        assert!(a.abs() < 1e-8);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("clarke");
        h.load(&CLARKE3, &[]).unwrap();
        h.load(&CLARKE2, &[]).unwrap();
        h.load(&CLARKEINV, &[]).unwrap();
        h.check_pins(
            "clarke3.0",
            &[
                "a float in 0",
                "b float in 0",
                "c float in 0",
                "x float out 0",
                "y float out 0",
                "h float out 0",
            ],
        );
        h.check_pins(
            "clarke2.0",
            &[
                "a float in 0",
                "b float in 0",
                "x float out 0",
                "y float out 0",
            ],
        );
        h.check_pins(
            "clarkeinv.0",
            &[
                "x float in 0",
                "y float in 0",
                "h float in 0",
                "theta float in 0",
                "a float out 0",
                "b float out 0",
                "c float out 0",
            ],
        );
        h.thread(&["clarke2.0"]);
        h.expect(&[("clarke2.0.a", Float(2.0))], "clarke2.0.x", Float(2.0));
        assert_eq!(h.get("clarke2.0.y"), Float(INV_SQRT3 * 2.0));
    }
}
