//! `scarakins`: SCARA robots, switchable (type 0 SCARA, type 1 identity,
//! type 2 user; see [`super::switchkins`]).
//!
//! Joints: 0 the shoulder (degrees; 0 = inner arm along X), 1 the elbow
//! (degrees; 0 = outer arm straight out), 2 the vertical slide (length,
//! positive down), 3 the wrist (degrees), 4 and 5 carried to A and B (the
//! tilts a SCARA display shows). World C is the tool's heading,
//! `j0 + j1 + j3`.
//!
//! Pins (float in, LinuxCNC's names and defaults): `scarakins.D1` 490
//! (ground to inner arm), `D2` 340 (inner arm length), `D3` 50 (inner to
//! outer arm height), `D4` 250 (outer arm length), `D5` 50 (effector to
//! tool tip, down), `D6` 50 (tool tip off the wrist axis).
//!
//! The elbow's side comes from the inverse flags: bit 0 set bends it the
//! negative way. The forward kinematics set that bit when joint 1 is
//! negative, so forward then inverse gives the same joints back.
//! (LinuxCNC sets it for joint 1 below 90°, which flips an elbow between
//! 0° and 90° to the other side; this module keeps it.)
//!
//! Refused: tool positions beyond the arm's reach or inside the circle
//! it cannot fold into, and the wrist on the column's axis, where the
//! shoulder angle is undefined.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Pin, Result};

use super::loader::float_in;
use super::math::{deg, finite, rad};
use super::pinned::{PinGeometry, Pinned};
use super::switchkins::{self, SwitchSpec};
use super::trivkins::Trivkins;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `scarakins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "scarakins",
    params: switchkins::PARAMS,
    help: "SCARA robot kinematics (switchable)",
    load,
};

/// Inverse flag: bend the elbow the negative way.
pub const ELBOW_NEGATIVE: u64 = 0x01;

/// LinuxCNC's default dimensions, D1 to D6.
pub const DEFAULTS: [f64; 6] = [490.0, 340.0, 50.0, 250.0, 50.0, 50.0];

/// Joints the kinematics use (4 and 5 are carried to A and B).
pub const JOINTS: usize = 6;

/// Slack for a reach computed right at the arm's limit.
const REACH_SLACK: f64 = 1e-9;

/// A SCARA of fixed dimensions (`d[0]` is D1 … `d[5]` is D6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scara {
    /// D1 … D6, as the pins.
    pub d: [f64; 6],
}

impl Default for Scara {
    fn default() -> Self {
        Scara { d: DEFAULTS }
    }
}

impl Kinematics for Scara {
    fn name(&self) -> &str {
        "scarakins"
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
        if joints.len() < 4 {
            return Err(KinsError::Unsupported);
        }
        let n = joints.len().min(JOINTS);
        finite(&joints[..n])?;
        finite(&self.d)?;
        let [d1, d2, d3, d4, d5, d6] = self.d;
        let a0 = rad(joints[0]);
        let a1 = a0 + rad(joints[1]);
        let a3 = a1 + rad(joints[3]);
        let x = d2 * a0.cos() + d4 * a1.cos() + d6 * a3.cos();
        let y = d2 * a0.sin() + d4 * a1.sin() + d6 * a3.sin();
        let z = d1 + d3 - joints[2] - d5;
        let c = deg(a3);
        finite(&[x, y, z, c])?;
        pose.0[0] = x;
        pose.0[1] = y;
        pose.0[2] = z;
        pose.0[5] = c;
        for (axis, j) in (3..5).zip(4..n) {
            pose.0[axis] = joints[j];
        }
        flags.inverse = if rad(joints[1]).sin() < 0.0 {
            ELBOW_NEGATIVE
        } else {
            0
        };
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        if joints.len() < 4 {
            return Err(KinsError::Unsupported);
        }
        let [x, y, z, a, b, c, ..] = pose.0;
        finite(&[x, y, z, a, b, c])?;
        finite(&self.d)?;
        let [d1, d2, d3, d4, d5, d6] = self.d;
        if d2 <= 0.0 || d4 <= 0.0 {
            return Err(KinsError::NoSolution);
        }
        let heading = rad(c);
        // The wrist axis, where the tool offset D6 hangs from.
        let xt = x - d6 * heading.cos();
        let yt = y - d6 * heading.sin();
        let r2 = xt * xt + yt * yt;
        if r2 <= (d2 + d4) * (d2 + d4) * 1e-24 {
            return Err(KinsError::NoSolution);
        }
        let cos_elbow = (r2 - d2 * d2 - d4 * d4) / (2.0 * d2 * d4);
        if !(-1.0 - REACH_SLACK..=1.0 + REACH_SLACK).contains(&cos_elbow) {
            return Err(KinsError::NoSolution);
        }
        let mut q1 = cos_elbow.clamp(-1.0, 1.0).acos();
        if flags.inverse & ELBOW_NEGATIVE != 0 {
            q1 = -q1;
        }
        let q0 = yt.atan2(xt) - (d4 * q1.sin()).atan2(d2 + d4 * q1.cos());
        let (q0, q1) = (deg(q0), deg(q1));
        let out = [q0, q1, d1 + d3 - d5 - z, c - (q0 + q1), a, b];
        finite(&out)?;
        let n = joints.len().min(JOINTS);
        joints[..n].copy_from_slice(&out[..n]);
        flags.forward = 0;
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < 6)
    }
}

/// The module's own kinematics: the dimensions read from the pins at
/// every call.
struct Scarakins {
    d: [Pin<f64, In>; 6],
}

impl Scarakins {
    fn export(c: &Component) -> Result<Pinned<Scarakins>> {
        let p = |i: usize| float_in(c, &format!("scarakins.D{}", i + 1), DEFAULTS[i]);
        Ok(Pinned(Scarakins {
            d: [p(0)?, p(1)?, p(2)?, p(3)?, p(4)?, p(5)?],
        }))
    }
}

impl PinGeometry for Scarakins {
    const NAME: &'static str = "scarakins";
    type Geometry = Scara;

    fn geometry(&self) -> Scara {
        Scara {
            d: self.d.each_ref().map(|p| p.get()),
        }
    }
}

/// How scarakins switches: XYZABC, no duplicates, six joints at most.
pub const SPEC: SwitchSpec = SwitchSpec {
    module: "scarakins",
    required: "xyzabc",
    requires_letters: false,
    allow_duplicates: false,
    max_joints: JOINTS,
    honours_identity_first: false,
    forward_iterates: false,
    gui_pins: false,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, SPEC, |c, _: &Trivkins| Scarakins::export(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(k: &Scara, j: [f64; 6]) -> (Pose, KinsFlags) {
        let mut p = Pose::ZERO;
        let mut f = KinsFlags::default();
        k.forward(&j, &mut p, &mut f).unwrap();
        (p, f)
    }

    fn inv(k: &Scara, p: &Pose, f: KinsFlags) -> std::result::Result<[f64; 6], KinsError> {
        let mut j = [0.0; 6];
        let mut f = f;
        k.inverse(p, &mut j, &mut f).map(|()| j)
    }

    #[test]
    fn stretched_out_along_x() {
        let k = Scara::default();
        let (p, f) = fwd(&k, [0.0, 0.0, 10.0, 0.0, 1.0, 2.0]);
        // D2 + D4 + D6 out, D1 + D3 − D5 − j2 up.
        assert_eq!(p.0[..6], [640.0, 0.0, 480.0, 1.0, 2.0, 0.0]);
        assert_eq!(f.inverse, 0);
        // Fully stretched is the edge of the reach, still solvable.
        let j = inv(&k, &p, f).unwrap();
        assert!(j
            .iter()
            .zip([0.0, 0.0, 10.0, 0.0, 1.0, 2.0])
            .all(|(a, b)| (a - b).abs() < 1e-6));
    }

    #[test]
    fn elbow_side_comes_back_through_the_flags() {
        let k = Scara::default();
        for elbow in [45.0, -45.0, 120.0, -120.0] {
            let j = [30.0, elbow, 5.0, 10.0, 0.0, 0.0];
            let (p, f) = fwd(&k, j);
            let back = inv(&k, &p, f).unwrap();
            assert!((back[1] - elbow).abs() < 1e-9, "{elbow}: {back:?}");
        }
    }

    #[test]
    fn unreachable_and_singular_poses_are_refused() {
        let k = Scara::default();
        let mut p = Pose::ZERO;
        p.0[0] = 700.0; // beyond D2 + D4 + D6
        assert_eq!(
            inv(&k, &p, KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        p.0[0] = 50.0 + 50.0; // wrist 50 from the column: inside D2 − D4
        assert_eq!(
            inv(&k, &p, KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        p.0[0] = 50.0; // wrist on the column's axis
        let equal = Scara {
            d: [490.0, 300.0, 50.0, 300.0, 50.0, 50.0],
        };
        assert_eq!(
            inv(&equal, &p, KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        p.0[0] = f64::NAN;
        assert_eq!(
            inv(&k, &p, KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        let broken = Scara {
            d: [490.0, 0.0, 50.0, 250.0, 50.0, 50.0],
        };
        p.0[0] = 300.0;
        assert_eq!(
            inv(&broken, &p, KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
    }

    fn geometry() -> impl Strategy<Value = Scara> {
        (
            0.0f64..1000.0,
            10.0f64..800.0,
            -100.0f64..100.0,
            10.0f64..800.0,
            -100.0f64..100.0,
            0.0f64..100.0,
        )
            .prop_map(|(d1, d2, d3, d4, d5, d6)| Scara {
                d: [d1, d2, d3, d4, d5, d6],
            })
    }

    fn check_round_trip(k: Scara, j: [f64; 6]) -> std::result::Result<(), TestCaseError> {
        let (p, f) = fwd(&k, j);
        let back = inv(&k, &p, f).unwrap();
        let wrap = |a: f64| crate::kins::math::wrap_degrees(a);
        for i in [0, 1, 3] {
            prop_assert!(
                wrap(back[i] - j[i]).abs() < 1e-6,
                "joint {}: {:?} vs {:?}",
                i,
                back,
                j
            );
        }
        for i in [2, 4, 5] {
            prop_assert!(
                (back[i] - j[i]).abs() < 1e-6,
                "joint {}: {:?} vs {:?}",
                i,
                back,
                j
            );
        }
        let (p2, _) = fwd(&k, back);
        for a in 0..6 {
            let d = if a == 5 {
                wrap(p2.0[a] - p.0[a])
            } else {
                p2.0[a] - p.0[a]
            };
            prop_assert!(d.abs() < 1e-6, "axis {}: {:?} vs {:?}", a, p2, p);
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn round_trips_with_default_dimensions(
            q0 in -180.0f64..180.0, q1 in 2.0f64..178.0, neg in any::<bool>(),
            z in -200.0f64..200.0, q3 in -180.0f64..180.0,
            a in -90.0f64..90.0, b in -90.0f64..90.0,
        ) {
            let q1 = if neg { -q1 } else { q1 };
            check_round_trip(Scara::default(), [q0, q1, z, q3, a, b])?;
        }

        #[test]
        fn round_trips_with_random_dimensions(
            k in geometry(),
            q0 in -180.0f64..180.0, q1 in 2.0f64..178.0, neg in any::<bool>(),
            z in -200.0f64..200.0, q3 in -180.0f64..180.0,
        ) {
            let q1 = if neg { -q1 } else { q1 };
            check_round_trip(k, [q0, q1, z, q3, 0.0, 0.0])?;
        }
    }
}
