//! `5axiskins`: a bridge mill whose head tilts (B) and turns (C) about a
//! pivot above the tool, with W moving the tool along its own axis.
//! Switchable (type 0 this kinematics, type 1 identity, type 2 user; see
//! [`super::switchkins`]; `sparm=identityfirst` swaps types 0 and 1).
//!
//! The tool tip hangs `L + W` below the pivot (`L = pivot-length`); B is
//! the tool's angle from straight down, C the direction it leans towards
//! in the XY plane. The X Y Z joints place the spindle nose when the
//! head is upright, so the pivot is at `(jx, jy, jz + L)`:
//!
//! ```text
//! forward:  X = jx + (L + W)·sin B·cos C
//!           Y = jy + (L + W)·sin B·sin C
//!           Z = jz + L − (L + W)·cos B
//! inverse:  jx = X − (L + W)·sin B·cos C, and likewise for Y and Z
//! ```
//!
//! B, C and W pass through; so do A, U and V when `coordinates=` names
//! them. The W joint moves nothing itself (its motion is in X Y Z), but
//! a joint is needed to show W.
//!
//! Joints follow `coordinates=` (default `xyzbcw`): it must contain the
//! six letters, may repeat letters (a gantry's second joint gets the same
//! value) and may add A, U and V, which map one to one.
//!
//! Pin (float in, LinuxCNC's name): `5axiskins.pivot-length` (default
//! 250; configurations add the tool length to the machine's pivot
//! length).

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Pin, Result};

use super::loader::float_in;
use super::math::{finite, rad};
use super::switchkins::{self, SwitchSpec};
use super::trivkins::{Trivkins, MAX_JOINTS};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The module's name, and its pins' prefix.
const NAME: &str = "5axiskins";

/// The `5axiskins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: switchkins::PARAMS,
    help: "bridge mill with a tilting (B) and turning (C) head, W along the tool (switchable)",
    load,
};

/// LinuxCNC's default `5axiskins.pivot-length`.
pub const DEFAULT_PIVOT_LENGTH: f64 = 250.0;

/// How the module switches: X Y Z B C W required, duplicates and A U V
/// allowed, `sparm=identityfirst` honoured.
pub const SPEC: SwitchSpec = SwitchSpec {
    module: NAME,
    required: "xyzbcw",
    requires_letters: true,
    allow_duplicates: true,
    max_joints: MAX_JOINTS,
    honours_identity_first: true,
    forward_iterates: false,
    gui_pins: false,
};

/// The head's geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BridgeHead {
    /// From the pivot to the tool tip with W = 0.
    pub pivot_length: f64,
}

impl BridgeHead {
    /// The tool tip's offset from the upright spindle nose, for tilt `b`,
    /// direction `c` (degrees) and tool motion `w`.
    pub fn tip_offset(&self, b: f64, c: f64, w: f64) -> [f64; 3] {
        let reach = self.pivot_length + w;
        let (sin_b, cos_b) = rad(b).sin_cos();
        let (sin_c, cos_c) = rad(c).sin_cos();
        [
            reach * sin_b * cos_c,
            reach * sin_b * sin_c,
            self.pivot_length - reach * cos_b,
        ]
    }

    /// Forward kinematics through the joint map `map`.
    fn forward(
        &self,
        map: &Trivkins,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        finite(&[self.pivot_length])?;
        finite(&joints[..joints.len().min(map.axis_of_joint().len())])?;
        let mut jp = *pose;
        map.forward(joints, &mut jp, &mut KinsFlags::default())?;
        let [x, y, z, _, b, c, _, _, w] = jp.0;
        let d = self.tip_offset(b, c, w);
        let tip = [x + d[0], y + d[1], z + d[2]];
        finite(&tip)?;
        jp.0[..3].copy_from_slice(&tip);
        *pose = jp;
        Ok(())
    }

    /// Inverse kinematics through the joint map `map`.
    fn inverse(
        &self,
        map: &Trivkins,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        finite(&[self.pivot_length])?;
        let [x, y, z, _, b, c, _, _, w] = pose.0;
        finite(&[x, y, z, b, c, w])?;
        let d = self.tip_offset(b, c, w);
        let mut jp = *pose;
        let nose = [x - d[0], y - d[1], z - d[2]];
        finite(&nose)?;
        jp.0[..3].copy_from_slice(&nose);
        for &a in map.axis_of_joint() {
            finite(&[jp.0[a]])?;
        }
        map.inverse(&jp, joints, &mut KinsFlags::default())
    }
}

/// The bridge mill of fixed geometry with its joint map.
#[derive(Debug, Clone, PartialEq)]
pub struct BridgeKins {
    /// The geometry.
    pub head: BridgeHead,
    map: Trivkins,
}

impl BridgeKins {
    /// The kinematics with joints mapped by `coordinates` (which must
    /// contain X Y Z B C W); a refused map is the error `loadrt` would
    /// give for it.
    pub fn new(head: BridgeHead, coordinates: &str) -> Result<BridgeKins> {
        let map = switchkins::identity_map(&SPEC, Some(coordinates))?;
        Ok(BridgeKins { head, map })
    }
}

impl Kinematics for BridgeKins {
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
        self.head.forward(&self.map, joints, pose)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.head.inverse(&self.map, pose, joints)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.map.has_axis(axis)
    }
}

/// The module's own kinematics: the pivot length read from its pin at
/// every call.
struct FiveAxisKins {
    map: Trivkins,
    pivot_length: Pin<f64, In>,
}

impl FiveAxisKins {
    fn export(c: &Component, map: &Trivkins) -> Result<FiveAxisKins> {
        Ok(FiveAxisKins {
            map: map.clone(),
            pivot_length: float_in(c, &format!("{NAME}.pivot-length"), DEFAULT_PIVOT_LENGTH)?,
        })
    }

    fn head(&self) -> BridgeHead {
        BridgeHead {
            pivot_length: self.pivot_length.get(),
        }
    }
}

impl Kinematics for FiveAxisKins {
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
        self.head().forward(&self.map, joints, pose)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.head().inverse(&self.map, pose, joints)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.map.has_axis(axis)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, SPEC, FiveAxisKins::export)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const HEAD: BridgeHead = BridgeHead {
        pivot_length: 250.0,
    };

    fn kins(coordinates: &str) -> BridgeKins {
        BridgeKins::new(HEAD, coordinates).unwrap()
    }

    fn fwd(k: &BridgeKins, j: &[f64]) -> Pose {
        let mut p = Pose::ZERO;
        k.forward(j, &mut p, &mut KinsFlags::default()).unwrap();
        p
    }

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    #[test]
    fn an_upright_head_is_identity() {
        let k = kins("xyzbcw");
        let p = fwd(&k, &[1.0, 2.0, 3.0, 0.0, 45.0, 0.0]);
        assert!(close(&p.0[..3], &[1.0, 2.0, 3.0], 1e-12), "{p:?}");
        assert_eq!(p.0[5], 45.0);
    }

    #[test]
    fn the_tip_swings_about_the_pivot() {
        let k = kins("xyzbcw");
        // B = 90°, C = 0: the tool points along +X at the pivot's height.
        let p = fwd(&k, &[0.0, 0.0, 0.0, 90.0, 0.0, 0.0]);
        assert!(close(&p.0[..3], &[250.0, 0.0, 250.0], 1e-9), "{p:?}");
        // C = 90° turns that lean towards +Y.
        let p = fwd(&k, &[0.0, 0.0, 0.0, 90.0, 90.0, 0.0]);
        assert!(close(&p.0[..3], &[0.0, 250.0, 250.0], 1e-9), "{p:?}");
        // W lengthens the tool: upright, the tip goes down by W.
        let p = fwd(&k, &[0.0, 0.0, 0.0, 0.0, 0.0, 10.0]);
        assert!(close(&p.0[..3], &[0.0, 0.0, -10.0], 1e-9), "{p:?}");
        assert_eq!(p.0[8], 10.0);
    }

    #[test]
    fn gantry_joints_and_extra_letters_follow_coordinates() {
        // The sample configuration's xyzbcwy: joint 6 is Y's second.
        let k = kins("xyzbcwy");
        let mut p = Pose::ZERO;
        p.0[..3].copy_from_slice(&[10.0, 20.0, 30.0]);
        p.0[4] = 30.0;
        let mut j = [0.0; 7];
        k.inverse(&p, &mut j, &mut KinsFlags::default()).unwrap();
        assert_eq!(j[1], j[6]);
        assert!(close(&fwd(&k, &j).0[..3], &p.0[..3], 1e-9));
        let k = kins("xyzbcwuv");
        p.0[6] = 4.0;
        p.0[7] = 5.0;
        let mut j = [0.0; 8];
        k.inverse(&p, &mut j, &mut KinsFlags::default()).unwrap();
        assert_eq!(j[6..], [4.0, 5.0]);
        assert_eq!(k.has_axis(3), Some(false));
        // The six letters are required.
        let e = BridgeKins::new(HEAD, "xyzbc").unwrap_err().to_string();
        assert!(e.contains("lacks W"), "{e}");
    }

    #[test]
    fn non_numbers_are_refused() {
        let k = kins("xyzbcw");
        let mut p = Pose::ZERO;
        p.0[4] = f64::NAN;
        let mut j = [0.0; 6];
        assert_eq!(
            k.inverse(&p, &mut j, &mut KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
        let mut back = Pose::ZERO;
        assert_eq!(
            k.forward(
                &[0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0],
                &mut back,
                &mut KinsFlags::default()
            ),
            Err(KinsError::NoSolution)
        );
        let bad = BridgeKins::new(
            BridgeHead {
                pivot_length: f64::NAN,
            },
            "xyzbcw",
        )
        .unwrap();
        assert_eq!(
            bad.inverse(&Pose::ZERO, &mut j, &mut KinsFlags::default()),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn round_trips(
            xyz in prop::array::uniform3(-500.0f64..500.0),
            b in -120.0f64..120.0, c in -720.0f64..720.0, w in -100.0f64..100.0,
            pivot in 0.0f64..400.0,
        ) {
            let k = BridgeKins::new(BridgeHead { pivot_length: pivot }, "xyzbcw").unwrap();
            let mut p = Pose::ZERO;
            p.0[..3].copy_from_slice(&xyz);
            p.0[4] = b;
            p.0[5] = c;
            p.0[8] = w;
            let mut j = [0.0; 6];
            k.inverse(&p, &mut j, &mut KinsFlags::default()).unwrap();
            let back = fwd(&k, &j);
            prop_assert!(close(&back.0, &p.0, 1e-9), "{:?} vs {:?}", back, p);
        }
    }
}
