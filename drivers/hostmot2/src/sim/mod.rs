//! The HostMot2 firmware simulator: a register-level model of a board
//! ([`Hm2Model`]) serving a configurable IDROM
//! ([`FirmwareSpec`](crate::image::FirmwareSpec)) and running its modules
//! in simulated time, its connectors wired to a [`World`].

pub mod boards;
pub mod encoder;
pub mod ioport;
pub mod model;
pub mod pwm;
pub mod stepgen;
pub mod watchdog;
pub mod world;

pub use model::Hm2Model;
pub use world::{Bench, EncoderIn, Inputs, Outputs, PwmOut, StepOut, World};
