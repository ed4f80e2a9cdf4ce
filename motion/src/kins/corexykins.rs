//! `corexykins`: CoreXY kinematics. Two motors drive one belt loop each;
//! moving both the same way moves X, moving them against each other
//! moves Y:
//!
//! ```text
//! X = (j0 + j1) / 2     j0 = X + Y
//! Y = (j0 - j1) / 2     j1 = X - Y
//! Z = j2                j2 = Z
//! ```
//!
//! Joints 3 to 8, when the machine has them, are A B C U V W one to one.
//! At least three joints are needed. `loadrt corexykins` takes no
//! parameters and exports no pins; the type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Result};

use super::loader::register;
use super::math::finite;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The `corexykins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "corexykins",
    params: &[],
    help: "CoreXY kinematics: X = (j0 + j1)/2, Y = (j0 - j1)/2",
    load,
};

/// The fewest joints a CoreXY machine has (the two belt motors and Z).
pub const MIN_JOINTS: usize = 3;

/// CoreXY kinematics (no geometry to configure).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Corexykins;

impl Kinematics for Corexykins {
    fn name(&self) -> &str {
        "corexykins"
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
        pose.0[0] = 0.5 * (joints[0] + joints[1]);
        pose.0[1] = 0.5 * (joints[0] - joints[1]);
        pose.0[2..n].copy_from_slice(&joints[2..n]);
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
        let (x, y) = (pose.0[0], pose.0[1]);
        finite(&[x + y, x - y])?;
        joints[0] = x + y;
        joints[1] = x - y;
        joints[2..n].copy_from_slice(&pose.0[2..n]);
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

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("corexykins")?;
    register(host, b, "corexykins", Arc::new(Corexykins))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn belts_move_x_together_and_y_against_each_other() {
        let k = Corexykins;
        let mut p = Pose::ZERO;
        let mut f = KinsFlags::default();
        k.forward(&[2.0, 2.0, 5.0], &mut p, &mut f).unwrap();
        assert_eq!(p.0[..3], [2.0, 0.0, 5.0]);
        k.forward(&[1.0, -1.0, 0.0], &mut p, &mut f).unwrap();
        assert_eq!(p.0[..3], [0.0, 1.0, 0.0]);
        // Axes past the joints keep their value.
        p.0[5] = 7.0;
        k.forward(&[1.0, 1.0, 1.0, 4.0], &mut p, &mut f).unwrap();
        assert_eq!((p.0[3], p.0[5]), (4.0, 7.0));
    }

    #[test]
    fn refuses_too_few_joints_and_non_numbers() {
        let k = Corexykins;
        let mut f = KinsFlags::default();
        let mut p = Pose::ZERO;
        assert_eq!(
            k.forward(&[1.0, 2.0], &mut p, &mut f),
            Err(KinsError::Unsupported)
        );
        assert_eq!(
            k.forward(&[1.0, f64::NAN, 0.0], &mut p, &mut f),
            Err(KinsError::NoSolution)
        );
        let mut j = [0.0; 3];
        p.0[1] = f64::INFINITY;
        assert_eq!(k.inverse(&p, &mut j, &mut f), Err(KinsError::NoSolution));
        assert_eq!(j, [0.0; 3], "nothing written on failure");
        p.0[0] = f64::MAX;
        p.0[1] = f64::MAX;
        assert_eq!(k.inverse(&p, &mut j, &mut f), Err(KinsError::NoSolution));
    }

    proptest! {
        #[test]
        fn round_trips(pose in prop::array::uniform9(-1e4f64..1e4), n in 3usize..=9) {
            let k = Corexykins;
            let mut f = KinsFlags::default();
            let p = Pose(pose);
            let mut j = [0.0; 9];
            k.inverse(&p, &mut j[..n], &mut f).unwrap();
            let mut back = Pose::ZERO;
            k.forward(&j[..n], &mut back, &mut f).unwrap();
            for a in 0..n {
                prop_assert!((back.0[a] - p.0[a]).abs() < 1e-9);
            }
            let mut j2 = [0.0; 9];
            k.inverse(&back, &mut j2[..n], &mut f).unwrap();
            for i in 0..n {
                prop_assert!((j2[i] - j[i]).abs() < 1e-9);
            }
        }
    }
}
