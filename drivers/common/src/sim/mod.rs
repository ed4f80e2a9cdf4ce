//! The board-model harness (hardware.md §0.2): what every driver's
//! simulator is built on.
//!
//! * A board model implements [`MemModel`] (a register window) or
//!   [`PortModel`] (I/O ports), plus [`BoardModel::advance`]: time passes
//!   for a model only through `advance`.
//! * [`SimBoard`] wraps a model and is a [`RegWindow`](crate::bus::RegWindow)
//!   or [`PortBus`](crate::bus::PortBus), so the driver runs on it exactly as
//!   on hardware. Tests reach the model through [`SimBoard::with`] (the
//!   plant API: the outside world is set there, never through registers),
//!   move time with [`SimBoard::advance`], and check what the driver did
//!   in the [`AccessLog`].
//! * [`SimClock`]: a board under `loadrt` uses
//!   [`SimClock::following_thread`], so it advances by the HAL thread's
//!   time that the driver's `read` passes in `tick`; in tests time moves
//!   only by explicit `advance`.
//! * [`publish`] / [`find`]: the boards a `loadrt` made, for tests and
//!   tools in the same process.
//! * The outside world a board drives (motors, encoders, switches) comes
//!   from [`crate::plant`].

mod board;
mod clock;
mod log;
mod registry;

pub use board::{BoardModel, MemModel, PortModel, SimBoard, SpiModel};
pub use clock::{Clock, MonotonicClock, SimClock};
pub use log::{Access, AccessLog, Dir, Width};
pub use registry::{find, publish, publish_any};
