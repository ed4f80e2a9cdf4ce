//! The vocabulary the controller and its clients share, at the bottom of
//! the crate: why a command was refused ([`Reject`], with the values it
//! names: [`Direction`], [`Quantity`], [`Feature`]), what a record read
//! from the channel got wrong ([`WireError`]) and a joint's homing
//! configuration ([`HomingConfig`], [`HomeFlags`], [`ConfigProblem`]).
//!
//! A leaf: nothing here uses the commands, homing or the core, so both
//! [`crate::command`] and [`crate::homing`] build on it without using
//! each other. Each refusal and each coded value is described once, as a
//! table from which its codes and texts are generated (`coded_enum!`,
//! `rejects!`).

mod coded;
mod homing_config;
mod reject;
mod reject_macro;
mod values;
mod wire_error;

pub use homing_config::{ConfigProblem, HomeFlags, HomingConfig, MAX_HOME_ALL_SEQUENCE};
pub use reject::{axis_letter, reject_code, result_name, CommandResult, Reject};
pub use reject_macro::RejectWire;
pub use values::{Direction, Feature, Quantity};
pub use wire_error::WireError;
