//! `hostmot2`: Mesa HostMot2 FPGA cards (LinuxCNC's `hostmot2`, `hm2_pci`
//! and `hm2_test` drivers), with a simulator of the firmware.

pub mod board;
pub mod config;
pub mod error;
pub mod firmware;
pub mod fuzz;
pub mod hal;
pub mod idrom;
pub mod image;
pub mod llio;
pub mod log;
pub mod md;
pub mod modules;
pub mod pci;
pub mod pins;
pub mod readhmid;
pub mod regs;
pub mod sim;
pub mod test_patterns;
pub mod tram;
pub mod transport;
pub mod window;

pub use error::{Hm2Error, Result};
