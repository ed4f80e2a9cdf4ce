//! The LinuxCNC-compatible motion controller.
//!
//! The front, re-exported here: [`MotionCore`] (the controller,
//! independent of HAL: joints, the enable state machine, the free, teleop
//! and coordinated modes, jogs, homing, limits, following error, faults;
//! [`MotionCore::command`] applies one [`Command`], [`MotionCore::cycle`]
//! runs one servo cycle), [`MotionClient`] (commands and status through a
//! running instance's shared memory, from any process), [`MotionHandle`]
//! (the same in the process that loaded `motmod`), and [`modules`] (the
//! `loadrt` modules: `motmod` and the kinematics).
//!
//! Public modules, for what is used by name: [`command`] (the command
//! table: commands, their records and command lines, and the refusals),
//! [`channel`] (the shared-memory channel's regions and records),
//! [`homing`] (the homing configuration and states), [`kins`] (the
//! [`Kinematics`] trait, poses and the kinematics modules), [`tp`] and
//! [`simple_tp`] (the coordinated and the single-axis planner), [`eoffset`]
//! (the external axis offsets and `OFFSET_AV_RATIO`), [`sizes`]
//! (the maxima), [`comp`] and [`comp_file`] (screw compensation).
//!
//! Inside, three layers; a file only uses files of its own layer or
//! below, so data flows one way: commands down into the core, status up
//! out of it.
//!
//! * Types, at the bottom: `vocab` (a leaf: the refusals and their wire
//!   codes, the homing configuration), `sizes`, `command`, `events`
//!   (reported messages), `status` (the status a client reads), `kins`,
//!   the homing states and `registry`.
//! * The controller, independent of HAL: `simple_tp`, `joint` and `axis`
//!   (one joint, one world axis), `eoffset` (an axis's external
//!   offset), `homing` (state machines and sequence manager), `tp` and
//!   `core`.
//! * The bindings, on top: `channel` (the shared-memory command channel
//!   and status snapshot), `mailbox` (the in-process command hand-off) and
//!   `motmod` (the `motmod` module: pins, params, threads, the
//!   `motion-command-handler` and `motion-controller` functions).
//!
//! Load order, as in LinuxCNC: `loadrt trivkins ...` (or another
//! kinematics module), then `loadrt motmod ...`.

mod axis;
pub mod channel;
pub mod command;
pub mod comp;
pub mod comp_file;
mod core;
pub mod eoffset;
mod events;
mod fault;
#[doc(hidden)]
pub mod fuzzing;
pub mod homing;
mod joint;
pub mod kins;
pub mod logger;
mod mailbox;
mod motmod;
mod registry;
pub mod simple_tp;
pub mod sizes;
mod status;
#[cfg(test)]
mod test_support;
pub mod tp;
pub mod tp_home;
mod vocab;

pub use axis::{AxisInputs, AxisStatus};
pub use channel::{Accepted, ClientError, MotionClient, MotionStatus, Rejected};
pub use command::{Command, CommandResult, Direction, Feature, Quantity, Reject};
pub use core::{
    MotionConfig, MotionCore, MotionInputs, MotionState, OrientState, Spindle, SpindleOutput,
    MODE_ENTRY_TOLERANCE,
};
pub use eoffset::EoffsetInputs;
pub use events::{Event, EventRing};
pub use fault::{Fault, FollowingErrorTrip, FAULT_WORDS};
pub use joint::{JointInputs, JointStatus};
pub use kins::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};
pub use motmod::MotionHandle;

/// The `loadrt` modules of this crate.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &kins::trivkins::MODULE,
        &kins::corexykins::MODULE,
        &kins::bipodkins::MODULE,
        &kins::tripodkins::MODULE,
        &kins::scarakins::MODULE,
        &kins::pumakins::MODULE,
        &kins::genserkins::MODULE,
        &kins::lineardeltakins::MODULE,
        &kins::rotarydeltakins::MODULE,
        &kins::genhexkins::MODULE,
        &kins::trt::XYZAC_MODULE,
        &kins::trt::XYZBC_MODULE,
        &kins::maxkins::MODULE,
        &kins::fiveaxiskins::MODULE,
        &kins::rosekins::MODULE,
        &kins::pentakins::MODULE,
        &kins::xyzab_tdr::MODULE,
        &kins::millturn::MODULE,
        &kins::scorbotkins::MODULE,
        &kins::rotatekins::MODULE,
        &kins::userkins::MODULE,
        &kins::gantrykins::MODULE,
        &kins::gentrivkins::MODULE,
        &kins::matrixkins::MODULE,
        &kins::three21kins::MODULE,
        &kins::trsrn::XYZACB_MODULE,
        &kins::trsrn::XYZBCA_MODULE,
        &motmod::MODULE,
    ]
}
