//! `lineardeltakins`: linear delta robots (Rostock style). Three towers
//! stand on a circle of radius R, tower 0 at (0, R) and the others 120°
//! on either side; a carriage rides up each tower (joints 0–2, its
//! height) and a rod of length L joins it to the effector, which hangs
//! below the carriages. Joints 3–8, when present, are A B C U V W one to
//! one.
//!
//! ```text
//! inverse:  j_i = Z + √(L² − (Tx_i − X)² − (Ty_i − Y)²)
//! forward:  the effector is the lower of the two points at distance L
//!           from the three carriages
//! ```
//!
//! Pins (float in, LinuxCNC's names and defaults): `lineardeltakins.R`
//! 130.25 (the effective tower radius: rod centres to effector centre)
//! and `lineardeltakins.L` 269 (rod length). Type KINEMATICS_BOTH.
//!
//! Refused: positions a rod cannot reach or reaches only lying flat (its
//! pull is then singular), carriage heights whose rods do not meet below
//! them, and non-positive dimensions.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Pin, Result};

use super::loader::{float_in, register};
use super::math::{below_plane, finite, lower_sphere_intersection};
use super::pinned::{PinGeometry, Pinned};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The `lineardeltakins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "lineardeltakins",
    params: &[],
    help: "linear delta robot kinematics (pins R and L)",
    load,
};

/// LinuxCNC's default radius: 198.25 − 33 − 35 (smooth rod offset less
/// the effector's and the carriages' joint offsets).
pub const DEFAULT_R: f64 = 198.25 - 33.0 - 35.0;

/// LinuxCNC's default rod length.
pub const DEFAULT_L: f64 = 269.0;

/// The fewest joints (the three carriages).
pub const MIN_JOINTS: usize = 3;

/// A linear delta of fixed geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearDelta {
    /// Tower radius.
    pub r: f64,
    /// Rod length.
    pub l: f64,
}

impl Default for LinearDelta {
    fn default() -> Self {
        LinearDelta {
            r: DEFAULT_R,
            l: DEFAULT_L,
        }
    }
}

impl LinearDelta {
    /// The XY positions of the three towers.
    pub fn towers(&self) -> [[f64; 2]; 3] {
        let (s, c) = (60f64.to_radians().sin(), 0.5);
        [
            [0.0, self.r],
            [-s * self.r, -c * self.r],
            [s * self.r, -c * self.r],
        ]
    }

    fn check(&self) -> std::result::Result<(), KinsError> {
        finite(&[self.r, self.l])?;
        if self.r > 0.0 && self.l > 0.0 {
            Ok(())
        } else {
            Err(KinsError::NoSolution)
        }
    }
}

impl Kinematics for LinearDelta {
    fn name(&self) -> &str {
        "lineardeltakins"
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
        if joints.len() < MIN_JOINTS {
            return Err(KinsError::Unsupported);
        }
        let n = joints.len().min(NUM_AXES);
        finite(&joints[..n])?;
        self.check()?;
        let t = self.towers();
        let centers = [0, 1, 2].map(|i| [t[i][0], t[i][1], joints[i]]);
        let p = lower_sphere_intersection(centers, self.l).ok_or(KinsError::NoSolution)?;
        // Every rod must hang down from its carriage, as the inverse
        // kinematics assume.
        if joints[..3].iter().any(|&j| j <= p[2]) {
            return Err(KinsError::NoSolution);
        }
        pose.0[..3].copy_from_slice(&p);
        pose.0[3..n].copy_from_slice(&joints[3..n]);
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        if joints.len() < MIN_JOINTS {
            return Err(KinsError::Unsupported);
        }
        let n = joints.len().min(NUM_AXES);
        finite(&pose.0[..n])?;
        self.check()?;
        let [x, y, z, ..] = pose.0;
        let mut carriage = [0.0; 3];
        for (c, [tx, ty]) in carriage.iter_mut().zip(self.towers()) {
            let rise2 = self.l * self.l - (tx - x) * (tx - x) - (ty - y) * (ty - y);
            if rise2.is_nan() || rise2 <= 0.0 {
                return Err(KinsError::NoSolution);
            }
            *c = z + rise2.sqrt();
        }
        finite(&carriage)?;
        // The forward kinematics give the meeting point below the
        // carriages' plane: a position above it is not theirs.
        let t = self.towers();
        let points = [0, 1, 2].map(|i| [t[i][0], t[i][1], carriage[i]]);
        if !below_plane([x, y, z], points) {
            return Err(KinsError::NoSolution);
        }
        joints[..3].copy_from_slice(&carriage);
        joints[3..n].copy_from_slice(&pose.0[3..n]);
        Ok(())
    }

    /// X, Y and Z always; A to W only with enough joints, which the
    /// module does not know.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        match axis {
            0..=2 => Some(true),
            3..=8 => None,
            _ => Some(false),
        }
    }
}

/// The module's kinematics: R and L read from the pins at every call.
struct Lineardeltakins {
    r: Pin<f64, In>,
    l: Pin<f64, In>,
}

impl PinGeometry for Lineardeltakins {
    const NAME: &'static str = "lineardeltakins";
    type Geometry = LinearDelta;

    fn geometry(&self) -> LinearDelta {
        LinearDelta {
            r: self.r.get(),
            l: self.l.get(),
        }
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("lineardeltakins")?;
    let c = b.component();
    let kins = Lineardeltakins {
        r: float_in(c, "lineardeltakins.R", DEFAULT_R)?,
        l: float_in(c, "lineardeltakins.L", DEFAULT_L)?,
    };
    register(host, b, "lineardeltakins", Arc::new(Pinned(kins)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn inv(k: &LinearDelta, p: [f64; 3]) -> std::result::Result<[f64; 3], KinsError> {
        crate::kins::testing::inverse(k, &p, [0.0; 3])
    }

    fn fwd(k: &LinearDelta, j: [f64; 3]) -> std::result::Result<[f64; 3], KinsError> {
        crate::kins::testing::forward(k, &j)
    }

    #[test]
    fn centred_effector_hangs_below_equal_carriages() {
        let k = LinearDelta::default();
        let rise = (DEFAULT_L * DEFAULT_L - DEFAULT_R * DEFAULT_R).sqrt();
        let j = inv(&k, [0.0, 0.0, 10.0]).unwrap();
        for ji in j {
            assert!((ji - (10.0 + rise)).abs() < 1e-9);
        }
        let p = fwd(&k, [300.0; 3]).unwrap();
        assert!(p[0].abs() < 1e-9 && p[1].abs() < 1e-9);
        assert!((p[2] - (300.0 - rise)).abs() < 1e-9);
        // Moving towards tower 0 (+Y) raises its carriage the most.
        let j = inv(&k, [0.0, 50.0, 0.0]).unwrap();
        assert!(j[0] > j[1] && (j[1] - j[2]).abs() < 1e-9);
    }

    #[test]
    fn out_of_reach_is_refused() {
        let k = LinearDelta::default();
        assert_eq!(inv(&k, [0.0, -300.0, 0.0]), Err(KinsError::NoSolution));
        // Exactly at rod's length from tower 0: the rod lies flat.
        assert_eq!(
            inv(&k, [0.0, DEFAULT_R - DEFAULT_L, 0.0]),
            Err(KinsError::NoSolution)
        );
        // Carriages too far apart for the rods to meet.
        assert_eq!(fwd(&k, [0.0, 0.0, 1000.0]), Err(KinsError::NoSolution));
        assert_eq!(inv(&k, [f64::NAN, 0.0, 0.0]), Err(KinsError::NoSolution));
        let bad = LinearDelta { r: 0.0, l: 269.0 };
        assert_eq!(inv(&bad, [0.0; 3]), Err(KinsError::NoSolution));
    }

    #[test]
    fn extra_joints_pass_through() {
        let k = LinearDelta::default();
        let mut pose = Pose([0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let mut j = [0.0; 9];
        k.inverse(&pose, &mut j, &mut KinsFlags::default()).unwrap();
        assert_eq!(j[3..], [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        pose = Pose::ZERO;
        k.forward(&j[..5], &mut pose, &mut KinsFlags::default())
            .unwrap();
        assert_eq!(pose.0[3..], [1.0, 2.0, 0.0, 0.0, 0.0, 0.0]);
    }

    fn check(k: LinearDelta, fx: f64, fy: f64, z: f64) -> std::result::Result<(), TestCaseError> {
        // Anywhere inside 90% of the circle the rods reach over the whole
        // tower triangle (L > 2R keeps every point in reach).
        let p = [fx * k.r, fy * k.r, z];
        let j = inv(&k, p).unwrap();
        let back = fwd(&k, j).unwrap();
        let tol = 1e-9 * (k.l + z.abs());
        for a in 0..3 {
            prop_assert!((back[a] - p[a]).abs() < tol, "{:?} vs {:?}", back, p);
        }
        let j2 = inv(&k, back).unwrap();
        for i in 0..3 {
            prop_assert!((j2[i] - j[i]).abs() < tol);
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn round_trips_with_the_default_geometry(
            r in 0.0f64..0.9, t in 0.0f64..std::f64::consts::TAU, z in -500.0f64..500.0,
        ) {
            // The default rods (269) reach 0.9·R past the centre.
            check(LinearDelta::default(), r * t.cos(), r * t.sin(), z)?;
        }

        #[test]
        fn round_trips_with_random_geometries(
            radius in 10.0f64..1000.0, ratio in 2.05f64..5.0,
            r in 0.0f64..0.9, t in 0.0f64..std::f64::consts::TAU, z in -500.0f64..500.0,
        ) {
            let k = LinearDelta { r: radius, l: radius * ratio };
            check(k, r * t.cos(), r * t.sin(), z)?;
        }
    }
}
