//! The simulated CiA 402 drive (hardware.md §6.12) and what runs it:
//!
//! * [`SimDrive`]: NMT slave, SDO server, PDO engine, EMCY, the power
//!   state machine, CSP/CSV/PV/homing with a motor model, fault
//!   injection ([`Injection`]).
//! * On the in-process bus: [`crate::bus::SimBus`] holds drives and
//!   advances them with simulated time.
//! * As its own process on a real or virtual CAN interface: [`process`]
//!   (the `canservo-sim` binary).
//!
//! Its parts: [`od`] (the object dictionary), `dictionary` (its
//! contents), `pdo` (the PDO rules and packing), `axis` (motor and
//! loops), `drive` and `control` (the drive itself).

mod axis;
mod control;
mod dictionary;
mod drive;
pub mod od;
mod pdo;
pub mod process;

pub use axis::{AxisParams, Demand};
pub use dictionary::{Identity, SUPPORTED_MODES};
pub use drive::{Injection, NmtState, SimDrive, SimDriveConfig};
