//! `gantrykins`: ganged-joint kinematics from LinuxCNC 2.7 and earlier,
//! whose joint↔axis map lives in parameters that HAL files may change
//! (`setp gantrykins.joint-3 1`). LinuxCNC 2.8 folded it into trivkins
//! (`coordinates=xyyz kinstype=both`) and no longer ships it; configurations
//! written for it still load it and set its parameters.
//!
//! `loadrt gantrykins coordinates=XYYZ`: joint *j* drives the axis named
//! by the *j*-th letter (default `XYZABC`; letters case-insensitive,
//! blanks ignored, at most nine). Parameters `gantrykins.joint-0` …
//! `gantrykins.joint-8` (s32 rw) hold each joint's axis number (0 = X …
//! 8 = W), set from `coordinates=` at load and −1 for joints past its
//! letters; a value outside 0..8 leaves the joint out of the kinematics.
//! Both are read at every call. The forward kinematics set each axis
//! from the last joint that names it, as LinuxCNC's do, and leave axes
//! no joint names alone; the inverse gives every joint its axis' value.
//! The type is KINEMATICS_BOTH.
//!
//! LinuxCNC's module loops for ever on a character that is not an axis
//! letter and ignores letters past the ninth; here both are refused by
//! parameter name.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, Param, Result, Rw};

use super::loader::{bad_param, register};
use super::math::finite;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, AXIS_LETTERS, NUM_AXES};

/// The module's name.
const NAME: &str = "gantrykins";

/// How many `gantrykins.joint-N` parameters the module has (LinuxCNC
/// 2.7's joint count).
pub const JOINTS: usize = 9;

/// The default `coordinates=`.
pub const DEFAULT_COORDINATES: &str = "XYZABC";

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "coordinates",
    kind: ParamKind::Str,
    help: "axis letter of each joint, in joint order (default XYZABC)",
}];

/// The `gantrykins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: PARAMS,
    help: "ganged joints with the joint to axis map in gantrykins.joint-N parameters",
    load,
};

/// The axis number of each joint from a `coordinates=` value (−1 past
/// its letters), or why it was refused.
pub fn parse_coordinates(
    coordinates: &str,
) -> std::result::Result<[i32; JOINTS], super::trivkins::TrivkinsError> {
    use super::trivkins::TrivkinsError;
    let mut map = [-1; JOINTS];
    let letters = coordinates.chars().filter(|c| !matches!(c, ' ' | '\t'));
    for (n, c) in letters.enumerate() {
        let lower = c.to_ascii_lowercase();
        let axis = AXIS_LETTERS
            .iter()
            .position(|&l| l == lower)
            .ok_or(TrivkinsError::BadLetter(c))?;
        let slot = map
            .get_mut(n)
            .ok_or_else(|| TrivkinsError::TooManyLetters {
                given: coordinates.to_string(),
                max: JOINTS,
            })?;
        // An axis index is below NUM_AXES, so it fits an i32.
        *slot = i32::try_from(axis).unwrap_or(-1);
    }
    Ok(map)
}

/// The axis index joint map value `v` names, if any.
fn axis_of(v: i32) -> Option<usize> {
    usize::try_from(v).ok().filter(|&a| a < NUM_AXES)
}

/// Gantry kinematics over a fixed map (the parameters' values).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gantry {
    /// The axis number of each joint; outside 0..8 for none.
    pub map: [i32; JOINTS],
}

impl Kinematics for Gantry {
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
        for (&v, j) in self.map.iter().zip(joints) {
            if axis_of(v).is_some() {
                finite(std::slice::from_ref(j))?;
            }
        }
        for (&v, &j) in self.map.iter().zip(joints) {
            if let Some(a) = axis_of(v) {
                pose.0[a] = j;
            }
        }
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        for (&v, _) in self.map.iter().zip(joints.iter()) {
            if let Some(a) = axis_of(v) {
                finite(&pose.0[a..=a])?;
            }
        }
        for (&v, slot) in self.map.iter().zip(joints.iter_mut()) {
            if let Some(a) = axis_of(v) {
                *slot = pose.0[a];
            }
        }
        Ok(())
    }

    /// The axes some joint names.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(self.map.iter().any(|&v| axis_of(v) == Some(axis)))
    }
}

/// The module's kinematics: the map read from its parameters at every
/// call.
struct GantryParams {
    joints: [Param<i32, Rw>; JOINTS],
}

impl GantryParams {
    fn gantry(&self) -> Gantry {
        Gantry {
            map: std::array::from_fn(|i| self.joints[i].get()),
        }
    }
}

impl Kinematics for GantryParams {
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
        self.gantry().forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.gantry().inverse(pose, joints, flags)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.gantry().has_axis(axis)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let map = parse_coordinates(args.str("coordinates").unwrap_or(DEFAULT_COORDINATES))
        .map_err(|e| bad_param(NAME, "coordinates", e.to_string()))?;
    let b = host.new_rt_component(NAME)?;
    let c = b.component();
    let mut params = Vec::with_capacity(JOINTS);
    for (i, &axis) in map.iter().enumerate() {
        params.push(c.param(&format!("{NAME}.joint-{i}"), axis)?);
    }
    let joints: [Param<i32, Rw>; JOINTS] =
        params
            .try_into()
            .map_err(|_| hal_core::HalError::ModuleLoad {
                module: NAME.into(),
                reason: "joint parameters were not all made".into(),
            })?;
    register(host, b, NAME, Arc::new(GantryParams { joints }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn gantry(c: &str) -> Gantry {
        Gantry {
            map: parse_coordinates(c).unwrap(),
        }
    }

    #[test]
    fn coordinates_give_each_joint_its_axis() {
        assert_eq!(
            parse_coordinates("XYZABC").unwrap(),
            [0, 1, 2, 3, 4, 5, -1, -1, -1]
        );
        assert_eq!(
            parse_coordinates("x y\ty z").unwrap(),
            [0, 1, 1, 2, -1, -1, -1, -1, -1]
        );
        assert_eq!(parse_coordinates("").unwrap(), [-1; 9]);
        assert!(parse_coordinates("xyq")
            .unwrap_err()
            .to_string()
            .contains("'q'"));
        assert!(parse_coordinates("xyzabcuvwx")
            .unwrap_err()
            .to_string()
            .contains("more than 9"));
    }

    #[test]
    fn the_last_joint_of_an_axis_wins_and_unnamed_axes_are_kept() {
        let k = gantry("xyyz");
        let mut pose = Pose([9.0; 9]);
        let mut flags = KinsFlags::default();
        k.forward(&[1.0, 2.0, 2.5, 3.0], &mut pose, &mut flags)
            .unwrap();
        assert_eq!(pose.0, [1.0, 2.5, 3.0, 9.0, 9.0, 9.0, 9.0, 9.0, 9.0]);
        let mut j = [0.0; 5];
        k.inverse(&pose, &mut j, &mut flags).unwrap();
        assert_eq!(j, [1.0, 2.5, 2.5, 3.0, 0.0]);
        assert_eq!(k.has_axis(1), Some(true));
        assert_eq!(k.has_axis(3), Some(false));
        // Out-of-range map values leave the joint out.
        let k = Gantry {
            map: [0, 42, -7, 2, -1, -1, -1, -1, -1],
        };
        let mut j = [5.0; 4];
        k.inverse(&Pose([1.0; 9]), &mut j, &mut flags).unwrap();
        assert_eq!(j, [1.0, 5.0, 5.0, 1.0]);
    }

    #[test]
    fn non_numbers_are_refused_and_change_nothing() {
        let k = gantry("xyyz");
        let mut flags = KinsFlags::default();
        let mut pose = Pose::ZERO;
        pose.0[2] = f64::NAN;
        let mut j = [4.0; 4];
        assert_eq!(
            k.inverse(&pose, &mut j, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(j, [4.0; 4]);
        // A NaN on an axis no joint uses is not the module's concern.
        let mut pose = Pose::ZERO;
        pose.0[8] = f64::NAN;
        k.inverse(&pose, &mut j, &mut flags).unwrap();
        let mut out = Pose::ZERO;
        assert_eq!(
            k.forward(&[0.0, f64::INFINITY, 0.0, 0.0], &mut out, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(out, Pose::ZERO);
    }

    proptest! {
        #[test]
        fn any_map_round_trips_the_axes_it_names(
            map in prop::array::uniform9(-2i32..10),
            p in prop::array::uniform9(-1e6f64..1e6),
        ) {
            let k = Gantry { map };
            let mut flags = KinsFlags::default();
            let mut j = [0.0; JOINTS];
            k.inverse(&Pose(p), &mut j, &mut flags).unwrap();
            let mut back = Pose([f64::MAX; 9]);
            k.forward(&j, &mut back, &mut flags).unwrap();
            for (a, (&got, &given)) in back.0.iter().zip(&p).enumerate() {
                let want = if k.has_axis(a) == Some(true) { given } else { f64::MAX };
                prop_assert_eq!(got, want);
            }
        }
    }
}
