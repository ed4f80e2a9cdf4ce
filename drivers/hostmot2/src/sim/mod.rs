//! The HostMot2 firmware simulator: a register-level model of a board
//! ([`Hm2Model`]) serving a configurable IDROM
//! ([`FirmwareSpec`](crate::image::FirmwareSpec)) and running its modules
//! in simulated time, its connectors wired to a [`World`].

pub mod boards;
pub mod cpld;
pub mod encoder;
pub mod epp;
pub mod eth;
pub mod eth_server;
pub mod ioport;
pub mod machine;
pub mod mirror;
pub mod modbus_slave;
pub mod model;
pub mod pktuart;
pub mod plx;
pub mod plx_boards;
pub mod pty_peer;
pub mod pwm;
pub mod spi;
pub mod sserial;
pub mod stepgen;
pub mod watchdog;
pub mod world;
pub mod xilinx;

pub use model::Hm2Model;
pub use world::{Bench, EncoderIn, Inputs, Outputs, PwmOut, StepOut, World};

use std::sync::Arc;

use hal_driver::sim::SimBoard;

use crate::window::WindowTransport;

/// A simulated board as the driver sees it: the model behind the shared
/// layer's [`SimBoard`] (a `RegWindow`).
pub type SimHm2 = SimBoard<Hm2Model>;

/// The transport to a simulated board.
pub type SimTransport = WindowTransport<Arc<SimHm2>>;

/// A simulated board running `spec`, wired to `world`, and a transport to it.
pub fn board(
    spec: crate::image::FirmwareSpec,
    world: Box<dyn World>,
) -> (Arc<SimHm2>, SimTransport) {
    let board = Arc::new(SimBoard::new(Hm2Model::with_world(spec, world)));
    let t = WindowTransport::new(board.clone());
    (board, t)
}
