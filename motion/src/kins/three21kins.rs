//! `three21kins`: six-joint arms with a three-axis wrist whose axes meet
//! in one point (the "3-2-1" arm: three positioning joints, a spherical
//! wrist), solved in closed form; LinuxCNC 2.10's module, switchable
//! (type 0 the arm, type 1 identity, type 2 user; see
//! [`super::switchkins`]; `sparm=identityfirst` swaps types 0 and 1).
//!
//! The chain is pumakins' PUMA with the shoulder moved: `D1` up the
//! waist axis and `A1` out from it. `D2` and `D3` both lie along the
//! shoulder's axis, so only their sum counts (the offset across the
//! arm's plane); `A2` is the upper arm, `A3` and `D4` the elbow offset
//! and forearm, `D6` the wrist centre to the tool tip along the tool
//! axis. Joints are in degrees; the world pose is the tool tip (X Y Z)
//! and the tool's roll, pitch and yaw (A B C, degrees). The inverse
//! flags pick one of the eight solutions and the forward kinematics set
//! them to describe the joints they were given, with pumakins' values
//! ([`super::pumakins::SHOULDER_RIGHT`] …); at a wrist singularity joint
//! 4 keeps its current value and the forward flag `REACH` says so. Poses
//! out of reach, or with the wrist centre on the waist axis, are refused.
//!
//! Pins (float in, LinuxCNC's names and defaults, those of the AR2 arm):
//! `three21kins.A1` 64.2, `.A2` 305, `.A3` 0, `.D1` 169.77, `.D2` 0,
//! `.D3` −6.25, `.D4` 223.63, `.D6` 36.5, read at every call.
//! `coordinates=` (default and at most `xyzabc`, no letter twice) maps
//! the identity types' joints.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Pin, Result};

use super::loader::float_in;
use super::pinned::{PinGeometry, Pinned};
use super::pumakins::Arm6;
use super::switchkins::{self, SwitchSpec};
use super::trivkins::Trivkins;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The module's name.
const NAME: &str = "three21kins";

/// The `three21kins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: switchkins::PARAMS,
    help: "six-joint arm with a spherical wrist, closed-form (switchable)",
    load,
};

/// The pins' names, in the order of [`DEFAULTS`].
const PIN_NAMES: [&str; 8] = ["A1", "A2", "A3", "D1", "D2", "D3", "D4", "D6"];

/// LinuxCNC's defaults (the AR2 arm): A1 A2 A3 D1 D2 D3 D4 D6.
pub const DEFAULTS: [f64; 8] = [64.2, 305.0, 0.0, 169.77, 0.0, -6.25, 223.63, 36.5];

/// Joints of the arm.
pub const JOINTS: usize = 6;

/// An arm of fixed dimensions (the pins' values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Three21 {
    /// `A1`: shoulder out from the waist axis.
    pub a1: f64,
    /// `A2`: upper arm.
    pub a2: f64,
    /// `A3`: elbow offset.
    pub a3: f64,
    /// `D1`: shoulder up from the base.
    pub d1: f64,
    /// `D2`: offset along the shoulder axis.
    pub d2: f64,
    /// `D3`: offset along the elbow axis (parallel to the shoulder's).
    pub d3: f64,
    /// `D4`: forearm.
    pub d4: f64,
    /// `D6`: wrist centre to tool tip.
    pub d6: f64,
}

impl Default for Three21 {
    fn default() -> Self {
        let [a1, a2, a3, d1, d2, d3, d4, d6] = DEFAULTS;
        Three21 {
            a1,
            a2,
            a3,
            d1,
            d2,
            d3,
            d4,
            d6,
        }
    }
}

impl Three21 {
    /// The chain the arm is.
    pub(crate) fn arm6(&self) -> Arm6 {
        Arm6 {
            a1: self.a1,
            d1: self.d1,
            a2: self.a2,
            a3: self.a3,
            d3: self.d2 + self.d3,
            d4: self.d4,
            d6: self.d6,
        }
    }
}

impl Kinematics for Three21 {
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

    /// X Y Z A B C.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

/// The module's own kinematics: the dimensions read from the pins at
/// every call.
struct Three21Pins {
    dims: [Pin<f64, In>; 8],
}

impl Three21Pins {
    fn export(c: &Component) -> Result<Pinned<Three21Pins>> {
        let p = |i: usize| float_in(c, &format!("{NAME}.{}", PIN_NAMES[i]), DEFAULTS[i]);
        Ok(Pinned(Three21Pins {
            dims: [p(0)?, p(1)?, p(2)?, p(3)?, p(4)?, p(5)?, p(6)?, p(7)?],
        }))
    }
}

impl PinGeometry for Three21Pins {
    const NAME: &'static str = NAME;
    type Geometry = Three21;

    fn geometry(&self) -> Three21 {
        let [a1, a2, a3, d1, d2, d3, d4, d6] = self.dims.each_ref().map(|p| p.get());
        Three21 {
            a1,
            a2,
            a3,
            d1,
            d2,
            d3,
            d4,
            d6,
        }
    }
}

/// How three21kins switches: XYZABC, no duplicates, six joints,
/// `sparm=identityfirst` honoured.
pub const SPEC: SwitchSpec = SwitchSpec {
    module: NAME,
    required: "xyzabc",
    requires_letters: false,
    allow_duplicates: false,
    max_joints: JOINTS,
    honours_identity_first: true,
    forward_iterates: false,
    gui_pins: false,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, SPEC, |c, _: &Trivkins| Three21Pins::export(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kins::math::{angle_diff, rad};
    use proptest::prelude::*;

    fn fwd(k: &Three21, j: [f64; 6]) -> (Pose, KinsFlags) {
        let mut p = Pose::ZERO;
        let mut f = KinsFlags::default();
        k.forward(&j, &mut p, &mut f).unwrap();
        (p, f)
    }

    fn inv(k: &Three21, p: &Pose, iflags: u64, current: [f64; 6]) -> Result<[f64; 6], KinsError> {
        let mut j = current;
        let mut f = KinsFlags {
            forward: 0,
            inverse: iflags,
        };
        k.inverse(p, &mut j, &mut f).map(|()| j)
    }

    fn same_angles(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter()
            .zip(b)
            .all(|(x, y)| angle_diff(rad(*x), rad(*y)).abs() < rad(tol))
    }

    fn same_pose(a: &Pose, b: &Pose, tol: f64) -> bool {
        (0..3).all(|i| (a.0[i] - b.0[i]).abs() < tol) && same_angles(&a.0[3..6], &b.0[3..6], tol)
    }

    #[test]
    fn home_pose_follows_linuxcncs_forward_formula() {
        // LinuxCNC's closed-form position for joints 0 (the wrist
        // straight down the forearm): x = A1 + A2 + A3·1 - 0, z = D1 - D4,
        // y = D2 + D3, then D6 along the tool axis (down).
        let k = Three21::default();
        let (p, _) = fwd(&k, [0.0; 6]);
        let want = [64.2 + 305.0, -6.25, 169.77 - 223.63 - 36.5];
        assert!(
            p.0[..3].iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-9),
            "{p:?}"
        );
        // Turning the waist turns the arm about Z.
        let (p, _) = fwd(&k, [90.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(
            (p.0[0] - 6.25).abs() < 1e-9 && (p.0[1] - 369.2).abs() < 1e-9,
            "{p:?}"
        );
    }

    #[test]
    fn out_of_reach_and_non_numbers_are_refused() {
        let k = Three21::default();
        let mut p = Pose::ZERO;
        p.0[0] = 5000.0;
        let mut j = [1.0; 6];
        assert_eq!(
            k.inverse(&p, &mut j, &mut KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        assert_eq!(j, [1.0; 6]);
        p.0[0] = f64::NAN;
        assert_eq!(
            k.inverse(&p, &mut j, &mut KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        let mut flags = KinsFlags::default();
        assert_eq!(
            k.forward(
                &[0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0],
                &mut p,
                &mut flags
            ),
            Err(KinsError::NoSolution)
        );
    }

    /// Joints away from the singularities: joint 5 off 0 and 180, the
    /// wrist centre off the waist axis, the elbow not straight or folded.
    fn regular(k: &Three21, j: &[f64; 6]) -> bool {
        let arm = k.arm6();
        let q = j.map(rad);
        let w = arm.wrist(&q).pos;
        let d3 = arm.d3;
        let planar = (w[0].powi(2) + w[1].powi(2) - d3 * d3).max(0.0).sqrt();
        // The wrist centre from the shoulder, in the arm's plane.
        let (s1, c1) = q[0].sin_cos();
        let out = c1 * w[0] + s1 * w[1] - k.a1;
        let reach = out.hypot(w[2] - k.d1);
        let forearm = k.a3.hypot(k.d4);
        q[4].sin().abs() > 0.05
            && planar > 0.05 * k.a2
            && reach < (k.a2 + forearm) * 0.999
            && reach > (k.a2 - forearm).abs() * 1.001 + 1e-3
    }

    fn geometry() -> impl Strategy<Value = Three21> {
        (
            prop::array::uniform4(-100.0f64..100.0),
            100.0f64..600.0,
            100.0f64..600.0,
            0.0f64..100.0,
            -50.0f64..50.0,
        )
            .prop_map(|([a1, a3, d1, d2], a2, d4, d6, d3)| Three21 {
                a1,
                a2,
                a3,
                d1,
                d2,
                d3,
                d4,
                d6,
            })
    }

    fn check(k: Three21, j: [f64; 6]) -> std::result::Result<(), TestCaseError> {
        prop_assume!(regular(&k, &j));
        let (p, f) = fwd(&k, j);
        let back = inv(&k, &p, f.inverse, j).unwrap();
        prop_assert!(same_angles(&back, &j, 1e-6), "{:?} vs {:?}", back, j);
        for flags in 0..8 {
            if let Ok(sol) = inv(&k, &p, flags, j) {
                prop_assert!(sol.iter().all(|v| v.is_finite()));
                let (p2, _) = fwd(&k, sol);
                prop_assert!(
                    same_pose(&p2, &p, 1e-6),
                    "flags {}: {:?} vs {:?}",
                    flags,
                    p2,
                    p
                );
            }
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn round_trips_with_default_dimensions(j in prop::array::uniform6(-170.0f64..170.0)) {
            check(Three21::default(), j)?;
        }

        #[test]
        fn round_trips_with_random_dimensions(
            k in geometry(), j in prop::array::uniform6(-170.0f64..170.0),
        ) {
            check(k, j)?;
        }
    }
}
