//! ClassicLadder, LinuxCNC's ladder-logic PLC, for the HAL.
//!
//! * [`module`]: `loadrt classicladder_rt` (pins, parameters, the
//!   refresh funct).
//! * [`user`]: `loadusr classicladder FILE.clp`, the loader.
//! * [`clp`]: the `.clp` project bundle as written; [`compile`]: its
//!   checks against a module's sizes, giving a [`model::Program`].
//! * [`expr`]: arithmetic expressions, compiled to postfix.
//! * [`runtime`] and [`vars`]: the scan and the PLC memory.
//! * [`handoff`]: the program's way from the loader to the module.
//! * `fuzzing` (feature `fuzzing`): the `.clp` fuzz-target body.

#![forbid(unsafe_code)]

pub mod clp;
pub mod compile;
mod error;
pub mod expr;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod handoff;
pub mod model;
pub mod module;
pub mod runtime;
pub mod user;
pub mod vars;

pub use error::LadderError;

use hal_core::ModuleDef;

/// Every module this crate provides.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![&module::MODULE]
}
