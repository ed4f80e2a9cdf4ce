//! `tripodkins`: three motors reel in wires (or drive struts) that meet
//! at the tool D. Motor A sits at the origin, B at (Bx, 0, 0) and C at
//! (Cx, Cy, 0); the joints are the lengths AD (joint 0), BD (joint 1)
//! and CD (joint 2).
//!
//! ```text
//! inverse:  AD = |D − A|   BD = |D − B|   CD = |D − C|
//! forward:  x = (AD² − BD² + Bx²) / (2·Bx)
//!           y = (AD² − CD² + Cx² + Cy² − 2·Cx·x) / (2·Cy)
//!           z = ±√(AD² − x² − y²)
//! ```
//!
//! The forward solution has two branches, mirrored in the motors' plane:
//! z ≥ 0 normally, z ≤ 0 when the forward flags are non-zero. Lengths
//! that do not meet in a point are refused, and so is a geometry whose
//! motors lie on one line (Bx = 0 or Cy = 0).
//!
//! Pins (float io, as LinuxCNC names them): `tripodkins.Bx` (default 1),
//! `tripodkins.Cx` (default 0.5) and `tripodkins.Cy` (default 1). Only
//! X, Y and Z are computed; the type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Io, Pin, Result};

use super::loader::{float_io, register};
use super::math::finite;
use super::pinned::{PinGeometry, Pinned};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `tripodkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "tripodkins",
    params: &[],
    help: "three wires from motors at (0,0,0), (Bx,0,0) and (Cx,Cy,0) to the tool",
    load,
};

/// A tripod of fixed geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tripod {
    /// X of motor B.
    pub bx: f64,
    /// X of motor C.
    pub cx: f64,
    /// Y of motor C.
    pub cy: f64,
}

impl Default for Tripod {
    fn default() -> Self {
        Tripod {
            bx: 1.0,
            cx: 0.5,
            cy: 1.0,
        }
    }
}

impl Kinematics for Tripod {
    fn name(&self) -> &str {
        "tripodkins"
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Both
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let [ad, bd, cd] = *joints.first_chunk().ok_or(KinsError::Unsupported)?;
        let Tripod { bx, cx, cy } = *self;
        finite(&[ad, bd, cd, bx, cx, cy])?;
        if bx == 0.0 || cy == 0.0 || ad < 0.0 || bd < 0.0 || cd < 0.0 {
            return Err(KinsError::NoSolution);
        }
        let x = (ad * ad - bd * bd + bx * bx) / (2.0 * bx);
        let y = (ad * ad - cd * cd + cx * cx + cy * cy - 2.0 * cx * x) / (2.0 * cy);
        let z2 = ad * ad - x * x - y * y;
        if z2.is_nan() || z2 < 0.0 {
            return Err(KinsError::NoSolution);
        }
        let z = if flags.forward == 0 {
            z2.sqrt()
        } else {
            -z2.sqrt()
        };
        finite(&[x, y, z])?;
        pose.0[0] = x;
        pose.0[1] = y;
        pose.0[2] = z;
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let slots: &mut [f64; 3] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        let (x, y, z) = (pose.0[0], pose.0[1], pose.0[2]);
        let Tripod { bx, cx, cy } = *self;
        finite(&[x, y, z, bx, cx, cy])?;
        let ad = (x * x + y * y + z * z).sqrt();
        let bd = ((x - bx).powi(2) + y * y + z * z).sqrt();
        let cd = ((x - cx).powi(2) + (y - cy).powi(2) + z * z).sqrt();
        finite(&[ad, bd, cd])?;
        *slots = [ad, bd, cd];
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 3)
    }
}

/// The module's kinematics: the geometry read from its pins at every
/// call.
struct Tripodkins {
    bx: Pin<f64, Io>,
    cx: Pin<f64, Io>,
    cy: Pin<f64, Io>,
}

impl PinGeometry for Tripodkins {
    const NAME: &'static str = "tripodkins";
    type Geometry = Tripod;

    fn geometry(&self) -> Tripod {
        Tripod {
            bx: self.bx.get(),
            cx: self.cx.get(),
            cy: self.cy.get(),
        }
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("tripodkins")?;
    let d = Tripod::default();
    let bx = float_io(b.component(), "tripodkins.Bx", d.bx)?;
    let cx = float_io(b.component(), "tripodkins.Cx", d.cx)?;
    let cy = float_io(b.component(), "tripodkins.Cy", d.cy)?;
    register(
        host,
        b,
        "tripodkins",
        Arc::new(Pinned(Tripodkins { bx, cx, cy })),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(k: &Tripod, j: [f64; 3]) -> std::result::Result<[f64; 3], KinsError> {
        crate::kins::testing::forward(k, &j)
    }

    fn inv(k: &Tripod, p: [f64; 3]) -> std::result::Result<[f64; 3], KinsError> {
        crate::kins::testing::inverse(k, &p, [0.0; 3])
    }

    /// tklinuxcnc's tripod.ini geometry.
    const SAMPLE: Tripod = Tripod {
        bx: 10.0,
        cx: 5.0,
        cy: 7.071,
    };

    #[test]
    fn equal_lengths_put_the_tool_over_the_motors_circumcentre() {
        // Every joint homes at 6.123 in the sample configuration.
        let p = fwd(&SAMPLE, [6.123; 3]).unwrap();
        assert!((p[0] - 5.0).abs() < 1e-12, "{p:?}");
        let cy = SAMPLE.cy;
        let y = (cy * cy - 25.0) / (2.0 * cy);
        assert!((p[1] - y).abs() < 1e-12, "{p:?}");
        assert!(p[2] > 0.0);
        let j = inv(&SAMPLE, p).unwrap();
        assert!(j.iter().all(|l| (l - 6.123).abs() < 1e-12), "{j:?}");
    }

    #[test]
    fn the_forward_flags_pick_the_mirror_branch() {
        let mut pose = Pose::ZERO;
        let mut flags = KinsFlags {
            forward: 1,
            inverse: 0,
        };
        SAMPLE.forward(&[6.123; 3], &mut pose, &mut flags).unwrap();
        let up = fwd(&SAMPLE, [6.123; 3]).unwrap();
        assert_eq!(pose.0[2], -up[2]);
    }

    #[test]
    fn lengths_that_do_not_meet_and_flat_geometry_are_refused() {
        // Too short to reach each other.
        assert_eq!(fwd(&SAMPLE, [1.0, 1.0, 1.0]), Err(KinsError::NoSolution));
        assert_eq!(fwd(&SAMPLE, [-1.0, 9.0, 9.0]), Err(KinsError::NoSolution));
        assert_eq!(
            fwd(&SAMPLE, [f64::NAN, 9.0, 9.0]),
            Err(KinsError::NoSolution)
        );
        let flat = Tripod { cy: 0.0, ..SAMPLE };
        assert_eq!(fwd(&flat, [6.0, 6.0, 6.0]), Err(KinsError::NoSolution));
        let mut p = Pose::ZERO;
        assert_eq!(
            SAMPLE.forward(&[1.0, 1.0], &mut p, &mut KinsFlags::default()),
            Err(KinsError::Unsupported)
        );
    }

    proptest! {
        #[test]
        fn round_trips_above_the_motors(
            x in -20.0f64..20.0, y in -20.0f64..20.0, z in 0.01f64..20.0,
        ) {
            let j = inv(&SAMPLE, [x, y, z]).unwrap();
            let p = fwd(&SAMPLE, j).unwrap();
            prop_assert!((p[0] - x).abs() < 1e-6 && (p[1] - y).abs() < 1e-6
                && (p[2] - z).abs() < 1e-6, "{:?} vs {} {} {}", p, x, y, z);
        }
    }
}
