//! `gentrivkins`: LinuxCNC 2.7's generalised trivial kinematics, which
//! 2.8 renamed trivkins; configurations written for 2.7 still load it.
//!
//! `loadrt gentrivkins coordinates=XYYZ kinstype=B`: joint *j* drives the
//! axis named by the *j*-th letter of `coordinates` (default
//! `XYZABCUVW`; letters case-insensitive, blanks ignored, at most nine);
//! `kinstype` is read as trivkins reads it (`1` identity, the default, `B`
//! both, `F` forward only, `I` inverse only; the first character
//! decides). The map is fixed at load: unlike [`super::gantrykins`] the
//! module has no pins or parameters. The forward kinematics set each axis
//! from the last joint that names it, as LinuxCNC 2.7's do; the inverse
//! gives every joint its axis' value.
//!
//! LinuxCNC's module loops for ever on a character that is not an axis
//! letter and takes any unknown kinstype as identity; here both are
//! refused by parameter name.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, Result};

use super::gantrykins::{parse_coordinates, Gantry};
use super::loader::{bad_param, register};
use super::trivkins::{parse_kinstype, DEFAULT_COORDINATES};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The module's name.
const NAME: &str = "gentrivkins";

const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "coordinates",
        kind: ParamKind::Str,
        help: "axis letter of each joint, in joint order (default XYZABCUVW)",
    },
    ParamDecl {
        name: "kinstype",
        kind: ParamKind::Str,
        help: "1 identity (default), B both, F forward only, I inverse only",
    },
];

/// The `gentrivkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: PARAMS,
    help: "LinuxCNC 2.7's generalised trivial kinematics (joint to axis map)",
    load,
};

/// The kinematics: a fixed joint map and the type motion is told.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gentriv {
    /// The joint↔axis map.
    pub map: Gantry,
    /// What motion may assume.
    pub kins_type: KinematicsType,
}

impl Kinematics for Gentriv {
    fn name(&self) -> &str {
        NAME
    }

    fn kins_type(&self) -> KinematicsType {
        self.kins_type
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.map.forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.map.inverse(pose, joints, flags)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.map.has_axis(axis)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let kins_type = parse_kinstype(args.str("kinstype").unwrap_or("1"))
        .map_err(|e| bad_param(NAME, "kinstype", e.to_string()))?;
    let map = parse_coordinates(args.str("coordinates").unwrap_or(DEFAULT_COORDINATES))
        .map_err(|e| bad_param(NAME, "coordinates", e.to_string()))?;
    let kins = Gentriv {
        map: Gantry { map },
        kins_type,
    };
    let b = host.new_rt_component(NAME)?;
    register(host, b, NAME, Arc::new(kins))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn gentriv(c: &str) -> Gentriv {
        Gentriv {
            map: Gantry {
                map: parse_coordinates(c).unwrap(),
            },
            kins_type: KinematicsType::Both,
        }
    }

    #[test]
    fn the_default_map_is_one_joint_per_axis() {
        let k = gentriv(DEFAULT_COORDINATES);
        let p = Pose([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
        let mut j = [0.0; 9];
        let mut flags = KinsFlags::default();
        k.inverse(&p, &mut j, &mut flags).unwrap();
        assert_eq!(j, p.0);
        let mut back = Pose::ZERO;
        k.forward(&j, &mut back, &mut flags).unwrap();
        assert_eq!(back, p);
        assert_eq!(k.name(), "gentrivkins");
    }

    proptest! {
        #[test]
        fn gantry_maps_round_trip(
            letters in prop::collection::vec(prop::sample::select(&['x', 'y', 'z', 'a', 'Y'][..]), 1..9),
            p in prop::array::uniform9(-1e6f64..1e6),
        ) {
            let text: String = letters.into_iter().collect();
            let k = gentriv(&text);
            let mut flags = KinsFlags::default();
            let mut j = [0.0; 9];
            k.inverse(&Pose(p), &mut j, &mut flags).unwrap();
            let mut back = Pose(p);
            back.0[..3].fill(f64::MAX);
            k.forward(&j, &mut back, &mut flags).unwrap();
            for (a, &want) in p.iter().enumerate() {
                if k.has_axis(a) == Some(true) {
                    prop_assert_eq!(back.0[a], want);
                }
            }
        }
    }
}
