//! `scorbot-kins`: the Scorbot ER-3 arm of LinuxCNC's sample
//! configuration `by_machine/scorbot-er-3`.
//!
//! Joint 0 turns the whole arm about the vertical axis through the
//! base; joints 1 (shoulder) and 2 (elbow) move the wrist in the
//! vertical plane joint 0 selects; joints 3 and 4 (wrist pitch and roll,
//! which LinuxCNC's sample configuration mixes into motor commands with
//! a `differential` component) pass through to A and B. Angles are in
//! degrees and, for joints 1 and 2, measured from the horizontal: joint
//! 2 is the absolute angle of the forearm, not its angle to the upper
//! arm. In the arm's plane, with `r` the horizontal distance from the
//! base axis:
//!
//! ```text
//! r = H + L1·cos j1 + L2·cos j2     X = r·cos j0    A = j3
//! Z = V + L1·sin j1 + L2·sin j2     Y = r·sin j0    B = j4
//! ```
//!
//! with the ER-3's fixed dimensions in millimetres: the shoulder `H` =
//! 16 out from the base axis and `V` = 140 up from the base plate, the
//! upper arm `L1` and forearm `L2` both 221. C U V W are always 0.
//!
//! The inverse takes the elbow-up solution: joint 0 points the arm at
//! the wrist, the shoulder angle comes from the triangle shoulder,
//! elbow, wrist by the law of cosines, and the forearm's angle is that
//! of the line from the elbow to the wrist. LinuxCNC takes the forearm
//! angle through an arcsine, which is the same angle while the wrist is
//! not behind the elbow; here it is exact everywhere, so the forward
//! kinematics always undo the inverse. A wrist farther from the shoulder
//! than `L1 + L2`, nearer than `|L1 − L2|`, or on the shoulder itself
//! (where the shoulder angle is undefined) is refused with
//! [`KinsError::NoSolution`].
//!
//! The module has no pins or parameters (LinuxCNC's has none either);
//! the type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Result};

use super::loader::register;
use super::math::{deg, finite, rad};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The module's name.
const NAME: &str = "scorbot-kins";

/// The `scorbot-kins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: &[],
    help: "Scorbot ER-3 five-joint arm (base, shoulder, elbow, wrist pitch and roll)",
    load,
};

/// Joints the kinematics use.
pub const JOINTS: usize = 5;

/// The closest the wrist may come to the shoulder, relative to the arm's
/// length, before the shoulder angle counts as undefined.
const SINGULAR: f64 = 1e-9;

/// The arm's dimensions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scorbot {
    /// Horizontal distance from the base axis to the shoulder.
    pub shoulder_out: f64,
    /// Height of the shoulder above the base plate.
    pub shoulder_up: f64,
    /// Shoulder to elbow.
    pub upper_arm: f64,
    /// Elbow to wrist.
    pub forearm: f64,
}

/// The ER-3, as LinuxCNC's module has it (millimetres).
pub const ER3: Scorbot = Scorbot {
    shoulder_out: 16.0,
    shoulder_up: 140.0,
    upper_arm: 221.0,
    forearm: 221.0,
};

impl Default for Scorbot {
    fn default() -> Self {
        ER3
    }
}

impl Scorbot {
    /// Shoulder and forearm angles (degrees from the horizontal) that put
    /// the wrist at `(r, z)` from the shoulder in the arm's plane.
    fn plane_angles(&self, r: f64, z: f64) -> std::result::Result<(f64, f64), KinsError> {
        let (l1, l2) = (self.upper_arm, self.forearm);
        let d = r.hypot(z);
        let reach = l1 + l2;
        if !(l1 > 0.0 && l2 > 0.0) || d > reach || d < (l1 - l2).abs() || d <= SINGULAR * reach {
            return Err(KinsError::NoSolution);
        }
        // The angle at the shoulder between the wrist and the elbow.
        let cos_shoulder = ((l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d)).clamp(-1.0, 1.0);
        let shoulder = z.atan2(r) + cos_shoulder.acos();
        let (s, c) = shoulder.sin_cos();
        let forearm = (z - l1 * s).atan2(r - l1 * c);
        Ok((deg(shoulder), deg(forearm)))
    }
}

impl Kinematics for Scorbot {
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
        let mut j = [0.0; JOINTS];
        let n = joints.len().min(JOINTS);
        j[..n].copy_from_slice(&joints[..n]);
        finite(&j)?;
        let [base, shoulder, elbow, pitch, roll] = j;
        let (s1, c1) = rad(shoulder).sin_cos();
        let (s2, c2) = rad(elbow).sin_cos();
        let r = self.shoulder_out + self.upper_arm * c1 + self.forearm * c2;
        let z = self.shoulder_up + self.upper_arm * s1 + self.forearm * s2;
        let (s0, c0) = rad(base).sin_cos();
        let mut out = [0.0; NUM_AXES];
        out[..5].copy_from_slice(&[r * c0, r * s0, z, pitch, roll]);
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
        let [x, y, z, a, b, ..] = pose.0;
        finite(&[x, y, z, a, b])?;
        let base = y.atan2(x);
        let r = x.hypot(y) - self.shoulder_out;
        let (shoulder, elbow) = self.plane_angles(r, z - self.shoulder_up)?;
        let out = [deg(base), shoulder, elbow, a, b];
        finite(&out)?;
        for (slot, value) in joints.iter_mut().zip(out) {
            *slot = value;
        }
        Ok(())
    }

    /// X Y Z A B.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component(NAME)?;
    register(host, b, NAME, Arc::new(ER3))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(j: [f64; 5]) -> [f64; 9] {
        crate::kins::testing::forward(&ER3, &j).unwrap()
    }

    fn inv(p: [f64; 5]) -> std::result::Result<[f64; 5], KinsError> {
        crate::kins::testing::inverse(&ER3, &p, [0.0; 5])
    }

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    #[test]
    fn stretched_out_arm_reaches_its_full_length() {
        let p = fwd([0.0; 5]);
        assert!(
            close(&p, &[458.0, 0.0, 140.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], 1e-9),
            "{p:?}"
        );
        // Base at 90°: the arm points along +Y.
        let p = fwd([90.0, 0.0, 0.0, 5.0, -7.0]);
        assert!(
            close(&p[..5], &[0.0, 458.0, 140.0, 5.0, -7.0], 1e-9),
            "{p:?}"
        );
        // Upper arm straight up, forearm level: an L.
        let p = fwd([0.0, 90.0, 0.0, 0.0, 0.0]);
        assert!(close(&p[..3], &[237.0, 0.0, 361.0], 1e-9), "{p:?}");
        let j = inv([237.0, 0.0, 361.0, 0.0, 0.0]).unwrap();
        assert!(close(&j, &[0.0, 90.0, 0.0, 0.0, 0.0], 1e-9), "{j:?}");
    }

    #[test]
    fn agrees_with_linuxcncs_inverse_in_front_of_the_elbow() {
        // LinuxCNC's inverse for equal links, written out for one pose.
        let (x, y, z) = (200.0f64, 150.0f64, 250.0f64);
        let (r, h) = (x.hypot(y) - 16.0, z - 140.0);
        let d = r.hypot(h);
        let j1 = (r / d).acos().to_degrees() + (d / 2.0 / 221.0).acos().to_degrees();
        let j2 = -((221.0 * j1.to_radians().sin() - h) / 221.0)
            .asin()
            .to_degrees();
        let j = inv([x, y, z, 1.0, 2.0]).unwrap();
        let want = [y.atan2(x).to_degrees(), j1, j2, 1.0, 2.0];
        assert!(close(&j, &want, 1e-9), "{j:?} vs {want:?}");
    }

    #[test]
    fn unreachable_and_singular_wrists_are_refused() {
        // Beyond full stretch.
        assert_eq!(
            inv([459.0, 0.0, 140.0, 0.0, 0.0]),
            Err(KinsError::NoSolution)
        );
        // On the shoulder itself.
        assert_eq!(
            inv([16.0, 0.0, 140.0, 0.0, 0.0]),
            Err(KinsError::NoSolution)
        );
        assert_eq!(
            inv([f64::NAN, 0.0, 140.0, 0.0, 0.0]),
            Err(KinsError::NoSolution)
        );
        let mut pose = Pose::ZERO;
        let mut flags = KinsFlags::default();
        assert_eq!(
            ER3.forward(&[0.0, f64::INFINITY], &mut pose, &mut flags),
            Err(KinsError::NoSolution)
        );
        // A refused call leaves the joints alone.
        let mut j = [7.0; 5];
        pose.0[0] = 1000.0;
        assert_eq!(
            ER3.inverse(&pose, &mut j, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(j, [7.0; 5]);
    }

    proptest! {
        #[test]
        fn reachable_poses_round_trip(
            base in -180.0f64..180.0, dist in 0.001f64..441.999, elev in -180.0f64..180.0,
            a in -360.0f64..360.0, b in -360.0f64..360.0,
        ) {
            // A wrist `dist` from the shoulder at elevation `elev`, in the
            // plane at `base`.
            let (se, ce) = elev.to_radians().sin_cos();
            let r = 16.0 + dist * ce;
            let (s0, c0) = base.to_radians().sin_cos();
            let p = [r * c0, r * s0, 140.0 + dist * se, a, b];
            let j = inv(p).unwrap();
            prop_assert!(j.iter().all(|v| v.is_finite()));
            let back = fwd(j);
            prop_assert!(close(&back[..5], &p, 1e-6), "{:?} vs {:?}", back, p);
        }

        #[test]
        fn any_pose_gives_finite_joints_or_a_refusal(
            p in prop::array::uniform5(-1000.0f64..1000.0),
        ) {
            match inv(p) {
                Ok(j) => prop_assert!(j.iter().all(|v| v.is_finite())),
                Err(e) => prop_assert_eq!(e, KinsError::NoSolution),
            }
        }
    }
}
