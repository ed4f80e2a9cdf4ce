//! `rosekins`: a rose engine, where the workpiece turns on a spindle and
//! the tool moves across it (transverse, joint 0) and along it
//! (longitudinal, joint 1); joint 2 is the spindle angle in degrees.
//!
//! ```text
//! forward:  X = j0·cos j2    Y = j0·sin j2    Z = j1
//! inverse:  j0 = √(X² + Y²)  j1 = Z           j2 = atan2(Y, X) + 360°·revolutions
//! ```
//!
//! The spindle angle is not wrapped: the inverse counts the times the
//! pose crosses the negative X axis (from the second quadrant into the
//! third adds a turn, back takes one away), so a spiral cut turns the
//! spindle on and on. The count lives in the module, as in LinuxCNC, and
//! every inverse call moves it; a pose exactly on the negative X axis
//! counts as the second quadrant (a −0 Y is taken as +0, so that it does
//! not jump a turn).
//!
//! Pins (float out, LinuxCNC's names, set by every inverse call):
//! `rosekins.revolutions` (the turn count), `rosekins.theta_degrees`
//! (atan2(Y, X) in degrees) and `rosekins.bigtheta_degrees` (the
//! accumulated angle, joint 2). The type is KINEMATICS_BOTH; the world
//! axes are X, Y and Z.

use std::sync::atomic::{AtomicI64, AtomicU8, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Out, Pin, Result};

use super::loader::register;
use super::math::{deg, finite, rad};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `rosekins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "rosekins",
    params: &[],
    help: "rose engine: transverse, longitudinal and spindle joints",
    load,
};

/// What one inverse call saw: LinuxCNC's three output pins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoseAngles {
    /// Turns counted so far.
    pub revolutions: f64,
    /// The pose's angle, −180° to 180°.
    pub theta_degrees: f64,
    /// The accumulated angle (joint 2).
    pub bigtheta_degrees: f64,
}

/// The rose engine, with the turn count its inverse keeps.
#[derive(Debug, Default)]
pub struct Rose {
    /// The quadrant (1 to 4) of the last inverse call, 0 before the first.
    last_quadrant: AtomicU8,
    revolutions: AtomicI64,
}

fn quadrant(x: f64, y: f64) -> u8 {
    match (x >= 0.0, y >= 0.0) {
        (true, true) => 1,
        (false, true) => 2,
        (false, false) => 3,
        (true, false) => 4,
    }
}

impl Rose {
    /// Inverse kinematics that also report the angles they used.
    pub fn solve(
        &self,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<RoseAngles, KinsError> {
        let slots: &mut [f64; 3] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        // `+ 0.0` makes a −0 Y +0: atan2 would otherwise give −180°.
        let (x, y, z) = (pose.0[0], pose.0[1] + 0.0, pose.0[2]);
        finite(&[x, y, z])?;
        let now = quadrant(x, y);
        let before = self.last_quadrant.load(Relaxed);
        let mut revolutions = self.revolutions.load(Relaxed);
        match (before, now) {
            (2, 3) => revolutions += 1,
            (3, 2) => revolutions -= 1,
            _ => {}
        }
        let theta = deg(y.atan2(x));
        // Exact in f64 for any count a machine reaches.
        let turns = revolutions as f64;
        let angles = RoseAngles {
            revolutions: turns,
            theta_degrees: theta,
            bigtheta_degrees: theta + 360.0 * turns,
        };
        *slots = [x.hypot(y), z, angles.bigtheta_degrees];
        for rest in &mut joints[3..] {
            *rest = 0.0;
        }
        self.last_quadrant.store(now, Relaxed);
        self.revolutions.store(revolutions, Relaxed);
        Ok(angles)
    }
}

impl Kinematics for Rose {
    fn name(&self) -> &str {
        "rosekins"
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
        let [radius, z, angle] = *joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(&[radius, z, angle])?;
        let (sin, cos) = rad(angle).sin_cos();
        *pose = Pose::ZERO;
        pose.0[..3].copy_from_slice(&[radius * cos, radius * sin, z]);
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.solve(pose, joints).map(|_| ())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 3)
    }
}

/// The module's kinematics: the rose engine and its output pins.
struct Rosekins {
    rose: Rose,
    revolutions: Pin<f64, Out>,
    theta_degrees: Pin<f64, Out>,
    bigtheta_degrees: Pin<f64, Out>,
}

impl Kinematics for Rosekins {
    fn name(&self) -> &str {
        "rosekins"
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
        self.rose.forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let a = self.rose.solve(pose, joints)?;
        self.revolutions.set(a.revolutions);
        self.theta_degrees.set(a.theta_degrees);
        self.bigtheta_degrees.set(a.bigtheta_degrees);
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.rose.has_axis(axis)
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("rosekins")?;
    let c = b.component();
    let kins = Rosekins {
        rose: Rose::default(),
        revolutions: c.pin("rosekins.revolutions")?,
        theta_degrees: c.pin("rosekins.theta_degrees")?,
        bigtheta_degrees: c.pin("rosekins.bigtheta_degrees")?,
    };
    register(host, b, "rosekins", Arc::new(kins))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn inv(k: &Rose, p: [f64; 3]) -> [f64; 3] {
        crate::kins::testing::inverse(k, &p, [0.0; 3]).unwrap()
    }

    fn fwd(k: &Rose, j: [f64; 3]) -> [f64; 3] {
        crate::kins::testing::forward(k, &j).unwrap()
    }

    /// The point at `angle` degrees on a circle of radius `r`.
    fn on_circle(r: f64, angle: f64, z: f64) -> [f64; 3] {
        let (s, c) = angle.to_radians().sin_cos();
        [r * c, r * s, z]
    }

    #[test]
    fn joints_are_radius_height_and_angle() {
        let k = Rose::default();
        let j = inv(&k, [0.0, 2.0, 5.0]);
        assert!((j[0] - 2.0).abs() < 1e-12 && j[1] == 5.0 && (j[2] - 90.0).abs() < 1e-12);
        let p = fwd(&k, [3.0, -1.0, 180.0]);
        assert!((p[0] + 3.0).abs() < 1e-12 && p[1].abs() < 1e-12 && p[2] == -1.0);
    }

    #[test]
    fn crossing_the_negative_x_axis_counts_turns() {
        let k = Rose::default();
        let mut pose = Pose::ZERO;
        let mut j = [0.0; 3];
        let mut last = None;
        // Two and a half turns counterclockwise, then back.
        let steps: Vec<f64> = (0..=90).map(|i| f64::from(i) * 10.0).collect();
        for &a in steps.iter().chain(steps.iter().rev()) {
            pose.0[..3].copy_from_slice(&on_circle(4.0, a, 0.0));
            let angles = k.solve(&pose, &mut j).unwrap();
            assert!((j[2] - a).abs() < 1e-9, "at {a}: {j:?} {angles:?}");
            assert_eq!(angles.bigtheta_degrees, j[2]);
            last = Some(angles);
        }
        assert_eq!(last.unwrap().revolutions, 0.0);
    }

    #[test]
    fn a_minus_zero_y_on_the_negative_x_axis_does_not_jump_a_turn() {
        let k = Rose::default();
        let mut j = [0.0; 3];
        let mut pose = Pose::ZERO;
        pose.0[0] = -2.0;
        pose.0[1] = -0.0;
        k.solve(&pose, &mut j).unwrap();
        assert_eq!(j[2], 180.0);
    }

    #[test]
    fn short_joint_sets_and_non_numbers_are_refused() {
        let k = Rose::default();
        let mut p = Pose::ZERO;
        let mut flags = KinsFlags::default();
        assert_eq!(
            k.forward(&[1.0, 2.0], &mut p, &mut flags),
            Err(KinsError::Unsupported)
        );
        assert_eq!(
            k.inverse(&p, &mut [0.0; 2], &mut flags),
            Err(KinsError::Unsupported)
        );
        p.0[1] = f64::NAN;
        assert_eq!(
            k.inverse(&p, &mut [0.0; 3], &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(
            k.forward(&[1.0, 2.0, f64::INFINITY], &mut p, &mut flags),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn round_trips(
            r in 0.001f64..500.0, a in -179.9f64..180.0, z in -100.0f64..100.0,
        ) {
            let k = Rose::default();
            let p = on_circle(r, a, z);
            let j = inv(&k, p);
            prop_assert!((j[0] - r).abs() < 1e-9 && (j[2] - a).abs() < 1e-9, "{:?}", j);
            let back = fwd(&k, j);
            for i in 0..3 {
                prop_assert!((back[i] - p[i]).abs() < 1e-9, "{:?} vs {:?}", back, p);
            }
        }

        /// A walk in small steps keeps the spindle angle continuous.
        #[test]
        fn the_angle_follows_a_walk_around_the_axis(
            steps in prop::collection::vec(-30.0f64..30.0, 1..200),
        ) {
            let k = Rose::default();
            let mut angle = 0.0;
            let mut j = [0.0; 3];
            let mut pose = Pose::ZERO;
            for s in steps {
                angle += s;
                pose.0[..3].copy_from_slice(&on_circle(10.0, angle, 1.0));
                k.inverse(&pose, &mut j, &mut KinsFlags::default()).unwrap();
                prop_assert!((j[2] - angle).abs() < 1e-6, "{} vs {:?}", angle, j);
            }
        }
    }
}
