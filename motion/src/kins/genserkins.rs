//! `genserkins`: general serial arms of six revolute joints, switchable
//! (type 0 genser, type 1 identity, type 2 user; see
//! [`super::switchkins`]).
//!
//! The arm is described by Denavit–Hartenberg parameters in Craig's
//! ("modified") convention, one set per joint (see [`super::dh`]). Joints
//! are in degrees; the world pose is the last link's origin (X Y Z) and
//! its roll, pitch and yaw (A B C, degrees). The forward kinematics are
//! direct. The inverse kinematics iterate (Newton's method on the
//! Jacobian) from the joints' current positions, so they find the
//! solution nearest to where the arm is.
//!
//! Pins (LinuxCNC's names; defaults are a PUMA 560):
//! * `genserkins.A-N`, `genserkins.ALPHA-N` (radians), `genserkins.D-N`
//!   (float in, N = 0…5): link N's parameters;
//! * `genserkins.unrotate-N` (s32 in): joint N's angle is measured from
//!   `unrotate-N` times joint N−1's (for arms whose motors ride on the
//!   previous link);
//! * `genserkins.max-iterations` (u32 in, default 100): the iteration
//!   limit of the inverse kinematics;
//! * `genserkins.last-iterations` (u32 out): iterations the last inverse
//!   took.
//!
//! Refused: poses for which the iteration does not converge within the
//! limit, and singular arm configurations met on the way (a Jacobian
//! that cannot be inverted: an arm stretched straight, wrist axes in
//! line).

use std::f64::consts::FRAC_PI_2;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Out, Pin, Result};

use super::dh::{chain, jacobian, DhLink, Frame, LINKS};
use super::loader::float_in;
use super::math::{
    deg, finite, mat_mul, matrix_rpy, norm, rad, rotation_vector, rpy_matrix, solve6, sub,
    transpose,
};
use super::switchkins::{self, SwitchSpec};
use super::trivkins::Trivkins;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `genserkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "genserkins",
    params: switchkins::PARAMS,
    help: "general six-joint serial arm kinematics (switchable)",
    load,
};

/// Joints of the arm.
pub const JOINTS: usize = LINKS;

/// LinuxCNC's default iteration limit.
pub const DEFAULT_MAX_ITERATIONS: u32 = 100;

/// LinuxCNC's default links (a PUMA 560): (A, ALPHA, D) of links 0…5.
pub const DEFAULT_LINKS: [DhLink; LINKS] = [
    DhLink {
        a: 0.0,
        alpha: 0.0,
        d: 0.0,
    },
    DhLink {
        a: 0.0,
        alpha: -FRAC_PI_2,
        d: 0.0,
    },
    DhLink {
        a: 300.0,
        alpha: 0.0,
        d: 70.0,
    },
    DhLink {
        a: 50.0,
        alpha: -FRAC_PI_2,
        d: 400.0,
    },
    DhLink {
        a: 0.0,
        alpha: FRAC_PI_2,
        d: 0.0,
    },
    DhLink {
        a: 0.0,
        alpha: -FRAC_PI_2,
        d: 0.0,
    },
];

/// Position error (machine units) the inverse kinematics settle for.
const POSITION_TOLERANCE: f64 = 1e-9;
/// Orientation error (radians) the inverse kinematics settle for.
const ROTATION_TOLERANCE: f64 = 1e-11;
/// The largest joint step (radians) one iteration takes, so that a far
/// target is approached instead of overshot.
const MAX_STEP: f64 = 0.5;

/// A serial arm of fixed geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Genser {
    /// Link parameters.
    pub links: [DhLink; LINKS],
    /// `unrotate-N` of each joint (joint 0's is not used).
    pub unrotate: [i32; LINKS],
    /// Iteration limit of the inverse kinematics.
    pub max_iterations: u32,
}

impl Default for Genser {
    fn default() -> Self {
        Genser {
            links: DEFAULT_LINKS,
            unrotate: [0; LINKS],
            max_iterations: DEFAULT_MAX_ITERATIONS,
        }
    }
}

impl Genser {
    /// Link angles (radians) of joint positions (degrees).
    fn angles(&self, joints: &[f64; JOINTS]) -> [f64; JOINTS] {
        let mut q = joints.map(rad);
        for i in (1..JOINTS).rev() {
            q[i] -= f64::from(self.unrotate[i]) * rad(joints[i - 1]);
        }
        q
    }

    /// Joint positions (degrees) of link angles (radians).
    fn joint_positions(&self, q: &[f64; JOINTS]) -> [f64; JOINTS] {
        let mut j = q.map(deg);
        for i in 1..JOINTS {
            j[i] += f64::from(self.unrotate[i]) * j[i - 1];
        }
        j
    }

    fn check(&self) -> std::result::Result<(), KinsError> {
        for l in &self.links {
            finite(&[l.a, l.alpha, l.d])?;
        }
        Ok(())
    }

    /// The inverse kinematics: link angles (radians) that put the last
    /// link at `target`, starting from `q`, with the iterations taken.
    pub fn solve(
        &self,
        target: &Frame,
        mut q: [f64; JOINTS],
    ) -> (std::result::Result<[f64; JOINTS], KinsError>, u32) {
        for it in 0..self.max_iterations {
            let (tool, frames) = chain(&self.links, &q);
            let dp = sub(target.pos, tool.pos);
            let dr = rotation_vector(&mat_mul(&target.rot, &transpose(&tool.rot)));
            if norm(dp) <= POSITION_TOLERANCE && norm(dr) <= ROTATION_TOLERANCE {
                return (Ok(q), it);
            }
            let err = [dp[0], dp[1], dp[2], dr[0], dr[1], dr[2]];
            let Some(mut step) = solve6(jacobian(&frames, tool.pos), err) else {
                return (Err(KinsError::NoSolution), it + 1);
            };
            let largest = step.iter().fold(0.0f64, |m, s| m.max(s.abs()));
            if largest > MAX_STEP {
                step = step.map(|s| s * MAX_STEP / largest);
            }
            for (qi, s) in q.iter_mut().zip(step) {
                *qi += s;
            }
        }
        (Err(KinsError::NotConverged), self.max_iterations)
    }

    /// [`Kinematics::inverse`] plus the iterations it took.
    pub fn inverse_counted(
        &self,
        pose: &Pose,
        joints: &mut [f64],
    ) -> (std::result::Result<(), KinsError>, u32) {
        let Some(current) = joints.first_chunk::<JOINTS>() else {
            return (Err(KinsError::Unsupported), 0);
        };
        if let Err(e) = finite(&pose.0[..6]).and(finite(current)).and(self.check()) {
            return (Err(e), 0);
        }
        let [x, y, z, a, b, c, ..] = pose.0;
        let target = Frame {
            rot: rpy_matrix(rad(a), rad(b), rad(c)),
            pos: [x, y, z],
        };
        let (solved, iterations) = self.solve(&target, self.angles(current));
        let result = solved.and_then(|q| {
            let out = self.joint_positions(&q);
            finite(&out)?;
            joints[..JOINTS].copy_from_slice(&out);
            Ok(())
        });
        (result, iterations)
    }
}

impl Kinematics for Genser {
    fn name(&self) -> &str {
        "genserkins"
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
        let j: &[f64; JOINTS] = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(j)?;
        self.check()?;
        let (tool, _) = chain(&self.links, &self.angles(j));
        let [roll, pitch, yaw] = matrix_rpy(&tool.rot);
        let out = [
            tool.pos[0],
            tool.pos[1],
            tool.pos[2],
            deg(roll),
            deg(pitch),
            deg(yaw),
        ];
        finite(&out)?;
        pose.0[..6].copy_from_slice(&out);
        Ok(())
    }

    /// Iterates from the incoming `joints` (the arm's current position).
    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.inverse_counted(pose, joints).0
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 6)
    }
}

/// The pins of one link.
struct LinkPins {
    a: Pin<f64, In>,
    alpha: Pin<f64, In>,
    d: Pin<f64, In>,
    unrotate: Pin<i32, In>,
}

/// The module's own kinematics: the geometry read from the pins at every
/// call.
pub struct Genserkins {
    links: [LinkPins; LINKS],
    max_iterations: Pin<u32, In>,
    last_iterations: Pin<u32, Out>,
}

impl Genserkins {
    fn export(c: &Component) -> Result<Genserkins> {
        let link = |i: usize| -> Result<LinkPins> {
            let l = DEFAULT_LINKS[i];
            Ok(LinkPins {
                a: float_in(c, &format!("genserkins.A-{i}"), l.a)?,
                alpha: float_in(c, &format!("genserkins.ALPHA-{i}"), l.alpha)?,
                d: float_in(c, &format!("genserkins.D-{i}"), l.d)?,
                unrotate: c.pin(&format!("genserkins.unrotate-{i}"))?,
            })
        };
        Ok(Genserkins {
            links: [link(0)?, link(1)?, link(2)?, link(3)?, link(4)?, link(5)?],
            last_iterations: c.pin("genserkins.last-iterations")?,
            max_iterations: c.pin_init("genserkins.max-iterations", DEFAULT_MAX_ITERATIONS)?,
        })
    }

    /// The geometry on the pins now.
    pub fn geometry(&self) -> Genser {
        Genser {
            links: self.links.each_ref().map(|l| DhLink {
                a: l.a.get(),
                alpha: l.alpha.get(),
                d: l.d.get(),
            }),
            unrotate: self.links.each_ref().map(|l| l.unrotate.get()),
            max_iterations: self.max_iterations.get(),
        }
    }
}

impl Kinematics for Genserkins {
    fn name(&self) -> &str {
        "genserkins"
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
        self.geometry().forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let (result, iterations) = self.geometry().inverse_counted(pose, joints);
        self.last_iterations.set(iterations);
        result
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 6)
    }
}

/// How genserkins switches: XYZABC, no duplicates, six joints.
pub const SPEC: SwitchSpec = SwitchSpec {
    module: "genserkins",
    required: "xyzabc",
    requires_letters: false,
    allow_duplicates: false,
    max_joints: JOINTS,
    honours_identity_first: false,
    forward_iterates: false,
    gui_pins: false,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, SPEC, |c, _: &Trivkins| Genserkins::export(c))
}

#[cfg(test)]
mod tests;
