//! `pentakins`: pentapods, five struts holding a spindle-like effector
//! that the struts cannot turn about its own axis, so the pose has five
//! degrees of freedom: X Y Z and the tilts A (roll) and B (pitch).
//!
//! Strut *i* runs from base point `b_i` (world coordinates) to a ring of
//! radius `r_i` around the effector's axis at height `z_i` (effector
//! coordinates); its length is the distance from the base point to that
//! ring. With the effector at `p`, turned by `R = Ry(B)·Rx(A)`, and
//! `q = Rᵀ·(b_i − p)` the base point seen from the effector:
//!
//! ```text
//! inverse:  l_i = √((q_z − z_i)² + (√(q_x² + q_y²) − r_i)²)
//! forward:  Newton's method on those five equations, from the pose the
//!           call comes in with (normally the previous one)
//! ```
//!
//! `tool-offset` is added to the Z of every base point and every ring:
//! an untilted effector's pose does not change, and tilts turn about the
//! point that far along the effector's axis (tool-centre-point control).
//!
//! LinuxCNC's names and kinds: parameters (float rw)
//! `pentakins.base.N.x/y/z` and `pentakins.effector.N.r/z` for N = 0…4;
//! pins `pentakins.convergence-criterion` (float io, 1e-9: largest
//! strut error of a solution), `pentakins.limit-iterations` (u32 io,
//! 120), `pentakins.max-error` (float io, 100: total strut error beyond
//! which the iteration gives up), `pentakins.last-iterations` and
//! `pentakins.max-iterations` (u32 out: iterations of the last solution,
//! most iterations of any), `pentakins.tool-offset` (float in). LinuxCNC
//! 2.9 also exports a sixth set of geometry parameters (N = 5) that
//! reads past the end of its five struts; it is not exported here.
//!
//! Refused: non-positive joint lengths, forward kinematics that do not
//! converge within the limits, and singular positions (a base point on
//! the effector's axis, or a strut of zero length). The type is
//! KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Io, Out, Param, Pin, Result, Rw};

use super::loader::{float_in, float_io, register};
use super::math::{
    add, column, deg, finite, mat_mul, mat_vec, newton, rad, rot_x, rot_y, scale, sub, transpose,
    turn_derivative, Mat3, NewtonLimits, Vec3,
};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `pentakins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "pentakins",
    params: &[],
    help: "pentapod: five struts to rings on a five-axis effector (XYZAB)",
    load,
};

/// Struts (joints) of a pentapod.
pub const STRUTS: usize = 5;

/// LinuxCNC's default base points.
pub const DEFAULT_BASE: [Vec3; STRUTS] = [
    [-418.03, 324.56, 895.56],
    [417.96, 324.56, 895.56],
    [-418.03, -325.44, 895.56],
    [417.96, -325.44, 895.56],
    [-0.06, -492.96, 895.56],
];

/// LinuxCNC's default ring radii.
pub const DEFAULT_EFFECTOR_R: [f64; STRUTS] = [80.32; STRUTS];

/// LinuxCNC's default ring heights.
pub const DEFAULT_EFFECTOR_Z: [f64; STRUTS] = [-185.5, -159.5, -67.5, -41.5, -14.0];

/// LinuxCNC's default `convergence-criterion`.
pub const DEFAULT_CONVERGENCE_CRITERION: f64 = 1e-9;
/// LinuxCNC's default `limit-iterations`.
pub const DEFAULT_LIMIT_ITERATIONS: u32 = 120;
/// LinuxCNC's default `max-error`.
pub const DEFAULT_MAX_ERROR: f64 = 100.0;

/// A pentapod's geometry and iteration settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pentapod {
    /// Base points.
    pub base: [Vec3; STRUTS],
    /// Ring radii on the effector.
    pub effector_r: [f64; STRUTS],
    /// Ring heights on the effector.
    pub effector_z: [f64; STRUTS],
    /// Added to the Z of base points and rings.
    pub tool_offset: f64,
    /// Largest strut error of a converged solution.
    pub convergence_criterion: f64,
    /// Most iterations of one forward solution.
    pub limit_iterations: u32,
    /// Total strut error beyond which the iteration gives up.
    pub max_error: f64,
}

impl Default for Pentapod {
    fn default() -> Self {
        Pentapod {
            base: DEFAULT_BASE,
            effector_r: DEFAULT_EFFECTOR_R,
            effector_z: DEFAULT_EFFECTOR_Z,
            tool_offset: 0.0,
            convergence_criterion: DEFAULT_CONVERGENCE_CRITERION,
            limit_iterations: DEFAULT_LIMIT_ITERATIONS,
            max_error: DEFAULT_MAX_ERROR,
        }
    }
}

/// A converged forward solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solution {
    /// X Y Z, A B (degrees).
    pub pose: [f64; STRUTS],
    /// Iterations it took.
    pub iterations: u32,
}

/// The effector's orientation for roll `a` and pitch `b` (radians) and
/// how it changes with each.
fn orientation(a: f64, b: f64) -> (Mat3, Mat3, Mat3) {
    let (rx, ry) = (rot_x(a), rot_y(b));
    (
        mat_mul(&ry, &rx),
        mat_mul(&ry, &turn_derivative(&rx, 0)),
        mat_mul(&turn_derivative(&ry, 1), &rx),
    )
}

impl Pentapod {
    fn check(&self) -> std::result::Result<(), KinsError> {
        finite(&[self.tool_offset, self.convergence_criterion, self.max_error])?;
        for i in 0..STRUTS {
            finite(&self.base[i])?;
            finite(&[self.effector_r[i], self.effector_z[i]])?;
        }
        Ok(())
    }

    /// Base point `i` (with the tool offset) as seen from the effector
    /// at `p` turned by `r`.
    fn seen_from_effector(&self, i: usize, p: Vec3, r: &Mat3) -> (Vec3, Vec3) {
        let d = sub(add(self.base[i], [0.0, 0.0, self.tool_offset]), p);
        (mat_vec(&transpose(r), d), d)
    }

    /// The length of strut `i` for the base point at `q` in effector
    /// coordinates, with the parts its derivative needs.
    fn strut(&self, i: usize, q: Vec3) -> (f64, f64, f64, f64) {
        let rho = q[0].hypot(q[1]);
        let along = q[2] - (self.effector_z[i] + self.tool_offset);
        let across = rho - self.effector_r[i];
        (along.hypot(across), along, across, rho)
    }

    /// The strut lengths for a pose (X Y Z, A B in degrees).
    pub fn struts(&self, pose: &[f64; STRUTS]) -> std::result::Result<[f64; STRUTS], KinsError> {
        finite(pose)?;
        self.check()?;
        let (r, _, _) = orientation(rad(pose[3]), rad(pose[4]));
        let p = [pose[0], pose[1], pose[2]];
        let mut lengths = [0.0; STRUTS];
        for (i, l) in lengths.iter_mut().enumerate() {
            let (q, _) = self.seen_from_effector(i, p, &r);
            *l = self.strut(i, q).0;
        }
        finite(&lengths)?;
        Ok(lengths)
    }

    /// The struts' errors against `joints` at `p` with roll and pitch
    /// `angles` (radians), and their Jacobian.
    fn linearise(
        &self,
        joints: &[f64; STRUTS],
        p: Vec3,
        angles: [f64; 2],
    ) -> Option<([[f64; STRUTS]; STRUTS], [f64; STRUTS])> {
        let (r, d_roll, d_pitch) = orientation(angles[0], angles[1]);
        let rt = transpose(&r);
        let mut jac = [[0.0; STRUTS]; STRUTS];
        let mut error = [0.0; STRUTS];
        for i in 0..STRUTS {
            let (q, d) = self.seen_from_effector(i, p, &r);
            let (length, along, across, rho) = self.strut(i, q);
            if !(length > 0.0 && rho > 0.0) {
                return None;
            }
            error[i] = length - joints[i];
            // How q moves with each coordinate: −Rᵀ for the position,
            // the turned derivative for the angles.
            let dq = [
                scale(column(&rt, 0), -1.0),
                scale(column(&rt, 1), -1.0),
                scale(column(&rt, 2), -1.0),
                mat_vec(&transpose(&d_roll), d),
                mat_vec(&transpose(&d_pitch), d),
            ];
            for (cell, dq) in jac[i].iter_mut().zip(dq) {
                let radial = (q[0] * dq[0] + q[1] * dq[1]) / rho;
                *cell = (along * dq[2] + across * radial) / length;
            }
        }
        Some((jac, error))
    }

    /// The forward kinematics from the pose `guess` (X Y Z, A B in
    /// degrees).
    pub fn solve(
        &self,
        joints: &[f64; STRUTS],
        guess: &[f64; STRUTS],
    ) -> std::result::Result<Solution, KinsError> {
        finite(joints)?;
        finite(guess)?;
        self.check()?;
        if joints.iter().any(|&l| l <= 0.0) {
            return Err(KinsError::NoSolution);
        }
        let limits = NewtonLimits {
            convergence_criterion: self.convergence_criterion,
            limit_iterations: self.limit_iterations,
            max_error: self.max_error,
        };
        let start = [guess[0], guess[1], guess[2], rad(guess[3]), rad(guess[4])];
        let (x, iterations) = newton(&limits, start, |x| {
            self.linearise(joints, [x[0], x[1], x[2]], [x[3], x[4]])
        })?;
        let pose = [x[0], x[1], x[2], deg(x[3]), deg(x[4])];
        finite(&pose)?;
        Ok(Solution { pose, iterations })
    }
}

impl Kinematics for Pentapod {
    fn name(&self) -> &str {
        "pentakins"
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
        let j = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        let guess = pose.0.first_chunk().ok_or(KinsError::Unsupported)?;
        let s = self.solve(j, guess)?;
        pose.0[..STRUTS].copy_from_slice(&s.pose);
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let slot = joints
            .first_chunk_mut::<STRUTS>()
            .ok_or(KinsError::Unsupported)?;
        *slot = self.struts(pose.0.first_chunk().ok_or(KinsError::Unsupported)?)?;
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < STRUTS)
    }
}

/// The geometry parameters of one strut.
struct StrutParams {
    base: [Param<f64, Rw>; 3],
    r: Param<f64, Rw>,
    z: Param<f64, Rw>,
}

/// The module's kinematics: the geometry read from its parameters and
/// pins at every call, the iteration figures written back.
struct Pentakins {
    struts: [StrutParams; STRUTS],
    convergence_criterion: Pin<f64, Io>,
    limit_iterations: Pin<u32, Io>,
    max_error: Pin<f64, Io>,
    last_iterations: Pin<u32, Out>,
    max_iterations: Pin<u32, Out>,
    tool_offset: Pin<f64, In>,
}

impl Pentakins {
    fn export(c: &Component) -> Result<Pentakins> {
        let param = |name: String, init: f64| c.param::<f64, Rw>(&name, init);
        let strut = |i: usize| -> Result<StrutParams> {
            let b = DEFAULT_BASE[i];
            Ok(StrutParams {
                base: [
                    param(format!("pentakins.base.{i}.x"), b[0])?,
                    param(format!("pentakins.base.{i}.y"), b[1])?,
                    param(format!("pentakins.base.{i}.z"), b[2])?,
                ],
                r: param(format!("pentakins.effector.{i}.r"), DEFAULT_EFFECTOR_R[i])?,
                z: param(format!("pentakins.effector.{i}.z"), DEFAULT_EFFECTOR_Z[i])?,
            })
        };
        Ok(Pentakins {
            struts: [strut(0)?, strut(1)?, strut(2)?, strut(3)?, strut(4)?],
            last_iterations: c.pin("pentakins.last-iterations")?,
            max_iterations: c.pin("pentakins.max-iterations")?,
            max_error: float_io(c, "pentakins.max-error", DEFAULT_MAX_ERROR)?,
            convergence_criterion: float_io(
                c,
                "pentakins.convergence-criterion",
                DEFAULT_CONVERGENCE_CRITERION,
            )?,
            limit_iterations: c.pin_init("pentakins.limit-iterations", DEFAULT_LIMIT_ITERATIONS)?,
            tool_offset: float_in(c, "pentakins.tool-offset", 0.0)?,
        })
    }

    fn geometry(&self) -> Pentapod {
        Pentapod {
            base: self
                .struts
                .each_ref()
                .map(|s| s.base.each_ref().map(|p| p.get())),
            effector_r: self.struts.each_ref().map(|s| s.r.get()),
            effector_z: self.struts.each_ref().map(|s| s.z.get()),
            tool_offset: self.tool_offset.get(),
            convergence_criterion: self.convergence_criterion.get(),
            limit_iterations: self.limit_iterations.get(),
            max_error: self.max_error.get(),
        }
    }
}

impl Kinematics for Pentakins {
    fn name(&self) -> &str {
        "pentakins"
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
        let j = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        let guess = pose.0.first_chunk().ok_or(KinsError::Unsupported)?;
        let s = self.geometry().solve(j, guess)?;
        pose.0[..STRUTS].copy_from_slice(&s.pose);
        self.last_iterations.set(s.iterations);
        if s.iterations > self.max_iterations.get() {
            self.max_iterations.set(s.iterations);
        }
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.geometry().inverse(pose, joints, flags)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < STRUTS)
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("pentakins")?;
    let kins = Pentakins::export(b.component())?;
    register(host, b, "pentakins", Arc::new(kins))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The sample configuration's geometry (sim/axis/pentapod's
    /// kinematics.hal) with its max-error.
    fn sample() -> Pentapod {
        Pentapod {
            base: [
                [-418.0, 500.0, -140.0],
                [418.0, 500.0, -140.0],
                [0.0, 500.0, -310.0],
                [418.0, 500.0, 510.0],
                [-418.0, 500.0, 510.0],
            ],
            effector_r: [80.3; STRUTS],
            effector_z: [87.0, 114.5, 140.5, 232.5, 258.5],
            max_error: 1000.0,
            ..Pentapod::default()
        }
    }

    #[test]
    fn the_sample_at_its_origin() {
        // Untilted at the origin, each strut spans the height between its
        // base point and its ring and the reach from the axis.
        let k = sample();
        let j = k.struts(&[0.0; STRUTS]).unwrap();
        for i in 0..STRUTS {
            let [x, y, z] = k.base[i];
            let reach = x.hypot(y) - k.effector_r[i];
            let want = (z - k.effector_z[i]).hypot(reach);
            assert!((j[i] - want).abs() < 1e-9, "{i}: {j:?}");
        }
        assert!((j[0] - 614.8469).abs() < 1e-3, "{j:?}");
        // And the forward kinematics find it again from a nearby pose.
        let s = k.solve(&j, &[5.0, -5.0, 5.0, 1.0, -1.0]).unwrap();
        assert!(s.pose.iter().all(|v| v.abs() < 1e-6), "{s:?}");
    }

    #[test]
    fn forward_finds_the_pose_from_a_nearby_guess_and_counts_iterations() {
        let k = sample();
        let want = [10.0, -20.0, 30.0, 5.0, -8.0];
        let j = k.struts(&want).unwrap();
        let s = k.solve(&j, &[0.0; STRUTS]).unwrap();
        for (a, b) in s.pose.iter().zip(want) {
            assert!((a - b).abs() < 1e-6, "{:?}", s.pose);
        }
        assert!(s.iterations > 1 && s.iterations < 20, "{s:?}");
        // Already there: one iteration.
        assert_eq!(k.solve(&j, &want).map(|s| s.iterations), Ok(1));
    }

    #[test]
    fn the_tool_offset_moves_the_point_tilts_turn_about() {
        let mut k = sample();
        let upright = k.struts(&[0.0; STRUTS]).unwrap();
        let tilted = k.struts(&[0.0, 0.0, 0.0, 10.0, 0.0]).unwrap();
        k.tool_offset = 25.0;
        // Untilted, nothing changes; tilted, the effector turns about
        // another point.
        let upright_t = k.struts(&[0.0; STRUTS]).unwrap();
        let tilted_t = k.struts(&[0.0, 0.0, 0.0, 10.0, 0.0]).unwrap();
        for (a, b) in upright.iter().zip(upright_t) {
            assert!((a - b).abs() < 1e-9);
        }
        assert!(tilted
            .iter()
            .zip(tilted_t)
            .any(|(a, b)| (a - b).abs() > 1.0));
    }

    #[test]
    fn limits_and_bad_input_are_refused() {
        let k = sample();
        let j = k.struts(&[10.0, 10.0, 10.0, 3.0, 3.0]).unwrap();
        let few = Pentapod {
            limit_iterations: 1,
            ..k
        };
        assert_eq!(few.solve(&j, &[0.0; STRUTS]), Err(KinsError::NotConverged));
        let tight = Pentapod {
            max_error: 1.0,
            ..k
        };
        assert_eq!(
            tight.solve(&j, &[0.0; STRUTS]),
            Err(KinsError::NotConverged)
        );
        let mut neg = j;
        neg[2] = 0.0;
        assert_eq!(k.solve(&neg, &[0.0; STRUTS]), Err(KinsError::NoSolution));
        assert_eq!(
            k.struts(&[f64::NAN, 0.0, 0.0, 0.0, 0.0]),
            Err(KinsError::NoSolution)
        );
        let mut p = Pose::ZERO;
        assert_eq!(
            k.forward(&[1.0; 4], &mut p, &mut KinsFlags::default()),
            Err(KinsError::Unsupported)
        );
    }

    proptest! {
        #[test]
        fn round_trips_from_the_previous_pose(
            xyz in prop::array::uniform3(-100.0f64..100.0),
            ab in prop::array::uniform2(-20.0f64..20.0),
            step in prop::array::uniform3(-2.0f64..2.0),
        ) {
            let k = sample();
            let pose = [xyz[0], xyz[1], xyz[2], ab[0], ab[1]];
            let j = k.struts(&pose).unwrap();
            // From a guess a servo cycle or so away, as motion calls it.
            let guess = [pose[0] + step[0], pose[1] + step[1], pose[2] + step[2], pose[3], pose[4]];
            let s = k.solve(&j, &guess).unwrap();
            for (a, b) in s.pose.iter().zip(pose) {
                prop_assert!((a - b).abs() < 1e-6, "{:?} vs {:?}", s.pose, pose);
            }
        }
    }
}
