//! `pumakins`: PUMA-style six-axis arms, switchable (type 0 PUMA, type 1
//! identity, type 2 user; see [`super::switchkins`]).
//!
//! The arm is the PUMA 560 chain of Craig's "Introduction to Robotics":
//! waist, shoulder and elbow, then a wrist of three axes meeting in one
//! point. Joints are in degrees; the world pose is the tool tip (X Y Z)
//! and the tool's roll, pitch and yaw (A B C, degrees).
//!
//! Pins (float io, LinuxCNC's names and defaults): `pumakins.A2` 300
//! (upper arm), `A3` 50 (elbow offset), `D3` 70 (shoulder offset), `D4`
//! 400 (forearm), `D6` 70 (wrist to tool tip along the tool axis).
//!
//! The inverse kinematics have eight solutions; the inverse flags pick
//! one ([`SHOULDER_RIGHT`], [`ELBOW_DOWN`], [`WRIST_FLIP`]) and the
//! forward kinematics set them to describe the joints they were given
//! (plus [`SINGULAR`] at a wrist singularity), so that the inverse of a
//! forward gives the same joints back. At a wrist singularity (joint 5
//! at 0°) joints 4 and 6 turn about one axis: joint 4 keeps its current
//! value and the forward flag [`REACH`] says so, as in LinuxCNC. Poses
//! out of the arm's reach, or with the wrist centre on the waist axis,
//! are refused.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, Io, Pin, Result};

use super::dh::{chain, DhLink, Frame, LINKS};
use super::loader::float_io;
use super::math::{angle_diff, column, deg, finite, matrix_rpy, rad, rpy_matrix, scale, sub, Mat3};
use super::pinned::{PinGeometry, Pinned};
use super::switchkins::{self, SwitchSpec};
use super::trivkins::Trivkins;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `pumakins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "pumakins",
    params: switchkins::PARAMS,
    help: "PUMA-style six-axis arm kinematics (switchable)",
    load,
};

/// Inverse flag: the shoulder on the other side of the waist axis.
pub const SHOULDER_RIGHT: u64 = 0x01;
/// Inverse flag: the elbow below the line from shoulder to wrist.
pub const ELBOW_DOWN: u64 = 0x02;
/// Inverse flag: the wrist turned half a turn with joint 5 mirrored.
pub const WRIST_FLIP: u64 = 0x04;
/// Inverse flag set by the forward kinematics at a wrist singularity.
pub const SINGULAR: u64 = 0x08;
/// Forward flag set by the inverse kinematics at a wrist singularity.
pub const REACH: u64 = 0x01;

/// LinuxCNC's default dimensions: A2, A3, D3, D4, D6.
pub const DEFAULTS: [f64; 5] = [300.0, 50.0, 70.0, 400.0, 70.0];

/// Joints of the arm.
pub const JOINTS: usize = 6;

/// Below this the wrist (or the arm) is taken as singular.
const SINGULAR_FUZZ: f64 = 1e-6;

/// A PUMA arm of fixed dimensions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Puma {
    /// Upper arm length.
    pub a2: f64,
    /// Elbow offset.
    pub a3: f64,
    /// Shoulder offset.
    pub d3: f64,
    /// Forearm length.
    pub d4: f64,
    /// Wrist centre to tool tip, along the tool axis.
    pub d6: f64,
}

impl Default for Puma {
    fn default() -> Self {
        let [a2, a3, d3, d4, d6] = DEFAULTS;
        Puma { a2, a3, d3, d4, d6 }
    }
}

/// The arm chain pumakins and three21kins share: a PUMA whose shoulder
/// sits `d1` up the waist axis and `a1` out from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Arm6 {
    /// Shoulder out from the waist axis.
    pub a1: f64,
    /// Shoulder up from the base.
    pub d1: f64,
    /// Upper arm length.
    pub a2: f64,
    /// Elbow offset.
    pub a3: f64,
    /// Shoulder offset (across the arm's plane).
    pub d3: f64,
    /// Forearm length.
    pub d4: f64,
    /// Wrist centre to tool tip, along the tool axis.
    pub d6: f64,
}

impl Puma {
    /// The chain with the shoulder on the waist axis at the base.
    fn arm6(&self) -> Arm6 {
        Arm6 {
            a1: 0.0,
            d1: 0.0,
            a2: self.a2,
            a3: self.a3,
            d3: self.d3,
            d4: self.d4,
            d6: self.d6,
        }
    }
}

/// The arm's solution for a wrist-centre position (radians).
struct Arm {
    th1: f64,
    th3: f64,
    s1: f64,
    c1: f64,
    s23: f64,
    c23: f64,
    th23: f64,
}

impl Arm6 {
    fn links(&self) -> [DhLink; LINKS] {
        use std::f64::consts::FRAC_PI_2;
        let l = |a, alpha, d| DhLink { a, alpha, d };
        [
            l(0.0, 0.0, self.d1),
            l(self.a1, -FRAC_PI_2, 0.0),
            l(self.a2, 0.0, self.d3),
            l(self.a3, -FRAC_PI_2, self.d4),
            l(0.0, FRAC_PI_2, 0.0),
            l(0.0, -FRAC_PI_2, 0.0),
        ]
    }

    fn dims(&self) -> [f64; 7] {
        [
            self.a1, self.d1, self.a2, self.a3, self.d3, self.d4, self.d6,
        ]
    }

    /// The wrist centre's frame (joints in radians).
    pub(crate) fn wrist(&self, q: &[f64; JOINTS]) -> Frame {
        chain(&self.links(), q).0
    }

    /// Waist, shoulder and elbow for wrist centre `p`, on the branches
    /// the flags pick.
    fn arm(&self, p: [f64; 3], flags: u64) -> Option<Arm> {
        let [px, py, pz] = p;
        let pz = pz - self.d1;
        let planar2 = px * px + py * py - self.d3 * self.d3;
        if planar2 < 0.0 || self.a2 == 0.0 {
            return None;
        }
        let shoulder = if flags & SHOULDER_RIGHT != 0 {
            -1.0
        } else {
            1.0
        };
        let th1 = py.atan2(px) - self.d3.atan2(shoulder * planar2.sqrt());
        let (s1, c1) = th1.sin_cos();
        let forearm2 = self.a3 * self.a3 + self.d4 * self.d4;
        // The wrist centre's distance out along the arm's plane, from the
        // shoulder (a1 out from the waist axis).
        let out = c1 * px + s1 * py;
        let reach2 = planar2 - 2.0 * self.a1 * out + self.a1 * self.a1;
        let k = (reach2 + pz * pz - self.a2 * self.a2 - forearm2) / (2.0 * self.a2);
        let disc = forearm2 - k * k;
        if disc < 0.0 {
            return None;
        }
        let elbow = if flags & ELBOW_DOWN != 0 { -1.0 } else { 1.0 };
        let th3 = self.a3.atan2(self.d4) - k.atan2(elbow * disc.sqrt());
        let (s3, c3) = th3.sin_cos();
        let u = out - self.a1;
        let t1 = (-self.a3 - self.a2 * c3) * pz + u * (self.a2 * s3 - self.d4);
        let t2 = (self.a2 * s3 - self.d4) * pz + (self.a3 + self.a2 * c3) * u;
        let t3 = pz * pz + u * u;
        if t3 <= SINGULAR_FUZZ * SINGULAR_FUZZ {
            return None;
        }
        Some(Arm {
            th1,
            th3,
            s1,
            c1,
            s23: t1 / t3,
            c23: t2 / t3,
            th23: t1.atan2(t2),
        })
    }

    /// Joint 4 for the arm and the tool rotation `r`, or `None` at a
    /// wrist singularity.
    fn wrist_turn(arm: &Arm, r: &Mat3) -> Option<f64> {
        let z = column(r, 2);
        let n1 = -z[0] * arm.s1 + z[1] * arm.c1;
        let n2 = -z[0] * arm.c1 * arm.c23 - z[1] * arm.s1 * arm.c23 + z[2] * arm.s23;
        (n1.abs() >= SINGULAR_FUZZ || n2.abs() >= SINGULAR_FUZZ).then(|| n1.atan2(n2))
    }

    /// Joints 5 and 6 for the arm, joint 4 and the tool rotation `r`.
    fn wrist_rest(arm: &Arm, th4: f64, r: &Mat3) -> (f64, f64) {
        let (x, z) = (column(r, 0), column(r, 2));
        let Arm {
            s1, c1, s23, c23, ..
        } = *arm;
        let (s4, c4) = th4.sin_cos();
        let s5 =
            z[2] * s23 * c4 - z[0] * (c1 * c23 * c4 + s1 * s4) - z[1] * (s1 * c23 * c4 - c1 * s4);
        let c5 = -z[0] * c1 * s23 - z[1] * s1 * s23 - z[2] * c23;
        let th5 = s5.atan2(c5);
        let (s5, c5) = th5.sin_cos();
        let s6 =
            x[2] * s23 * s4 - x[0] * (c1 * c23 * s4 - s1 * c4) - x[1] * (s1 * c23 * s4 + c1 * c4);
        let c6 = x[0] * ((c1 * c23 * c4 + s1 * s4) * c5 - c1 * s23 * s5)
            + x[1] * ((s1 * c23 * c4 - c1 * s4) * c5 - s1 * s23 * s5)
            - x[2] * (s23 * c4 * c5 + c23 * s5);
        (th5, s6.atan2(c6))
    }
}

impl Arm6 {
    /// Forward kinematics, setting the inverse flags that pick these
    /// joints' solution.
    pub(crate) fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let j: &[f64; JOINTS] = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(j)?;
        finite(&self.dims())?;
        let q = j.map(rad);
        let w = self.wrist(&q);
        let tip = super::math::add(w.pos, scale(w.z_axis(), self.d6));
        let [roll, pitch, yaw] = matrix_rpy(&w.rot);
        let out = [tip[0], tip[1], tip[2], deg(roll), deg(pitch), deg(yaw)];
        finite(&out)?;

        // Which of the eight solutions these joints are.
        let mut iflags = 0;
        let near = |a: f64, b: f64| angle_diff(a, b).abs() < 1e-6;
        if let Some(arm) = self.arm(w.pos, SHOULDER_RIGHT) {
            if near(arm.th1, q[0]) {
                iflags |= SHOULDER_RIGHT;
            }
        }
        if let Some(arm) = self.arm(w.pos, iflags | ELBOW_DOWN) {
            if near(arm.th3, q[2]) {
                iflags |= ELBOW_DOWN;
            }
        }
        match self
            .arm(w.pos, iflags)
            .and_then(|a| Self::wrist_turn(&a, &w.rot))
        {
            None => iflags |= SINGULAR,
            Some(th4) if !near(th4, q[3]) => iflags |= WRIST_FLIP,
            Some(_) => {}
        }
        pose.0[..6].copy_from_slice(&out);
        flags.inverse = iflags;
        Ok(())
    }

    /// Inverse kinematics on the branches the inverse flags pick.
    pub(crate) fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let current = *joints
            .first_chunk::<JOINTS>()
            .ok_or(KinsError::Unsupported)?;
        finite(&pose.0[..6])?;
        finite(&self.dims())?;
        let [x, y, z, a, b, c, ..] = pose.0;
        let r = rpy_matrix(rad(a), rad(b), rad(c));
        let p = sub([x, y, z], scale(column(&r, 2), self.d6));
        let arm = self.arm(p, flags.inverse).ok_or(KinsError::NoSolution)?;
        let mut fflags = 0;
        let th4 = match Self::wrist_turn(&arm, &r) {
            Some(th4) => th4,
            None => {
                fflags |= REACH;
                if !current[3].is_finite() {
                    return Err(KinsError::NoSolution);
                }
                rad(current[3])
            }
        };
        let (th5, th6) = Self::wrist_rest(&arm, th4, &r);
        let (th4, th5, th6) = if flags.inverse & WRIST_FLIP != 0 {
            use std::f64::consts::PI;
            (th4 + PI, -th5, th6 + PI)
        } else {
            (th4, th5, th6)
        };
        let out = [arm.th1, arm.th23 - arm.th3, arm.th3, th4, th5, th6].map(deg);
        finite(&out)?;
        joints[..JOINTS].copy_from_slice(&out);
        flags.forward = fflags;
        Ok(())
    }
}

impl Kinematics for Puma {
    fn name(&self) -> &str {
        "pumakins"
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
        self.arm6().forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.arm6().inverse(pose, joints, flags)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 6)
    }
}

/// The module's own kinematics: the dimensions read from the pins at
/// every call.
struct Pumakins {
    dims: [Pin<f64, Io>; 5],
}

impl Pumakins {
    fn export(c: &Component) -> Result<Pinned<Pumakins>> {
        let names = ["A2", "A3", "D3", "D4", "D6"];
        let p = |i: usize| float_io(c, &format!("pumakins.{}", names[i]), DEFAULTS[i]);
        Ok(Pinned(Pumakins {
            dims: [p(0)?, p(1)?, p(2)?, p(3)?, p(4)?],
        }))
    }
}

impl PinGeometry for Pumakins {
    const NAME: &'static str = "pumakins";
    type Geometry = Puma;

    fn geometry(&self) -> Puma {
        let [a2, a3, d3, d4, d6] = self.dims.each_ref().map(|p| p.get());
        Puma { a2, a3, d3, d4, d6 }
    }
}

/// How pumakins switches: XYZABC, no duplicates, six joints.
pub const SPEC: SwitchSpec = SwitchSpec {
    module: "pumakins",
    required: "xyzabc",
    requires_letters: false,
    allow_duplicates: false,
    max_joints: JOINTS,
    honours_identity_first: false,
    forward_iterates: false,
    gui_pins: false,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, SPEC, |c, _: &Trivkins| Pumakins::export(c))
}

#[cfg(test)]
mod tests;
