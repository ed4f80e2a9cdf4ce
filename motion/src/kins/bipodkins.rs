//! `bipodkins`: the bipod of the kinematics note. Two motors on a wall,
//! A at (0, 0) and B at (Bx, 0), reel in wires that hold the tool D; the
//! joints are the wire lengths AD (joint 0) and BD (joint 1). World Y
//! points down the wall, so the tool hangs at positive Y.
//!
//! ```text
//! inverse:  AD = √(x² + y²)            BD = √((Bx − x)² + y²)
//! forward:  x = (AD² − BD² + Bx²) / (2·Bx)
//!           y = +√(AD² − x²)           (the branch below the motors)
//! ```
//!
//! Poses on or above the motor line (y ≤ 0) are refused: the wires cannot
//! push, and on the line their pull is singular. Wire lengths that do not
//! make a triangle with the motors are refused by the forward kinematics.
//!
//! Pin (LinuxCNC names the motor positions of its tripodkins the same
//! way): `bipodkins.Bx` (float io, default 1), the distance between the
//! motors. Only X and Y are computed; the type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Io, Pin, Result};

use super::loader::{float_io, register};
use super::math::finite;
use super::pinned::{PinGeometry, Pinned};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `bipodkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "bipodkins",
    params: &[],
    help: "two-wire bipod hanging from motors at (0,0) and (Bx,0)",
    load,
};

/// Default distance between the motors.
pub const DEFAULT_BX: f64 = 1.0;

/// A bipod of fixed geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bipod {
    /// X of motor B (motor A is at the origin); must be positive.
    pub bx: f64,
}

impl Default for Bipod {
    fn default() -> Self {
        Bipod { bx: DEFAULT_BX }
    }
}

impl Kinematics for Bipod {
    fn name(&self) -> &str {
        "bipodkins"
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Both
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let [ad, bd] = *joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(&[ad, bd, self.bx])?;
        if self.bx <= 0.0 || ad < 0.0 || bd < 0.0 {
            return Err(KinsError::NoSolution);
        }
        let x = (ad * ad - bd * bd + self.bx * self.bx) / (2.0 * self.bx);
        let y2 = ad * ad - x * x;
        // y² = 0: the tool on the motor line, where the wires are straight.
        if y2.is_nan() || y2 <= 0.0 {
            return Err(KinsError::NoSolution);
        }
        let y = y2.sqrt();
        finite(&[x, y])?;
        pose.0[0] = x;
        pose.0[1] = y;
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let [ad_slot, bd_slot] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        let (x, y) = (pose.0[0], pose.0[1]);
        finite(&[x, y, self.bx])?;
        if self.bx <= 0.0 || y <= 0.0 {
            return Err(KinsError::NoSolution);
        }
        let ad = x.hypot(y);
        let bd = (self.bx - x).hypot(y);
        finite(&[ad, bd])?;
        *ad_slot = ad;
        *bd_slot = bd;
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 2)
    }
}

/// The module's kinematics: the geometry read from `bipodkins.Bx` at
/// every call.
struct Bipodkins {
    bx: Pin<f64, Io>,
}

impl PinGeometry for Bipodkins {
    const NAME: &'static str = "bipodkins";
    type Geometry = Bipod;

    fn geometry(&self) -> Bipod {
        Bipod { bx: self.bx.get() }
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("bipodkins")?;
    let bx = float_io(b.component(), "bipodkins.Bx", DEFAULT_BX)?;
    register(host, b, "bipodkins", Arc::new(Pinned(Bipodkins { bx })))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(k: &Bipod, j: [f64; 2]) -> std::result::Result<[f64; 2], KinsError> {
        crate::kins::testing::forward(k, &j)
    }

    fn inv(k: &Bipod, x: f64, y: f64) -> std::result::Result<[f64; 2], KinsError> {
        crate::kins::testing::inverse(k, &[x, y], [0.0; 2])
    }

    #[test]
    fn the_notes_worked_example() {
        // Motors 10 apart, tool 4 below the middle: both wires √(5² + 4²).
        let k = Bipod { bx: 10.0 };
        let j = inv(&k, 5.0, 4.0).unwrap();
        assert!((j[0] - 41f64.sqrt()).abs() < 1e-12 && (j[1] - j[0]).abs() < 1e-12);
        let p = fwd(&k, [3.0, 109f64.sqrt()]).unwrap();
        assert!((p[0] - 0.0).abs() < 1e-12 && (p[1] - 3.0).abs() < 1e-12);
    }

    #[test]
    fn singular_and_unreachable_poses_are_refused() {
        let k = Bipod { bx: 10.0 };
        // On and above the motor line.
        assert_eq!(inv(&k, 5.0, 0.0), Err(KinsError::NoSolution));
        assert_eq!(inv(&k, 5.0, -1.0), Err(KinsError::NoSolution));
        // Wires too short to meet, exactly straight, or negative.
        assert_eq!(fwd(&k, [3.0, 3.0]).unwrap_err(), KinsError::NoSolution);
        assert_eq!(fwd(&k, [4.0, 6.0]).unwrap_err(), KinsError::NoSolution);
        assert_eq!(fwd(&k, [-6.0, 6.0]).unwrap_err(), KinsError::NoSolution);
        assert_eq!(fwd(&k, [f64::NAN, 6.0]).unwrap_err(), KinsError::NoSolution);
        // No motor spacing.
        let flat = Bipod { bx: 0.0 };
        assert_eq!(inv(&flat, 0.0, 1.0), Err(KinsError::NoSolution));
        assert_eq!(fwd(&flat, [1.0, 1.0]).unwrap_err(), KinsError::NoSolution);
        // One joint is not a bipod.
        let mut p = Pose::ZERO;
        assert_eq!(
            k.forward(&[1.0], &mut p, &mut KinsFlags::default()),
            Err(KinsError::Unsupported)
        );
    }

    proptest! {
        #[test]
        fn round_trips_below_the_motors(
            bx in 0.1f64..1000.0, fx in -2.0f64..3.0, fy in 0.01f64..3.0,
        ) {
            let k = Bipod { bx };
            let (x, y) = (fx * bx, fy * bx);
            let j = inv(&k, x, y).unwrap();
            let p = fwd(&k, j).unwrap();
            prop_assert!((p[0] - x).abs() < 1e-9 * bx && (p[1] - y).abs() < 1e-9 * bx,
                "{:?} vs {} {}", p, x, y);
            let j2 = inv(&k, p[0], p[1]).unwrap();
            prop_assert!((j2[0] - j[0]).abs() < 1e-9 * bx && (j2[1] - j[1]).abs() < 1e-9 * bx);
        }
    }
}
