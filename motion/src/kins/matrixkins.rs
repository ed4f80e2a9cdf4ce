//! `matrixkins`: calibrated kinematics for three-axis Cartesian machines
//! (LinuxCNC 2.10's halcompile component): a 3×3 matrix `C` maps the
//! world X Y Z to joints 0 to 2, so scale errors and out-of-square axes
//! can be calibrated out; joints 3 to 8 are A B C U V W unchanged.
//!
//! ```text
//! inverse:  (j0, j1, j2) = C · (X, Y, Z)
//! forward:  (X, Y, Z)    = C⁻¹ · (j0, j1, j2)
//! ```
//!
//! The coefficients are the parameters `matrixkins.C_xx` …
//! `matrixkins.C_zz` (float rw, default the identity; LinuxCNC's first
//! release made them output pins, its current one parameters), read at
//! every call. A matrix that cannot be inverted
//! (singular, or holding a non-number) makes the forward kinematics fail
//! with [`KinsError::NoSolution`], as do non-finite joints or poses;
//! LinuxCNC's divides by the determinant regardless. Per halcompile
//! instance (`count=`/`names=`, one by default) there is the template's
//! `matrixkins.N.dummy` (bit out, TRUE). A configuration with fewer
//! joints reads the missing ones as 0. The type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::instances::instance_names;
use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Out, Param, Result, Rw};

use super::loader::register;
use super::math::{finite, mat_vec, solve_linear, Mat3, IDENTITY};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The module's name.
const NAME: &str = "matrixkins";

/// The `matrixkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: hal_core::instances::INSTANCE_PARAMS,
    help: "X Y Z through a calibration matrix (scale and squareness errors)",
    load,
};

/// The coefficient parameters' suffixes, row by row.
const COEFFICIENTS: [[&str; 3]; 3] = [
    ["C_xx", "C_xy", "C_xz"],
    ["C_yx", "C_yy", "C_yz"],
    ["C_zx", "C_zy", "C_zz"],
];

/// The kinematics for a fixed matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Matrix {
    /// World X Y Z to joints 0 to 2.
    pub c: Mat3,
}

impl Default for Matrix {
    fn default() -> Self {
        Matrix { c: IDENTITY }
    }
}

/// The first nine joints, missing ones as 0.
fn padded(joints: &[f64]) -> [f64; NUM_AXES] {
    let mut j = [0.0; NUM_AXES];
    let n = joints.len().min(NUM_AXES);
    j[..n].copy_from_slice(&joints[..n]);
    j
}

impl Kinematics for Matrix {
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
        let mut out = padded(joints);
        finite(&out)?;
        let xyz = solve_linear(self.c, [out[0], out[1], out[2]]).ok_or(KinsError::NoSolution)?;
        out[..3].copy_from_slice(&xyz);
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
        let j = mat_vec(&self.c, [out[0], out[1], out[2]]);
        out[..3].copy_from_slice(&j);
        finite(&out)?;
        for (slot, value) in joints.iter_mut().zip(out) {
            *slot = value;
        }
        Ok(())
    }
}

/// The module's kinematics: the matrix read from its parameters at
/// every call.
struct MatrixPins {
    c: [[Param<f64, Rw>; 3]; 3],
}

impl MatrixPins {
    fn matrix(&self) -> Matrix {
        Matrix {
            c: std::array::from_fn(|r| std::array::from_fn(|k| self.c[r][k].get())),
        }
    }
}

impl Kinematics for MatrixPins {
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
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.matrix().forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.matrix().inverse(pose, joints, flags)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let prefixes = instance_names(NAME, args)?;
    let b = host.new_rt_component(NAME)?;
    let c = b.component();
    for prefix in &prefixes {
        c.pin_init::<bool, Out>(&format!("{prefix}.dummy"), true)?;
    }
    let mut pins = Vec::with_capacity(9);
    for (r, row) in COEFFICIENTS.iter().enumerate() {
        for (k, suffix) in row.iter().enumerate() {
            pins.push(c.param::<f64, Rw>(&format!("{NAME}.{suffix}"), IDENTITY[r][k])?);
        }
    }
    let mut pins = pins.into_iter();
    let mut next = || {
        pins.next().ok_or_else(|| hal_core::HalError::ModuleLoad {
            module: NAME.into(),
            reason: "coefficient parameters were not all made".into(),
        })
    };
    let c = [
        [next()?, next()?, next()?],
        [next()?, next()?, next()?],
        [next()?, next()?, next()?],
    ];
    register(host, b, NAME, Arc::new(MatrixPins { c }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(k: &Matrix, j: [f64; 9]) -> std::result::Result<[f64; 9], KinsError> {
        crate::kins::testing::forward(k, &j)
    }

    fn inv(k: &Matrix, p: [f64; 9]) -> std::result::Result<[f64; 9], KinsError> {
        crate::kins::testing::inverse(k, &p, [0.0; 9])
    }

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    #[test]
    fn the_identity_matrix_is_trivial_kinematics() {
        let p = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
        assert_eq!(inv(&Matrix::default(), p).unwrap(), p);
        assert_eq!(fwd(&Matrix::default(), p).unwrap(), p);
    }

    #[test]
    fn skews_and_scales_move_the_joints_as_linuxcncs_test_expects() {
        // LinuxCNC's matrixkins test: X skewed by Y and Z.
        let k = Matrix {
            c: [[1.0, 0.01, 0.03], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        };
        let j = inv(&k, [10.0, 20.0, 30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        assert!(
            close(&j[..3], &[10.0 + 0.2 + 0.9, 20.0, 30.0], 1e-12),
            "{j:?}"
        );
        let k = Matrix {
            c: [[0.99, 0.0, 0.0], [0.0, 1.01, 0.0], [0.0, 0.0, 1.05]],
        };
        let j = inv(&k, [10.0, 20.0, 30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        assert!(close(&j[..3], &[9.9, 20.2, 31.5], 1e-12), "{j:?}");
    }

    #[test]
    fn singular_matrices_and_non_numbers_are_refused() {
        let k = Matrix {
            c: [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]],
        };
        let mut pose = Pose([5.0; 9]);
        let mut flags = KinsFlags::default();
        assert_eq!(
            k.forward(&[1.0, 2.0, 3.0], &mut pose, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(pose, Pose([5.0; 9]));
        let k = Matrix {
            c: [[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        };
        let mut j = [3.0; 3];
        assert_eq!(
            k.inverse(&pose, &mut j, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(j, [3.0; 3]);
        assert_eq!(
            fwd(
                &Matrix::default(),
                [f64::INFINITY, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
            ),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn calibration_matrices_round_trip(
            skew in prop::array::uniform6(-0.05f64..0.05),
            scale in prop::array::uniform3(0.9f64..1.1),
            p in prop::array::uniform9(-1000.0f64..1000.0),
        ) {
            let k = Matrix {
                c: [
                    [scale[0], skew[0], skew[1]],
                    [skew[2], scale[1], skew[3]],
                    [skew[4], skew[5], scale[2]],
                ],
            };
            let back = fwd(&k, inv(&k, p).unwrap()).unwrap();
            prop_assert!(close(&back, &p, 1e-9), "{:?} vs {:?}", back, p);
        }
    }
}
