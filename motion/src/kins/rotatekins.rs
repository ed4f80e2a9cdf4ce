//! `rotatekins`: LinuxCNC's example of a rotary table done in software.
//! Joints 0 to 8 are X Y Z A B C U V W, but the world X and Y are the
//! workpiece's, turned with the table by the C angle (degrees):
//!
//! ```text
//! inverse:  j0 = X·cos C − Y·sin C     forward:  X =  j0·cos C + j1·sin C
//!           j1 = X·sin C + Y·cos C               Y = −j0·sin C + j1·cos C
//! ```
//!
//! with C = j5; every other joint is its axis. A configuration with fewer
//! than nine joints reads the missing ones as 0. LinuxCNC's kins(9) page
//! still describes an older version (X and Y turned 45° from the joints);
//! this follows the module LinuxCNC 2.9 ships, which turns by C.
//!
//! The module has no pins or parameters; the type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Result};

use super::loader::register;
use super::math::{finite, rad};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The module's name.
const NAME: &str = "rotatekins";

/// The `rotatekins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: &[],
    help: "X and Y turned with the C axis: a rotary table in software",
    load,
};

/// The kinematics (no geometry).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Rotate;

impl Kinematics for Rotate {
    fn name(&self) -> &str {
        NAME
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
        let mut out = [0.0; NUM_AXES];
        let n = joints.len().min(NUM_AXES);
        out[..n].copy_from_slice(&joints[..n]);
        finite(&out)?;
        let (s, c) = rad(out[5]).sin_cos();
        let (j0, j1) = (out[0], out[1]);
        out[0] = j0 * c + j1 * s;
        out[1] = j1 * c - j0 * s;
        finite(&out)?;
        pose.0 = out;
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let mut out = pose.0;
        finite(&out)?;
        let (s, c) = rad(out[5]).sin_cos();
        let (x, y) = (out[0], out[1]);
        out[0] = x * c - y * s;
        out[1] = x * s + y * c;
        finite(&out)?;
        for (slot, value) in joints.iter_mut().zip(out) {
            *slot = value;
        }
        Ok(())
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component(NAME)?;
    register(host, b, NAME, Arc::new(Rotate))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(j: [f64; 9]) -> std::result::Result<[f64; 9], KinsError> {
        crate::kins::testing::forward(&Rotate, &j)
    }

    fn inv(p: [f64; 9]) -> std::result::Result<[f64; 9], KinsError> {
        crate::kins::testing::inverse(&Rotate, &p, [0.0; 9])
    }

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    #[test]
    fn the_table_turns_x_and_y_with_c() {
        let p = [10.0, 0.0, 3.0, 4.0, 5.0, 90.0, 7.0, 8.0, 9.0];
        let j = inv(p).unwrap();
        assert!(
            close(&j, &[0.0, 10.0, 3.0, 4.0, 5.0, 90.0, 7.0, 8.0, 9.0], 1e-12),
            "{j:?}"
        );
        // LinuxCNC's inverse, written out.
        let (x, y, c) = (3.0f64, -4.0f64, 30.0f64.to_radians());
        let j = inv([x, y, 0.0, 0.0, 0.0, 30.0, 0.0, 0.0, 0.0]).unwrap();
        let want = [x * c.cos() - y * c.sin(), x * c.sin() + y * c.cos()];
        assert!(close(&j[..2], &want, 1e-12), "{j:?}");
        // At C = 0 it is identity.
        let p = [1.0, 2.0, 3.0, 4.0, 5.0, 0.0, 7.0, 8.0, 9.0];
        assert_eq!(fwd(p).unwrap(), p);
    }

    #[test]
    fn short_joint_sets_read_as_zero_and_non_numbers_are_refused() {
        let mut pose = Pose([9.0; 9]);
        let mut flags = KinsFlags::default();
        Rotate
            .forward(&[1.0, 2.0, 3.0], &mut pose, &mut flags)
            .unwrap();
        assert_eq!(pose.0, [1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let mut j = [5.0; 3];
        pose.0[5] = f64::NAN;
        assert_eq!(
            Rotate.inverse(&pose, &mut j, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(j, [5.0; 3]);
        assert_eq!(
            fwd([0.0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0]),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn round_trips_everywhere(
            p in prop::array::uniform9(-1000.0f64..1000.0),
        ) {
            let back = fwd(inv(p).unwrap()).unwrap();
            prop_assert!(close(&back, &p, 1e-9), "{:?} vs {:?}", back, p);
        }
    }
}
