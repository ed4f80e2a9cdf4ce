//! The LinuxCNC-compatible motion controller.
//!
//! Three layers; a file only uses files of its own layer or below, so data
//! flows one way: commands down into the core, status up out of it.
//!
//! * Types, at the bottom: `vocab` (a leaf: the refusals and their wire
//!   codes, the homing configuration), [`sizes`] (the maxima), [`command`]
//!   (the command table: commands, their wire form and command lines),
//!   [`events`] (reported messages), [`status`] (the status a client
//!   reads), [`kins`] (the [`Kinematics`] trait, poses, the per-instance
//!   registry and the kinematics modules), the homing state types
//!   ([`homing::state`]), and [`registry`].
//! * The controller, independent of HAL: [`simple_tp`] (the single-axis
//!   planner), [`joint`] and [`axis`] (one joint, one world axis), the
//!   homing state machines and sequence manager ([`homing`]), and
//!   [`core`]: joints, the enable state machine, the free, teleop and
//!   coordinated modes, jogs, limits, following error, faults.
//! * The bindings, on top: [`channel`] (the shared-memory command channel
//!   and status snapshot, and [`MotionClient`]), [`mailbox`] (the in-process
//!   command hand-off) and [`motmod`] (the `motmod` module: pins, params,
//!   threads, the `motion-command-handler` and `motion-controller`
//!   functions, and [`MotionHandle`]).
//!
//! Load order, as in LinuxCNC: `loadrt trivkins ...` (or another
//! kinematics module), then `loadrt motmod ...`.

pub mod axis;
pub mod channel;
pub mod command;
pub mod comp;
pub mod comp_file;
pub mod core;
pub mod events;
pub mod homing;
pub mod joint;
pub mod kins;
pub mod mailbox;
pub mod motmod;
pub mod registry;
pub mod simple_tp;
pub mod sizes;
pub mod status;
#[cfg(test)]
mod test_support;
pub mod tp;
mod vocab;

pub use channel::{Accepted, ClientError, MotionClient, MotionStatus, Rejected};
pub use command::{Command, CommandResult, Direction, Feature, Quantity, Reject};
pub use core::{MotionConfig, MotionCore, MotionInputs, MotionState};
pub use events::Event;
pub use kins::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};
pub use motmod::MotionHandle;

/// The `loadrt` modules of this crate.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &kins::trivkins::MODULE,
        &kins::corexykins::MODULE,
        &kins::bipodkins::MODULE,
        &kins::scarakins::MODULE,
        &kins::pumakins::MODULE,
        &kins::genserkins::MODULE,
        &kins::lineardeltakins::MODULE,
        &kins::rotarydeltakins::MODULE,
        &kins::genhexkins::MODULE,
        &kins::trt::XYZAC_MODULE,
        &kins::trt::XYZBC_MODULE,
        &motmod::MODULE,
    ]
}
