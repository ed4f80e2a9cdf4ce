//! LinuxCNC's switchable kinematics ("switchkins"): one module offers
//! three kinematics types and `motion.switchkins-type` picks one at run
//! time.
//!
//! * type 0: the module's own kinematics (the startup default);
//! * type 1: identity kinematics over the `coordinates=` letters, as
//!   trivkins maps them;
//! * type 2: the user type. LinuxCNC fills it with a template that users
//!   rebuild; unmodified that template is identity kinematics, and so is
//!   this type.
//!
//! `sparm=identityfirst` (honoured by the modules whose LinuxCNC
//! counterpart honours it: xyzac-trt-kins and xyzbc-trt-kins) swaps types
//! 0 and 1. The module reports `KINEMATICS_BOTH` whatever the type, and
//! exports `kinstype.is-0` … `kinstype.is-2` (bit outputs, no module
//! prefix, as LinuxCNC names them) showing the active type.
//!
//! Iterative forward kinematics (genhexkins) restart from the pose the
//! type last produced when it is switched back in, and a module with a
//! display type (genhexkins) keeps `skgui.x` … `skgui.c` showing that
//! type's forward kinematics whatever type is active.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::{Component, Host, ModuleArgs, Out, ParamDecl, ParamKind, Pin, Result};

use super::loader::{bad_param, register};
use super::trivkins::Trivkins;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, AXIS_LETTERS, NUM_AXES};

/// How many types a switchable module offers.
pub const SWITCHKINS_TYPES: usize = 3;

/// The module parameters of every switchable module.
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "coordinates",
        kind: ParamKind::Str,
        help: "axis letter of each joint for the identity types",
    },
    ParamDecl {
        name: "sparm",
        kind: ParamKind::Str,
        help: "module-specific option (identityfirst: type 0 is identity)",
    },
];

/// What distinguishes one switchable module from another.
#[derive(Debug, Clone, Copy)]
pub struct SwitchSpec {
    /// Module and component name, the prefix of its pins.
    pub module: &'static str,
    /// The coordinates used when `coordinates=` is not given; for modules
    /// that require them, letters every `coordinates=` must contain.
    pub required: &'static str,
    /// Whether every letter of `required` must appear in `coordinates=`.
    pub requires_letters: bool,
    /// Whether a letter may name several joints.
    pub allow_duplicates: bool,
    /// The most joints `coordinates=` may name.
    pub max_joints: usize,
    /// Whether `sparm=identityfirst` swaps types 0 and 1.
    pub honours_identity_first: bool,
    /// Whether the module's own forward kinematics iterate from a guess.
    pub forward_iterates: bool,
    /// Whether the module exports `skgui.*` pins showing its own forward
    /// kinematics whatever type is active.
    pub gui_pins: bool,
}

/// A switchable module: the module's own kinematics `K` plus the identity
/// types, dispatching on the active type.
pub struct Switchkins<K: Kinematics> {
    spec: SwitchSpec,
    native: K,
    identity: Trivkins,
    identity_first: bool,
    current: AtomicUsize,
    kinstype_is: [Pin<bool, Out>; SWITCHKINS_TYPES],
    last_pose: [[AtomicU64; NUM_AXES]; SWITCHKINS_TYPES],
    last_valid: [AtomicBool; SWITCHKINS_TYPES],
    restart_from_last: [AtomicBool; SWITCHKINS_TYPES],
    gui: Option<[Pin<f64, Out>; 6]>,
}

impl<K: Kinematics> std::fmt::Debug for Switchkins<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Switchkins")
            .field("module", &self.spec.module)
            .field("type", &self.active_type())
            .field("identity_first", &self.identity_first)
            .finish()
    }
}

/// Parses and checks `coordinates=` against the module's rules.
pub fn identity_map(spec: &SwitchSpec, coordinates: Option<&str>) -> Result<Trivkins> {
    let module = spec.module;
    let given = coordinates.unwrap_or(spec.required);
    let map = Trivkins::new(given, KinematicsType::Both)
        .map_err(|e| bad_param(module, "coordinates", e.to_string()))?;
    let joints = map.axis_of_joint();
    if joints.len() > spec.max_joints {
        return Err(bad_param(
            module,
            "coordinates",
            format!(
                "{} joints, at most {} are allowed",
                joints.len(),
                spec.max_joints
            ),
        ));
    }
    if !spec.allow_duplicates {
        for (j, a) in joints.iter().enumerate() {
            if joints[..j].contains(a) {
                return Err(bad_param(
                    module,
                    "coordinates",
                    format!(
                        "duplicates are not allowed: letter {} is given twice",
                        AXIS_LETTERS[*a].to_ascii_uppercase()
                    ),
                ));
            }
        }
    }
    if spec.requires_letters {
        for letter in spec.required.chars() {
            let axis = AXIS_LETTERS.iter().position(|&l| l == letter);
            if !axis.is_some_and(|a| joints.contains(&a)) {
                return Err(bad_param(
                    module,
                    "coordinates",
                    format!(
                        "'{given}' lacks {}: the coordinates must contain all of {}",
                        letter.to_ascii_uppercase(),
                        spec.required.to_ascii_uppercase()
                    ),
                ));
            }
        }
    }
    Ok(map)
}

/// Loads a switchable module: checks `coordinates=` and `sparm=`, makes
/// the component with the `kinstype.is-N` (and `skgui.*`) pins, lets
/// `native` export the module's own pins, and registers the result.
pub fn load<K: Kinematics>(
    host: &Host,
    args: &ModuleArgs,
    spec: SwitchSpec,
    native: impl FnOnce(&Component, &Trivkins) -> Result<K>,
) -> Result<()> {
    let identity = identity_map(&spec, args.str("coordinates"))?;
    let identity_first = spec.honours_identity_first
        && args
            .str("sparm")
            .is_some_and(|s| s.contains("identityfirst"));
    let b = host.new_rt_component(spec.module)?;
    let c = b.component();
    let kinstype_is = [
        c.pin("kinstype.is-0")?,
        c.pin("kinstype.is-1")?,
        c.pin("kinstype.is-2")?,
    ];
    let gui = if spec.gui_pins {
        let p = |axis: &str| c.pin::<f64, Out>(&format!("skgui.{axis}"));
        Some([p("x")?, p("y")?, p("z")?, p("a")?, p("b")?, p("c")?])
    } else {
        None
    };
    let native = native(c, &identity)?;
    let kins = Switchkins {
        spec,
        native,
        identity,
        identity_first,
        current: AtomicUsize::new(0),
        kinstype_is,
        last_pose: Default::default(),
        last_valid: Default::default(),
        restart_from_last: Default::default(),
        gui,
    };
    kins.activate(0);
    register(host, b, spec.module, Arc::new(kins))
}

impl<K: Kinematics> Switchkins<K> {
    /// The active type (0, 1 or 2).
    pub fn active_type(&self) -> usize {
        self.current.load(Relaxed)
    }

    /// The module's own kinematics.
    pub fn native(&self) -> &K {
        &self.native
    }

    /// The type number of the module's own kinematics (0, or 1 with
    /// `sparm=identityfirst`).
    fn native_type(&self) -> usize {
        usize::from(self.identity_first)
    }

    fn active(&self) -> (usize, &dyn Kinematics) {
        let t = self.active_type();
        if t == self.native_type() {
            (t, &self.native)
        } else {
            (t, &self.identity)
        }
    }

    fn iterates(&self, t: usize) -> bool {
        self.spec.forward_iterates && t == self.native_type()
    }

    fn load_pose(&self, t: usize) -> Pose {
        let mut p = Pose::ZERO;
        for (v, cell) in p.0.iter_mut().zip(&self.last_pose[t]) {
            *v = f64::from_bits(cell.load(Relaxed));
        }
        p
    }

    fn save_pose(&self, t: usize, p: &Pose) {
        for (v, cell) in p.0.iter().zip(&self.last_pose[t]) {
            cell.store(v.to_bits(), Relaxed);
        }
        self.last_valid[t].store(true, Relaxed);
    }

    /// Makes `t` the active type and shows it on `kinstype.is-N`. An
    /// iterating type restarts from the last pose it produced, if any.
    fn activate(&self, t: usize) {
        for flag in &self.restart_from_last {
            flag.store(false, Relaxed);
        }
        self.current.store(t, Relaxed);
        for (i, pin) in self.kinstype_is.iter().enumerate() {
            pin.set(i == t);
        }
        if self.iterates(t) && self.last_valid[t].load(Relaxed) {
            self.restart_from_last[t].store(true, Relaxed);
        }
    }

    /// Keeps the `skgui.*` pins showing the module's own forward
    /// kinematics, iterating from its last pose when another type is
    /// active.
    fn update_gui(&self, joints: &[f64], t: usize, pose: &Pose) {
        let Some(pins) = &self.gui else { return };
        let native = self.native_type();
        let shown = if t == native {
            *pose
        } else {
            let mut p = self.load_pose(native);
            if self
                .native
                .forward(joints, &mut p, &mut KinsFlags::default())
                .is_err()
            {
                return;
            }
            self.save_pose(native, &p);
            p
        };
        for (pin, v) in pins.iter().zip(&shown.0[..6]) {
            pin.set(*v);
        }
    }
}

impl<K: Kinematics> Kinematics for Switchkins<K> {
    fn name(&self) -> &str {
        self.spec.module
    }

    /// Always both directions, whatever the type (as LinuxCNC).
    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Both
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let (t, kins) = self.active();
        if self.iterates(t) && self.restart_from_last[t].swap(false, Relaxed) {
            *pose = self.load_pose(t);
        }
        kins.forward(joints, pose, flags)?;
        if self.iterates(t) {
            self.save_pose(t, pose);
        }
        self.update_gui(joints, t, pose);
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.active().1.inverse(pose, joints, flags)
    }

    fn home(
        &self,
        pose: &mut Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.active().1.home(pose, joints, flags)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.active().1.has_axis(axis)
    }

    fn is_switchable(&self) -> bool {
        true
    }

    /// Activates type `kins_type` (0, 1 or 2); anything else is refused
    /// and leaves the active type alone.
    fn switch_to(&self, kins_type: i32) -> std::result::Result<(), KinsError> {
        let t = usize::try_from(kins_type)
            .ok()
            .filter(|&t| t < SWITCHKINS_TYPES)
            .ok_or(KinsError::Unsupported)?;
        self.activate(t);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const SPEC: SwitchSpec = SwitchSpec {
        module: "testkins",
        required: "xyzac",
        requires_letters: true,
        allow_duplicates: false,
        max_joints: 6,
        honours_identity_first: false,
        forward_iterates: false,
        gui_pins: false,
    };

    #[test]
    fn coordinates_follow_the_modules_rules() {
        assert_eq!(
            identity_map(&SPEC, None).unwrap().axis_of_joint(),
            [0, 1, 2, 3, 5]
        );
        assert_eq!(
            identity_map(&SPEC, Some("CAZYX")).unwrap().axis_of_joint(),
            [5, 3, 2, 1, 0]
        );
        for (bad, why) in [
            ("xyzc", "lacks A"),
            ("xyzacc", "duplicates"),
            ("xyzacuv", "at most 6"),
            ("xyzaq", "invalid character"),
        ] {
            let e = identity_map(&SPEC, Some(bad)).unwrap_err().to_string();
            assert!(e.contains(why) && e.contains("coordinates"), "{bad}: {e}");
        }
    }

    proptest! {
        // A fuzz target for `coordinates=` until the fuzz crate lands.
        #![proptest_config(ProptestConfig::with_cases(10_000))]

        /// Any `coordinates=` text either maps or is refused by name.
        #[test]
        fn any_coordinates_text_is_mapped_or_refused(
            chars in prop::collection::vec(
                prop::sample::select(&[
                    'x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w', 'X', 'C', ' ', '\t', 'q', '\0',
                    'é', '=', ',',
                ][..]),
                0..40,
            ),
        ) {
            let text: String = chars.into_iter().collect();
            match identity_map(&SPEC, Some(&text)) {
                Ok(map) => prop_assert!(map.axis_of_joint().len() <= SPEC.max_joints),
                Err(hal_core::HalError::ModuleParam { param, .. }) => {
                    prop_assert_eq!(param, "coordinates")
                }
                Err(e) => prop_assert!(false, "{}", e),
            }
        }
    }
}
