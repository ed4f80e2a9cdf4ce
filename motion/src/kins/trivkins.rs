//! `trivkins`: identity kinematics with a configurable joint↔axis map.
//!
//! `loadrt trivkins coordinates=XYYZ kinstype=B`: joint *j* drives the
//! axis named by the *j*-th letter of `coordinates` (default `XYZABCUVW`;
//! letters case-insensitive, blanks ignored, at most 32 characters and 16
//! joints). A letter may repeat, so several joints drive one axis (a
//! gantry): forward kinematics take the axis from the first joint of that
//! letter, inverse kinematics give every joint of the letter the same
//! value. `kinstype` picks what motion may assume: `1` identity (default),
//! `B` both, `F` forward-only, `I` inverse-only; like LinuxCNC only the
//! first character counts (`both` is `B`).
//!
//! The module creates a `trivkins` component without pins and registers
//! its [`Trivkins`] in [`super::KINEMATICS`] for `motmod` to find.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, Result};

use super::{
    Kinematics, KinematicsType, KinsError, KinsFlags, Pose, AXIS_LETTERS, KINEMATICS, NUM_AXES,
};

pub use crate::sizes::MAX_JOINTS;

/// Longest `coordinates=` value LinuxCNC accepts.
pub const MAX_COORDINATES_CHARS: usize = 32;

/// The default joint↔axis assignment.
pub const DEFAULT_COORDINATES: &str = "XYZABCUVW";

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

/// The `trivkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "trivkins",
    params: PARAMS,
    help: "identity kinematics with a configurable joint to axis map",
    load,
};

/// Identity kinematics over a joint↔axis map.
#[derive(Debug, Clone, PartialEq)]
pub struct Trivkins {
    /// Axis index (into [`AXIS_LETTERS`]) of each joint, in joint order.
    axis_of_joint: Vec<usize>,
    /// For each axis, the first joint assigned to it (its forward source).
    principal: [Option<usize>; NUM_AXES],
    kins_type: KinematicsType,
    coordinates: String,
}

/// Why a `coordinates=` or `kinstype=` value was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TrivkinsError {
    /// More than [`MAX_COORDINATES_CHARS`] characters.
    TooLong(usize),
    /// A character that is neither an axis letter nor a blank.
    BadLetter(char),
    /// More letters than [`MAX_JOINTS`].
    TooManyJoints(usize),
    /// No axis letter at all.
    Empty,
    /// A `kinstype` whose first character is not 1, B, F or I.
    BadKinsType(String),
    /// More letters than a module with a fixed joint count takes
    /// (gantrykins, gentrivkins: 9).
    TooManyLetters {
        /// The value given.
        given: String,
        /// The most letters allowed.
        max: usize,
    },
}

impl std::fmt::Display for TrivkinsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TrivkinsError::TooLong(n) => write!(
                f,
                "{n} characters, at most {MAX_COORDINATES_CHARS} are allowed"
            ),
            TrivkinsError::BadLetter(c) => write!(
                f,
                "invalid character '{c}', expected axis letters XYZABCUVW"
            ),
            TrivkinsError::TooManyJoints(n) => {
                write!(f, "{n} joints, at most {MAX_JOINTS} are allowed")
            }
            TrivkinsError::Empty => f.write_str("no axis letter given"),
            TrivkinsError::TooManyLetters { given, max } => {
                write!(f, "more than {max} letters in '{given}'")
            }
            TrivkinsError::BadKinsType(s) => write!(
                f,
                "'{s}' is not a kinematics type: use 1 (identity), B (both), F (forward only) or I (inverse only)"
            ),
        }
    }
}

/// Parses a `kinstype=` value: its first character decides, as in LinuxCNC;
/// an empty value is the default (identity).
pub fn parse_kinstype(s: &str) -> std::result::Result<KinematicsType, TrivkinsError> {
    match s.chars().next() {
        None | Some('1') => Ok(KinematicsType::Identity),
        Some('b' | 'B') => Ok(KinematicsType::Both),
        Some('f' | 'F') => Ok(KinematicsType::ForwardOnly),
        Some('i' | 'I') => Ok(KinematicsType::InverseOnly),
        Some(_) => Err(TrivkinsError::BadKinsType(s.to_string())),
    }
}

impl Trivkins {
    /// Builds the map from a `coordinates=` value.
    pub fn new(
        coordinates: &str,
        kins_type: KinematicsType,
    ) -> std::result::Result<Trivkins, TrivkinsError> {
        let chars = coordinates.chars().count();
        if chars > MAX_COORDINATES_CHARS {
            return Err(TrivkinsError::TooLong(chars));
        }
        let mut axis_of_joint = Vec::new();
        for c in coordinates.chars() {
            if c == ' ' || c == '\t' {
                continue;
            }
            let lower = c.to_ascii_lowercase();
            let axis = AXIS_LETTERS
                .iter()
                .position(|&l| l == lower)
                .ok_or(TrivkinsError::BadLetter(c))?;
            axis_of_joint.push(axis);
        }
        if axis_of_joint.is_empty() {
            return Err(TrivkinsError::Empty);
        }
        if axis_of_joint.len() > MAX_JOINTS {
            return Err(TrivkinsError::TooManyJoints(axis_of_joint.len()));
        }
        let mut principal = [None; NUM_AXES];
        for (j, &a) in axis_of_joint.iter().enumerate() {
            principal[a].get_or_insert(j);
        }
        Ok(Trivkins {
            axis_of_joint,
            principal,
            kins_type,
            coordinates: coordinates.to_string(),
        })
    }

    /// The axis index of each joint, in joint order.
    pub fn axis_of_joint(&self) -> &[usize] {
        &self.axis_of_joint
    }

    /// The joints assigned to axis `axis`, in joint order.
    pub fn joints_of_axis(&self, axis: usize) -> impl Iterator<Item = usize> + '_ {
        self.axis_of_joint
            .iter()
            .enumerate()
            .filter(move |(_, &a)| a == axis)
            .map(|(j, _)| j)
    }

    /// The `coordinates=` value as given.
    pub fn coordinates(&self) -> &str {
        &self.coordinates
    }

    /// Whether the map differs from the conventional one (joint *j* = axis
    /// *j*, or the plain lathe `XZ`): LinuxCNC then prints the map and, for
    /// non-BOTH kinematics, recommends `kinstype=both`.
    pub fn is_unconventional(&self) -> bool {
        let reordered = self.axis_of_joint.iter().enumerate().any(|(j, &a)| a != j);
        reordered && self.axis_of_joint != [0, 2]
    }

    /// The notice LinuxCNC prints for an unconventional map.
    pub fn notice(&self) -> String {
        let mut s = format!("trivkins: coordinates:{}\n", self.coordinates);
        for (j, &a) in self.axis_of_joint.iter().enumerate() {
            s.push_str(&format!(
                "   Joint {j} ==> Axis {}\n",
                AXIS_LETTERS[a].to_ascii_uppercase()
            ));
        }
        if self.kins_type != KinematicsType::Both {
            s.push_str("trivkins: Recommend: kinstype=both\n");
        }
        s
    }
}

impl Kinematics for Trivkins {
    fn name(&self) -> &str {
        "trivkins"
    }

    fn kins_type(&self) -> KinematicsType {
        self.kins_type
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        for (axis, p) in self.principal.iter().enumerate() {
            if let Some(&v) = p.and_then(|j| joints.get(j)) {
                pose.0[axis] = v;
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
        for (j, &axis) in self.axis_of_joint.iter().enumerate() {
            if let Some(slot) = joints.get_mut(j) {
                *slot = pose.0[axis];
            }
        }
        Ok(())
    }

    /// The axes named in `coordinates=`.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(self.principal.get(axis).is_some_and(|p| p.is_some()))
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let bad = |param: &str, e: TrivkinsError| HalError::ModuleParam {
        module: "trivkins".into(),
        param: param.into(),
        reason: e.to_string(),
    };
    let kins_type =
        parse_kinstype(args.str("kinstype").unwrap_or("1")).map_err(|e| bad("kinstype", e))?;
    let kins = Trivkins::new(
        args.str("coordinates").unwrap_or(DEFAULT_COORDINATES),
        kins_type,
    )
    .map_err(|e| bad("coordinates", e))?;
    let b = host.new_rt_component("trivkins")?;
    let notice = kins.is_unconventional().then(|| kins.notice());
    let registration = KINEMATICS
        .register(host.instance().name(), "trivkins", Arc::new(kins))
        .map_err(|e| HalError::ModuleLoad {
            module: "trivkins".into(),
            reason: e.to_string(),
        })?;
    let mut b = b;
    // The component owns the registration: unloading it (or shutting the
    // host down) drops the hook and with it the registry entry. There are
    // no outputs to make safe.
    b.on_safe_state(move || {
        let _keep = &registration;
    });
    b.ready()?;
    if let Some(n) = notice {
        eprint!("{n}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::HostConfig;

    fn kins(c: &str) -> Trivkins {
        Trivkins::new(c, KinematicsType::Identity).unwrap()
    }

    #[test]
    fn maps_letters_to_joints_in_order() {
        assert_eq!(kins("xyz").axis_of_joint(), &[0, 1, 2]);
        assert_eq!(kins("xz").axis_of_joint(), &[0, 2]);
        assert_eq!(kins("X Y\tZ").axis_of_joint(), &[0, 1, 2]);
        assert_eq!(kins("XYYZ").axis_of_joint(), &[0, 1, 1, 2]);
        assert_eq!(
            kins(DEFAULT_COORDINATES).axis_of_joint(),
            &[0, 1, 2, 3, 4, 5, 6, 7, 8]
        );
        let k = kins("xyzy");
        assert_eq!(k.joints_of_axis(1).collect::<Vec<_>>(), vec![1, 3]);
        assert_eq!(k.principal[1], Some(1));
    }

    #[test]
    fn knows_which_axes_are_its_coordinates() {
        let k = kins("xz");
        let has: Vec<_> = (0..NUM_AXES + 1).map(|a| k.has_axis(a)).collect();
        assert_eq!(has[0], Some(true));
        assert_eq!(has[1], Some(false));
        assert_eq!(has[2], Some(true));
        assert!(has[3..].iter().all(|h| *h == Some(false)), "{has:?}");
    }

    #[test]
    fn forward_uses_the_first_joint_and_keeps_absent_axes() {
        let k = kins("xyyz");
        let mut pose = Pose([9.0; NUM_AXES]);
        let mut fl = KinsFlags::default();
        k.forward(&[1.0, 2.0, 2.5, 3.0], &mut pose, &mut fl)
            .unwrap();
        assert_eq!(pose.0, [1.0, 2.0, 3.0, 9.0, 9.0, 9.0, 9.0, 9.0, 9.0]);
        // Fewer joints than letters: the missing ones are left alone.
        let mut pose = Pose::ZERO;
        k.forward(&[1.0, 2.0], &mut pose, &mut fl).unwrap();
        assert_eq!(pose.0[..3], [1.0, 2.0, 0.0]);
    }

    #[test]
    fn inverse_gives_every_gantry_joint_the_axis_value() {
        let k = kins("xyzy");
        let mut pose = Pose::ZERO;
        pose.0[0] = 1.0;
        pose.0[1] = 2.0;
        pose.0[2] = 3.0;
        let mut j = [7.0; 6];
        k.inverse(&pose, &mut j, &mut KinsFlags::default()).unwrap();
        assert_eq!(j, [1.0, 2.0, 3.0, 2.0, 7.0, 7.0]);
        let mut back = Pose::ZERO;
        k.forward(&j, &mut back, &mut KinsFlags::default()).unwrap();
        assert_eq!(back, pose);
    }

    #[test]
    fn round_trip_for_the_default_map() {
        let k = kins(DEFAULT_COORDINATES);
        let pose = Pose([1.5, -2.0, 3.25, 90.0, -45.0, 1e-9, 7.0, 8.0, -9.0]);
        let mut j = [0.0; 9];
        let mut fl = KinsFlags::default();
        k.inverse(&pose, &mut j, &mut fl).unwrap();
        let mut back = Pose::ZERO;
        k.forward(&j, &mut back, &mut fl).unwrap();
        assert_eq!(back, pose);
    }

    #[test]
    fn rejects_bad_coordinates_and_kinstypes() {
        let t = KinematicsType::Identity;
        assert_eq!(Trivkins::new("xq", t), Err(TrivkinsError::BadLetter('q')));
        assert_eq!(Trivkins::new("", t), Err(TrivkinsError::Empty));
        assert_eq!(Trivkins::new("  ", t), Err(TrivkinsError::Empty));
        assert_eq!(
            Trivkins::new("xyzxyzxyzxyzxyzxy", t),
            Err(TrivkinsError::TooManyJoints(17))
        );
        assert!(Trivkins::new("xyzxyzxyzxyzxyzx", t).is_ok());
        assert_eq!(
            Trivkins::new(&"x ".repeat(17), t),
            Err(TrivkinsError::TooLong(34))
        );
        assert_eq!(parse_kinstype("1"), Ok(KinematicsType::Identity));
        assert_eq!(parse_kinstype(""), Ok(KinematicsType::Identity));
        assert_eq!(parse_kinstype("b"), Ok(KinematicsType::Both));
        assert_eq!(parse_kinstype("both"), Ok(KinematicsType::Both));
        assert_eq!(parse_kinstype("F"), Ok(KinematicsType::ForwardOnly));
        assert_eq!(parse_kinstype("i"), Ok(KinematicsType::InverseOnly));
        assert!(parse_kinstype("x").is_err());
    }

    #[test]
    fn notices_unconventional_maps_like_linuxcnc() {
        assert!(!kins("xyz").is_unconventional());
        assert!(!kins("XZ").is_unconventional());
        assert!(!kins(DEFAULT_COORDINATES).is_unconventional());
        assert!(kins("xyyz").is_unconventional());
        assert!(kins("zyx").is_unconventional());
        let n = kins("xyyz").notice();
        assert!(n.contains("Joint 2 ==> Axis Y"), "{n}");
        assert!(n.contains("Recommend: kinstype=both"), "{n}");
        let both = Trivkins::new("xyyz", KinematicsType::Both).unwrap();
        assert!(!both.notice().contains("Recommend"));
    }

    fn host() -> Host {
        Host::create(HostConfig::for_tests("trivkins")).expect("host starts")
    }

    fn load(h: &Host, args: &[&str]) -> Result<()> {
        h.loadrt(&MODULE, args)
    }

    #[test]
    fn loadrt_registers_for_the_instance_until_unloaded() {
        let h = host();
        let name = h.instance().name().to_string();
        assert!(super::super::kinematics_for(&name).is_none());
        load(&h, &["coordinates=xyyz", "kinstype=b"]).unwrap();
        let (owner, k) = super::super::kinematics_for(&name).unwrap();
        assert_eq!(owner, "trivkins");
        assert_eq!(k.kins_type(), KinematicsType::Both);
        assert_eq!(h.loaded_components(), ["trivkins"]);
        // No pins or params of its own.
        assert!(h
            .instance()
            .pins()
            .unwrap()
            .iter()
            .all(|p| !p.name.starts_with("trivkins")));
        h.unloadrt("trivkins").unwrap();
        assert!(super::super::kinematics_for(&name).is_none());
        load(&h, &[]).unwrap();
        assert_eq!(
            super::super::kinematics_for(&name).unwrap().1.kins_type(),
            KinematicsType::Identity
        );
        drop(h);
        assert!(super::super::kinematics_for(&name).is_none());
    }

    #[test]
    fn bad_module_parameters_name_the_parameter_and_leave_nothing() {
        let h = host();
        for (args, param) in [
            (&["coordinates=xyq"][..], "coordinates"),
            (&["coordinates="][..], "coordinates"),
            (&["kinstype=7"][..], "kinstype"),
            (&["bogus=1"][..], "bogus"),
        ] {
            match load(&h, args) {
                Err(HalError::ModuleParam { param: p, .. }) => assert_eq!(p, param),
                other => panic!("{args:?}: {other:?}"),
            }
            assert!(h.loaded_components().is_empty());
            assert!(super::super::kinematics_for(h.instance().name()).is_none());
        }
    }
}
