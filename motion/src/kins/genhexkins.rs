//! `genhexkins`: hexapods (Stewart platforms), switchable (type 0
//! hexapod, type 1 identity, type 2 user; see [`super::switchkins`]).
//!
//! Six struts join base points `b_i` (world coordinates) to platform
//! points `a_i` (platform coordinates); the joints are the strut lengths.
//! The world pose is the platform's position (X Y Z) and its roll, pitch
//! and yaw (A B C, degrees).
//!
//! * Inverse kinematics, closed form: `l_i = |p + R·a_i − b_i|`.
//! * Forward kinematics, iterative (Newton's method from the pose the
//!   call comes in with, normally the previous one): the solution
//!   nearest that guess. Non-captive screw actuators on cardan joints
//!   change a strut's length as the joints twist; with a non-zero
//!   `screw-lead` both directions add that correction.
//!
//! Pins (LinuxCNC's names and defaults; float in unless said):
//! `genhexkins.base.N.x/y/z`, `genhexkins.platform.N.x/y/z` (strut
//! ends), `genhexkins.base-n.N.x/y/z`, `genhexkins.platform-n.N.x/y/z`
//! (unit vectors of the joints' axes, for the correction),
//! `genhexkins.screw-lead` (0: no correction), `genhexkins.correction.N`
//! (float out: the current correction), `genhexkins.spindle-offset` and
//! `genhexkins.tool-offset` (added to the Z of every strut end),
//! `genhexkins.convergence-criterion` (1e-9: largest strut error of a
//! solution), `genhexkins.limit-iterations` (u32, 120),
//! `genhexkins.max-error` (500: total strut error beyond which the
//! iteration gives up), `genhexkins.last-iterations` and
//! `genhexkins.max-iterations` (u32 out: iterations of the last
//! solution, most iterations of any), `genhexkins.fwd-kins-fail` (bit
//! out), `genhexkins.x` … `genhexkins.c` (float out: the last forward
//! solution, for a display; LinuxCNC declares these `in` and writes
//! them, here they are outputs), and the switchable module's `skgui.*`.
//!
//! Refused: struts of zero length, non-positive joint lengths, and
//! forward kinematics that do not converge within the limits or meet a
//! singular platform position (the struts' Jacobian cannot be
//! inverted, as with the platform in the plane of the base).

use std::f64::consts::TAU;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Out, Pin, Result};

use super::loader::float_in;
use super::math::{
    add, cross, deg, dot, finite, mat_mul, mat_vec, newton, norm, rad, rot_x, rot_y, rot_z,
    rpy_matrix, sub, turn_derivative, unit, Mat3, NewtonLimits, Vec3,
};
use super::switchkins::{self, SwitchSpec};
use super::trivkins::Trivkins;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `genhexkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "genhexkins",
    params: switchkins::PARAMS,
    help: "hexapod (Stewart platform) kinematics (switchable)",
    load,
};

/// Struts (joints) of a hexapod.
pub const STRUTS: usize = 6;

/// LinuxCNC's default base points.
pub const DEFAULT_BASE: [Vec3; STRUTS] = [
    [-22.950, 13.250, 0.0],
    [22.950, 13.250, 0.0],
    [22.950, 13.250, 0.0],
    [0.0, -26.500, 0.0],
    [0.0, -26.500, 0.0],
    [-22.950, 13.250, 0.0],
];

/// LinuxCNC's default platform points.
pub const DEFAULT_PLATFORM: [Vec3; STRUTS] = [
    [-1.000, 11.500, 0.0],
    [1.000, 11.500, 0.0],
    [10.459, -4.884, 0.0],
    [9.459, -6.616, 0.0],
    [-9.459, -6.616, 0.0],
    [-10.459, -4.884, 0.0],
];

/// LinuxCNC's default base joint axes (its rounded 0.707107 kept, so
/// the pins show LinuxCNC's values).
#[allow(clippy::approx_constant)]
pub const DEFAULT_BASE_N: [Vec3; STRUTS] = [
    [0.707107, 0.0, 0.707107],
    [0.0, -0.707107, 0.707107],
    [-0.707107, 0.0, 0.707107],
    [-0.707107, 0.0, 0.707107],
    [0.0, 0.707107, 0.707107],
    [0.707107, 0.0, 0.707107],
];

/// LinuxCNC's default platform joint axes.
pub const DEFAULT_PLATFORM_N: [Vec3; STRUTS] = [
    [-1.0, 0.0, 0.0],
    [0.866025, 0.5, 0.0],
    [0.866025, 0.5, 0.0],
    [0.866025, -0.5, 0.0],
    [0.866025, -0.5, 0.0],
    [-1.0, 0.0, 0.0],
];

/// LinuxCNC's default convergence criterion.
pub const DEFAULT_CONVERGENCE_CRITERION: f64 = 1e-9;
/// LinuxCNC's default iteration limit.
pub const DEFAULT_LIMIT_ITERATIONS: u32 = 120;
/// LinuxCNC's default error limit.
pub const DEFAULT_MAX_ERROR: f64 = 500.0;

/// A hexapod of fixed geometry, with its iteration settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hexapod {
    /// Strut ends on the base, world coordinates.
    pub base: [Vec3; STRUTS],
    /// Strut ends on the platform, platform coordinates.
    pub platform: [Vec3; STRUTS],
    /// Base joints' axes (unit vectors).
    pub base_n: [Vec3; STRUTS],
    /// Platform joints' axes (unit vectors, platform coordinates).
    pub platform_n: [Vec3; STRUTS],
    /// Lead of the strut screws (right-hand positive); 0 disables the
    /// length correction.
    pub screw_lead: f64,
    /// Added to the Z of every strut end.
    pub spindle_offset: f64,
    /// Added to the Z of every strut end (the tool length).
    pub tool_offset: f64,
    /// Largest strut error of a converged forward solution.
    pub convergence_criterion: f64,
    /// Most iterations of a forward solution.
    pub limit_iterations: u32,
    /// Total strut error beyond which the forward solution gives up.
    pub max_error: f64,
}

impl Default for Hexapod {
    fn default() -> Self {
        Hexapod {
            base: DEFAULT_BASE,
            platform: DEFAULT_PLATFORM,
            base_n: DEFAULT_BASE_N,
            platform_n: DEFAULT_PLATFORM_N,
            screw_lead: 0.0,
            spindle_offset: 0.0,
            tool_offset: 0.0,
            convergence_criterion: DEFAULT_CONVERGENCE_CRITERION,
            limit_iterations: DEFAULT_LIMIT_ITERATIONS,
            max_error: DEFAULT_MAX_ERROR,
        }
    }
}

/// One strut at a pose.
struct Strut {
    /// Length, corrected.
    length: f64,
    /// The correction in it.
    correction: f64,
    /// Unit vector from base to platform end.
    dir: Vec3,
}

/// A forward solution and what it took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solution {
    /// X Y Z (machine units) and A B C (degrees).
    pub pose: [f64; 6],
    /// Iterations used.
    pub iterations: u32,
}

impl Hexapod {
    fn lift(&self) -> f64 {
        self.spindle_offset + self.tool_offset
    }

    fn check(&self) -> std::result::Result<(), KinsError> {
        for i in 0..STRUTS {
            finite(&self.base[i])?;
            finite(&self.platform[i])?;
            finite(&self.base_n[i])?;
            finite(&self.platform_n[i])?;
        }
        finite(&[self.screw_lead, self.lift()])
    }

    /// Strut `i` with the platform at `p` turned by `r`.
    fn strut(&self, i: usize, p: Vec3, r: &Mat3) -> Option<Strut> {
        let lift = [0.0, 0.0, self.lift()];
        let arm = mat_vec(r, add(self.platform[i], lift));
        let v = sub(add(p, arm), add(self.base[i], lift));
        let dir = unit(v)?;
        let correction = if self.screw_lead != 0.0 {
            self.correction(i, dir, r)?
        } else {
            0.0
        };
        Some(Strut {
            length: norm(v) + correction,
            correction,
            dir,
        })
    }

    /// How much a non-captive screw on cardan joints lengthens strut `i`
    /// pointing along `dir`: the twist between its two joints' axes, as a
    /// fraction of a turn, times the lead.
    fn correction(&self, i: usize, dir: Vec3, r: &Mat3) -> Option<f64> {
        let base_axis = unit(cross(dir, cross(self.base_n[i], dir)))?;
        let platform_axis = unit(cross(mat_vec(r, self.platform_n[i]), dir))?;
        let twist = dot(base_axis, platform_axis).clamp(-1.0, 1.0).asin();
        Some(self.screw_lead * twist / TAU)
    }

    /// The strut lengths and their corrections for a pose (X Y Z and
    /// A B C in degrees).
    pub fn struts(
        &self,
        pose: &[f64; 6],
    ) -> std::result::Result<([f64; STRUTS], [f64; STRUTS]), KinsError> {
        finite(pose)?;
        self.check()?;
        let r = rpy_matrix(rad(pose[3]), rad(pose[4]), rad(pose[5]));
        let p = [pose[0], pose[1], pose[2]];
        let mut lengths = [0.0; STRUTS];
        let mut corrections = [0.0; STRUTS];
        for i in 0..STRUTS {
            let s = self.strut(i, p, &r).ok_or(KinsError::NoSolution)?;
            lengths[i] = s.length;
            corrections[i] = s.correction;
        }
        finite(&lengths)?;
        Ok((lengths, corrections))
    }

    /// The forward kinematics from the pose `guess`.
    pub fn solve(
        &self,
        joints: &[f64; STRUTS],
        guess: &[f64; 6],
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
        let start = [
            guess[0],
            guess[1],
            guess[2],
            rad(guess[3]),
            rad(guess[4]),
            rad(guess[5]),
        ];
        let (x, iterations) = newton(&limits, start, |x| {
            self.linearise(joints, [x[0], x[1], x[2]], [x[3], x[4], x[5]])
        })?;
        let pose = [x[0], x[1], x[2], deg(x[3]), deg(x[4]), deg(x[5])];
        finite(&pose)?;
        Ok(Solution { pose, iterations })
    }
}

impl Hexapod {
    /// The struts' errors against `joints` with the platform at `p`
    /// turned by roll, pitch and yaw `angles` (radians), and how they
    /// change with the six coordinates (the Jacobian).
    fn linearise(
        &self,
        joints: &[f64; STRUTS],
        p: Vec3,
        angles: Vec3,
    ) -> Option<([[f64; 6]; STRUTS], [f64; STRUTS])> {
        let [roll, pitch, yaw] = angles;
        let (rx, ry, rz) = (rot_x(roll), rot_y(pitch), rot_z(yaw));
        let r = mat_mul(&rz, &mat_mul(&ry, &rx));
        // How the rotation changes with each angle.
        let d_roll = mat_mul(&rz, &mat_mul(&ry, &turn_derivative(&rx, 0)));
        let d_pitch = mat_mul(&rz, &mat_mul(&turn_derivative(&ry, 1), &rx));
        let d_yaw = mat_mul(&turn_derivative(&rz, 2), &mat_mul(&ry, &rx));
        let mut jac = [[0.0; 6]; STRUTS];
        let mut error = [0.0; STRUTS];
        for i in 0..STRUTS {
            let s = self.strut(i, p, &r)?;
            error[i] = s.length - joints[i];
            let local = add(self.platform[i], [0.0, 0.0, self.lift()]);
            let row = &mut jac[i];
            row[..3].copy_from_slice(&s.dir);
            row[3] = dot(s.dir, mat_vec(&d_roll, local));
            row[4] = dot(s.dir, mat_vec(&d_pitch, local));
            row[5] = dot(s.dir, mat_vec(&d_yaw, local));
        }
        Some((jac, error))
    }
}

impl Kinematics for Hexapod {
    fn name(&self) -> &str {
        "genhexkins"
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
        pose.0[..6].copy_from_slice(&s.pose);
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
        let (lengths, _) = self.struts(pose.0.first_chunk().ok_or(KinsError::Unsupported)?)?;
        *slot = lengths;
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 6)
    }
}

/// The pins of one strut.
struct StrutPins {
    base: [Pin<f64, In>; 3],
    platform: [Pin<f64, In>; 3],
    base_n: [Pin<f64, In>; 3],
    platform_n: [Pin<f64, In>; 3],
    correction: Pin<f64, Out>,
}

/// The module's own kinematics: the geometry read from the pins at every
/// call, the iteration figures written back.
pub struct Genhexkins {
    struts: [StrutPins; STRUTS],
    screw_lead: Pin<f64, In>,
    spindle_offset: Pin<f64, In>,
    tool_offset: Pin<f64, In>,
    convergence_criterion: Pin<f64, In>,
    limit_iterations: Pin<u32, In>,
    max_error: Pin<f64, In>,
    last_iterations: Pin<u32, Out>,
    max_iterations: Pin<u32, Out>,
    fwd_kins_fail: Pin<bool, Out>,
    shown: [Pin<f64, Out>; 6],
}

impl Genhexkins {
    fn export(c: &Component) -> Result<Genhexkins> {
        let xyz = |what: &str, i: usize, init: Vec3| -> Result<[Pin<f64, In>; 3]> {
            let p = |k: usize, l: &str| float_in(c, &format!("genhexkins.{what}.{i}.{l}"), init[k]);
            Ok([p(0, "x")?, p(1, "y")?, p(2, "z")?])
        };
        let strut = |i: usize| -> Result<StrutPins> {
            Ok(StrutPins {
                base: xyz("base", i, DEFAULT_BASE[i])?,
                platform: xyz("platform", i, DEFAULT_PLATFORM[i])?,
                base_n: xyz("base-n", i, DEFAULT_BASE_N[i])?,
                platform_n: xyz("platform-n", i, DEFAULT_PLATFORM_N[i])?,
                correction: c.pin(&format!("genhexkins.correction.{i}"))?,
            })
        };
        let out = |l: &str| c.pin::<f64, Out>(&format!("genhexkins.{l}"));
        Ok(Genhexkins {
            struts: [
                strut(0)?,
                strut(1)?,
                strut(2)?,
                strut(3)?,
                strut(4)?,
                strut(5)?,
            ],
            last_iterations: c.pin("genhexkins.last-iterations")?,
            max_iterations: c.pin("genhexkins.max-iterations")?,
            max_error: float_in(c, "genhexkins.max-error", DEFAULT_MAX_ERROR)?,
            convergence_criterion: float_in(
                c,
                "genhexkins.convergence-criterion",
                DEFAULT_CONVERGENCE_CRITERION,
            )?,
            limit_iterations: c
                .pin_init("genhexkins.limit-iterations", DEFAULT_LIMIT_ITERATIONS)?,
            tool_offset: float_in(c, "genhexkins.tool-offset", 0.0)?,
            spindle_offset: float_in(c, "genhexkins.spindle-offset", 0.0)?,
            screw_lead: float_in(c, "genhexkins.screw-lead", 0.0)?,
            shown: [
                out("x")?,
                out("y")?,
                out("z")?,
                out("a")?,
                out("b")?,
                out("c")?,
            ],
            fwd_kins_fail: c.pin("genhexkins.fwd-kins-fail")?,
        })
    }

    /// The geometry and iteration settings on the pins now.
    pub fn geometry(&self) -> Hexapod {
        let read = |p: &[Pin<f64, In>; 3]| p.each_ref().map(|p| p.get());
        Hexapod {
            base: self.struts.each_ref().map(|s| read(&s.base)),
            platform: self.struts.each_ref().map(|s| read(&s.platform)),
            base_n: self.struts.each_ref().map(|s| read(&s.base_n)),
            platform_n: self.struts.each_ref().map(|s| read(&s.platform_n)),
            screw_lead: self.screw_lead.get(),
            spindle_offset: self.spindle_offset.get(),
            tool_offset: self.tool_offset.get(),
            convergence_criterion: self.convergence_criterion.get(),
            limit_iterations: self.limit_iterations.get(),
            max_error: self.max_error.get(),
        }
    }
}

impl Kinematics for Genhexkins {
    fn name(&self) -> &str {
        "genhexkins"
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
        match self.geometry().solve(j, guess) {
            Ok(s) => {
                pose.0[..6].copy_from_slice(&s.pose);
                self.last_iterations.set(s.iterations);
                if s.iterations > self.max_iterations.get() {
                    self.max_iterations.set(s.iterations);
                }
                self.fwd_kins_fail.set(false);
                for (pin, v) in self.shown.iter().zip(s.pose) {
                    pin.set(v);
                }
                Ok(())
            }
            Err(e) => {
                self.fwd_kins_fail.set(true);
                Err(e)
            }
        }
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
        let g = self.geometry();
        let (lengths, corrections) =
            g.struts(pose.0.first_chunk().ok_or(KinsError::Unsupported)?)?;
        *slot = lengths;
        if g.screw_lead != 0.0 {
            for (s, c) in self.struts.iter().zip(corrections) {
                s.correction.set(c);
            }
        }
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 6)
    }
}

/// How genhexkins switches: XYZABC, no duplicates, six joints; its own
/// forward kinematics iterate and feed the `skgui.*` pins.
pub const SPEC: SwitchSpec = SwitchSpec {
    module: "genhexkins",
    required: "xyzabc",
    requires_letters: false,
    allow_duplicates: false,
    max_joints: STRUTS,
    honours_identity_first: false,
    forward_iterates: true,
    gui_pins: true,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, SPEC, |c, _: &Trivkins| Genhexkins::export(c))
}

#[cfg(test)]
mod tests;
