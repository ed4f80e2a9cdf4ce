//! `rotarydeltakins`: rotary delta robots (Clavel's delta). Three hips
//! sit on a platform circle of radius `platformradius` in the plane Z = 0,
//! 120° apart; each turns a thigh of `thighlength` (joints 0–2, degrees:
//! 0 = thigh straight out, positive = knee down), and a parallelogram
//! shin of `shinlength` joins each knee to the foot, whose ankles sit
//! `footradius` from the controlled point. The foot hangs below the
//! platform, so Z is negative. Joint 0's thigh swings in the YZ plane on
//! the −Y side; joint 1's at 30° and joint 2's at 150° from +X. Joints
//! 3–8, when present, are A B C U V W one to one.
//!
//! Pins (float in, LinuxCNC's names and defaults):
//! `rotarydeltakins.platformradius` 10, `rotarydeltakins.thighlength`
//! 10, `rotarydeltakins.shinlength` 14, `rotarydeltakins.footradius` 6.
//! Type KINEMATICS_BOTH.
//!
//! The inverse kinematics pick the knee that points outwards, as
//! LinuxCNC's do; the forward kinematics the foot below the knees.
//! Refused: feet a leg cannot reach, feet above their knees (the other
//! branch, which the forward kinematics would not give back), hip angles
//! whose shins do not meet, and non-positive lengths.

use std::f64::consts::TAU;
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Pin, Result};

use super::loader::{float_in, register};
use super::math::{below_plane, deg, finite, lower_sphere_intersection, rad};
use super::pinned::{PinGeometry, Pinned};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The `rotarydeltakins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "rotarydeltakins",
    params: &[],
    help: "rotary delta robot kinematics",
    load,
};

/// LinuxCNC's defaults: platform radius, thigh, shin, foot radius.
pub const DEFAULTS: [f64; 4] = [10.0, 10.0, 14.0, 6.0];

/// The fewest joints (the three hips).
pub const MIN_JOINTS: usize = 3;

/// Direction (radians from +X) in which each leg points out.
const LEG_DIRECTION: [f64; 3] = [0.75 * TAU, TAU / 12.0, 5.0 * TAU / 12.0];

/// A rotary delta of fixed geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotaryDelta {
    /// Centre to hip axis.
    pub platform_radius: f64,
    /// Hip to knee.
    pub thigh: f64,
    /// Knee to ankle.
    pub shin: f64,
    /// Controlled point to ankle.
    pub foot_radius: f64,
}

impl Default for RotaryDelta {
    fn default() -> Self {
        let [platform_radius, thigh, shin, foot_radius] = DEFAULTS;
        RotaryDelta {
            platform_radius,
            thigh,
            shin,
            foot_radius,
        }
    }
}

impl RotaryDelta {
    fn check(&self) -> std::result::Result<(), KinsError> {
        let v = [
            self.platform_radius,
            self.thigh,
            self.shin,
            self.foot_radius,
        ];
        finite(&v)?;
        if self.platform_radius > 0.0
            && self.thigh > 0.0
            && self.shin > 0.0
            && self.foot_radius >= 0.0
        {
            Ok(())
        } else {
            Err(KinsError::NoSolution)
        }
    }

    /// Where the foot's centre would be for leg `i`'s knee at hip angle
    /// `q` (radians) if the shin had no length: the knee moved in by the
    /// foot radius. The foot is `shin` away from it.
    fn shifted_knee(&self, i: usize, q: f64) -> [f64; 3] {
        let (s, c) = LEG_DIRECTION[i].sin_cos();
        let reach = self.platform_radius - self.foot_radius + self.thigh * q.cos();
        [reach * c, reach * s, -self.thigh * q.sin()]
    }

    /// Hip angle (radians) of leg `i` with the foot at `p`, knee out.
    fn hip_angle(&self, i: usize, p: [f64; 3]) -> Option<f64> {
        let (sd, cd) = LEG_DIRECTION[i].sin_cos();
        // The foot in the leg's own frame: out along the leg, across it,
        // and up; shifted so that the hip is the origin and the ankle's
        // offset is taken off.
        let out = p[0] * cd + p[1] * sd + self.foot_radius - self.platform_radius;
        let across = -p[0] * sd + p[1] * cd;
        let up = p[2];
        // |foot − thigh·(cos q, 0, −sin q)| = shin gives
        // out·cos q − up·sin q = k.
        let k = (out * out + across * across + up * up + self.thigh * self.thigh
            - self.shin * self.shin)
            / (2.0 * self.thigh);
        let rho = out.hypot(up);
        if rho.is_nan() || rho <= 0.0 || k.abs() >= rho {
            return None;
        }
        let phi = up.atan2(out);
        let spread = (k / rho).acos();
        // Of the two knees, the one further out (larger cos q).
        let a = spread - phi;
        let b = -spread - phi;
        Some(if a.cos() >= b.cos() { a } else { b })
    }
}

impl Kinematics for RotaryDelta {
    fn name(&self) -> &str {
        "rotarydeltakins"
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
        if joints.len() < MIN_JOINTS {
            return Err(KinsError::Unsupported);
        }
        let n = joints.len().min(NUM_AXES);
        finite(&joints[..n])?;
        self.check()?;
        let knees = [0, 1, 2].map(|i| self.shifted_knee(i, rad(joints[i])));
        let p = lower_sphere_intersection(knees, self.shin).ok_or(KinsError::NoSolution)?;
        pose.0[..3].copy_from_slice(&p);
        pose.0[3..n].copy_from_slice(&joints[3..n]);
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        if joints.len() < MIN_JOINTS {
            return Err(KinsError::Unsupported);
        }
        let n = joints.len().min(NUM_AXES);
        finite(&pose.0[..n])?;
        self.check()?;
        let p = [pose.0[0], pose.0[1], pose.0[2]];
        let mut q = [0.0; 3];
        for (i, h) in q.iter_mut().enumerate() {
            *h = self.hip_angle(i, p).ok_or(KinsError::NoSolution)?;
        }
        // The foot must hang below its knees: above them it is the other
        // of the shins' two meeting points, the one the forward
        // kinematics do not give.
        let knees = [0, 1, 2].map(|i| self.shifted_knee(i, q[i]));
        if !below_plane(p, knees) {
            return Err(KinsError::NoSolution);
        }
        let hips = q.map(deg);
        finite(&hips)?;
        joints[..3].copy_from_slice(&hips);
        joints[3..n].copy_from_slice(&pose.0[3..n]);
        Ok(())
    }

    /// X, Y and Z always; A to W only with enough joints, which the
    /// module does not know.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        match axis {
            0..=2 => Some(true),
            3..=8 => None,
            _ => Some(false),
        }
    }
}

/// The module's kinematics: the lengths read from the pins at every call.
struct Rotarydeltakins {
    pins: [Pin<f64, In>; 4],
}

impl PinGeometry for Rotarydeltakins {
    const NAME: &'static str = "rotarydeltakins";
    type Geometry = RotaryDelta;

    fn geometry(&self) -> RotaryDelta {
        let [platform_radius, thigh, shin, foot_radius] = self.pins.each_ref().map(|p| p.get());
        RotaryDelta {
            platform_radius,
            thigh,
            shin,
            foot_radius,
        }
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("rotarydeltakins")?;
    let c = b.component();
    let names = ["platformradius", "thighlength", "shinlength", "footradius"];
    let p = |i: usize| float_in(c, &format!("rotarydeltakins.{}", names[i]), DEFAULTS[i]);
    let kins = Rotarydeltakins {
        pins: [p(0)?, p(1)?, p(2)?, p(3)?],
    };
    register(host, b, "rotarydeltakins", Arc::new(Pinned(kins)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn inv(k: &RotaryDelta, p: [f64; 3]) -> std::result::Result<[f64; 3], KinsError> {
        crate::kins::testing::inverse(k, &p, [0.0; 3])
    }

    fn fwd(k: &RotaryDelta, j: [f64; 3]) -> std::result::Result<[f64; 3], KinsError> {
        crate::kins::testing::forward(k, &j)
    }

    #[test]
    fn agrees_with_linuxcnc_on_reference_points() {
        // Hip angles LinuxCNC's formulas give for these feet with the
        // default geometry.
        let k = RotaryDelta::default();
        for (p, want) in [
            ([0.0, 0.0, -15.0], [42.772031019379895; 3]),
            (
                [2.0, 0.0, -15.0],
                [43.61007185407084, 35.04777709517646, 51.38394772934832],
            ),
            (
                [0.0, 2.0, -15.0],
                [52.50935677591935, 38.753382107809074, 38.753382107809074],
            ),
            (
                [1.0, -1.0, -12.0],
                [27.59551293171205, 31.41537344713408, 41.10705379159916],
            ),
        ] {
            let j = inv(&k, p).unwrap();
            for i in 0..3 {
                assert!((j[i] - want[i]).abs() < 1e-9, "{p:?}: {j:?}");
            }
            let back = fwd(&k, j).unwrap();
            for a in 0..3 {
                assert!((back[a] - p[a]).abs() < 1e-9, "{p:?}: {back:?}");
            }
        }
        // One knee down: the foot moves away from that leg (+Y for leg
        // 0), as LinuxCNC's forward kinematics have it.
        let p = fwd(&k, [30.0, 0.0, 0.0]).unwrap();
        let want = [0.0, 1.3092318993898906, -4.076169577566467];
        for a in 0..3 {
            assert!((p[a] - want[a]).abs() < 1e-9, "{p:?}");
        }
        // Thighs straight out put the foot in the hips' plane, where the
        // shins are flat and cannot carry it: singular, refused.
        assert_eq!(fwd(&k, [0.0; 3]), Err(KinsError::NoSolution));
    }

    #[test]
    fn unreachable_feet_are_refused() {
        let k = RotaryDelta::default();
        assert_eq!(inv(&k, [0.0, 0.0, -40.0]), Err(KinsError::NoSolution));
        assert_eq!(inv(&k, [30.0, 0.0, -10.0]), Err(KinsError::NoSolution));
        assert_eq!(inv(&k, [0.0, f64::NAN, -10.0]), Err(KinsError::NoSolution));
        // Knees so far apart the shins cannot meet.
        let short = RotaryDelta {
            shin: 3.0,
            ..RotaryDelta::default()
        };
        assert_eq!(fwd(&short, [0.0, 0.0, 0.0]), Err(KinsError::NoSolution));
        let broken = RotaryDelta {
            thigh: 0.0,
            ..RotaryDelta::default()
        };
        assert_eq!(inv(&broken, [0.0, 0.0, -15.0]), Err(KinsError::NoSolution));
    }

    fn geometry() -> impl Strategy<Value = RotaryDelta> {
        (5.0f64..50.0, 5.0f64..50.0, 1.3f64..2.5, 0.1f64..0.9).prop_map(|(pf, tl, sr, fr)| {
            RotaryDelta {
                platform_radius: pf,
                thigh: tl,
                shin: tl * sr,
                foot_radius: pf * fr,
            }
        })
    }

    fn check(k: RotaryDelta, q: [f64; 3]) -> std::result::Result<(), TestCaseError> {
        // Feet reached from hip angles; those whose outward knees would
        // sit below them are outside the module's workspace.
        let Ok(p) = fwd(&k, q) else { return Ok(()) };
        let Ok(j) = inv(&k, p) else { return Ok(()) };
        let scale = k.thigh + k.shin;
        let back = fwd(&k, j).unwrap();
        for a in 0..3 {
            prop_assert!(
                (back[a] - p[a]).abs() < 1e-9 * scale,
                "{:?} vs {:?}",
                back,
                p
            );
        }
        let j2 = inv(&k, back).unwrap();
        for i in 0..3 {
            prop_assert!((j2[i] - j[i]).abs() < 1e-6, "{:?} vs {:?}", j2, j);
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn round_trips_with_the_default_geometry(q in prop::array::uniform3(-20.0f64..70.0)) {
            check(RotaryDelta::default(), q)?;
        }

        #[test]
        fn round_trips_with_random_geometries(
            k in geometry(), q in prop::array::uniform3(-20.0f64..70.0),
        ) {
            check(k, q)?;
        }
    }
}
