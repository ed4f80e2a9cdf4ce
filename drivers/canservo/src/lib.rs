//! `canservo`: a CANopen CiA 402 servo-drive master over SocketCAN.
//!
//! (crate documentation is completed with the HAL binding)

pub mod bus;
pub mod codes;
pub mod drivefile;
pub mod engine;
pub mod error;
pub mod frame;
pub mod power;
pub mod regs;
pub mod rig;
pub mod sdo;
pub mod sim;
pub mod startup;
pub mod units;

pub use error::{Error, Result};
