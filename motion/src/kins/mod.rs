//! Kinematics: the mapping between joint positions and the world pose
//! (X Y Z A B C U V W), as a trait that kinematics modules implement and
//! `motmod` calls every servo cycle.
//!
//! A kinematics module (`loadrt trivkins ...`) registers its
//! implementation in [`KINEMATICS`] under the HAL instance's name; `motmod`
//! looks it up when it loads, so the kinematics module must be loaded
//! first, exactly as in LinuxCNC. The crate's `registry` module has the
//! lifetime rules.
//!
//! The modules, under LinuxCNC's names: [`trivkins`], [`corexykins`],
//! [`bipodkins`] (the kinematics note's example), [`tripodkins`],
//! [`scarakins`], [`pumakins`], [`genserkins`], [`lineardeltakins`],
//! [`rotarydeltakins`], [`genhexkins`], [`trt`] (`xyzac-trt-kins`,
//! `xyzbc-trt-kins`), and those of LinuxCNC's sim machines: [`maxkins`],
//! [`fiveaxiskins`] (`5axiskins`), [`rosekins`], [`pentakins`],
//! [`xyzab_tdr`] (`xyzab_tdr_kins`) and [`millturn`]; then
//! [`scorbotkins`] (`scorbot-kins`), [`rotatekins`], [`userkins`]
//! (LinuxCNC's template, unmodified), [`matrixkins`] (calibrated X Y Z),
//! [`three21kins`] (six-joint arms on pumakins' solver), [`trsrn`]
//! (`xyzacb_trsrn`, `xyzbca_trsrn`), and LinuxCNC 2.7's [`gantrykins`]
//! and [`gentrivkins`] for the configurations still written for them.
//! Those LinuxCNC makes switchable are built on [`switchkins`], or on
//! [`twotype`] for those made from LinuxCNC's `userkins.comp` template.
//! Each keeps its geometry in HAL pins or parameters read at every call,
//! and refuses poses it cannot reach, and singular ones, with a
//! [`KinsError`]: no module writes a non-finite joint or pose.
//! [`math`] and [`dh`] hold the geometry they share.

pub mod bipodkins;
pub mod corexykins;
pub mod dh;
pub mod fiveaxiskins;
pub mod gantrykins;
pub mod genhexkins;
pub mod genserkins;
pub mod gentrivkins;
pub mod lineardeltakins;
mod loader;
pub mod math;
pub mod matrixkins;
pub mod maxkins;
pub mod millturn;
pub mod pentakins;
mod pinned;
pub mod pumakins;
pub mod rosekins;
pub mod rotarydeltakins;
pub mod rotatekins;
pub mod scarakins;
pub mod scorbotkins;
pub mod switchkins;
#[cfg(test)]
mod testing;
pub mod three21kins;
pub mod tripodkins;
pub mod trivkins;
pub mod trsrn;
pub mod trt;
pub mod twotype;
pub mod userkins;
pub mod xyzab_tdr;

use std::sync::Arc;

use crate::registry::InstanceRegistry;

/// Number of world axes.
pub const NUM_AXES: usize = 9;

/// The world axes in index order; HAL names use the lower-case letter.
pub const AXIS_LETTERS: [char; NUM_AXES] = ['x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w'];

/// A world pose: X Y Z A B C U V W, indexed as [`AXIS_LETTERS`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose(pub [f64; NUM_AXES]);

impl Pose {
    /// The pose with every coordinate zero.
    pub const ZERO: Pose = Pose([0.0; NUM_AXES]);
}

/// What a kinematics module can compute, and so how motion uses it
/// (LinuxCNC's `KINEMATICS_TYPE`, with the same numbering).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(i32)]
pub enum KinematicsType {
    /// Joints and axes correspond one to one; forward kinematics work
    /// without homing and world jogs are allowed before homing.
    Identity = 1,
    /// Only forward kinematics (motion cannot run world modes).
    ForwardOnly = 2,
    /// Only inverse kinematics: world feedback is faked from the command.
    InverseOnly = 3,
    /// Both directions, but forward kinematics need homed joints.
    Both = 4,
}

/// The configuration flags LinuxCNC passes to every kinematics call:
/// `forward` selects among several world solutions, `inverse` among
/// several joint solutions. A call may update them to describe the
/// solution it found. Motion keeps one pair for all calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct KinsFlags {
    /// Forward-solution selector (LinuxCNC `fflags`).
    pub forward: u64,
    /// Inverse-solution selector (LinuxCNC `iflags`).
    pub inverse: u64,
}

/// Why a kinematics call failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KinsError {
    /// The pose or joint set has no solution (singularity, out of reach).
    NoSolution,
    /// An iterative solution did not converge.
    NotConverged,
    /// The module cannot do what was asked (a kinematics switch on a
    /// module that cannot switch, an unknown type).
    Unsupported,
}

impl std::fmt::Display for KinsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            KinsError::NoSolution => "no solution",
            KinsError::NotConverged => "did not converge",
            KinsError::Unsupported => "not supported by this kinematics",
        })
    }
}

/// A kinematics implementation. Calls come from the realtime servo
/// function, so implementations must not allocate, lock or block.
pub trait Kinematics: Send + Sync + 'static {
    /// The module's name (`trivkins`).
    fn name(&self) -> &str;

    /// What the module can compute.
    fn kins_type(&self) -> KinematicsType;

    /// Joint positions to world pose. `pose` comes in holding the previous
    /// result (the initial guess of iterative solvers); axes the module
    /// does not compute keep their value.
    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> Result<(), KinsError>;

    /// World pose to joint positions. Joints the module does not compute
    /// keep their value.
    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> Result<(), KinsError>;

    /// Sets `joints` and `pose` to a consistent home position
    /// (LinuxCNC's `kinematicsHome`). `pose` comes in as the world home
    /// (`[TRAJ]HOME`) and `joints` as the joints' home positions, when
    /// known; the default keeps the pose and computes the joints from it
    /// by inverse kinematics.
    fn home(
        &self,
        pose: &mut Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> Result<(), KinsError> {
        *flags = KinsFlags::default();
        self.inverse(pose, joints, flags)
    }

    /// Whether world axis `axis` (an index into [`AXIS_LETTERS`]) is one
    /// of the coordinates the module computes: `None` when the module does
    /// not say, and then motion lets every axis be jogged.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        let _ = axis;
        None
    }

    /// Whether the module can switch between several kinematics at run
    /// time (`motion.switchkins-type` is only exported if so).
    fn is_switchable(&self) -> bool {
        false
    }

    /// Switches to kinematics number `kins_type` (switchable modules only).
    fn switch_to(&self, kins_type: i32) -> Result<(), KinsError> {
        let _ = kins_type;
        Err(KinsError::Unsupported)
    }
}

/// The kinematics of each HAL instance.
pub static KINEMATICS: InstanceRegistry<dyn Kinematics> = InstanceRegistry::new("kinematics");

/// The kinematics loaded in `instance`, with the name of the module that
/// provides it.
pub fn kinematics_for(instance: &str) -> Option<(String, Arc<dyn Kinematics>)> {
    KINEMATICS.get(instance)
}
