//! The LinuxCNC-compatible motion controller.
//!
//! * [`kins`]: the [`Kinematics`](kins::Kinematics) trait, the per-instance
//!   kinematics registry and the `trivkins` module.
//! * [`motmod`]: the `motmod` module (pins, params, threads, the
//!   `motion-command-handler` and `motion-controller` functions) and
//!   [`MotionHandle`](motmod::MotionHandle), the Rust command interface.
//! * [`core`]: the controller itself, independent of HAL: joints, the
//!   enable state machine, the free, teleop and coordinated modes, joint
//!   and axis jogs, limits, following error, faults.
//! * [`joint`], [`axis`]: the state of one joint and of one world axis.
//! * [`simple_tp`]: the single-axis trapezoidal planner.
//! * [`homing`]: the homing state machines and the sequence manager.
//! * [`command`], [`events`], [`mailbox`], [`registry`]: commands and their
//!   results, reported messages, the command hand-off, and how modules of
//!   one instance find each other.
//!
//! Load order, as in LinuxCNC: `loadrt trivkins ...` (or another
//! kinematics module), then `loadrt motmod ...`.

pub mod axis;
pub mod channel;
pub mod command;
pub mod core;
pub mod events;
pub mod homing;
pub mod joint;
pub mod kins;
pub mod mailbox;
pub mod motmod;
pub mod registry;
pub mod simple_tp;
#[cfg(test)]
mod test_support;

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
