//! The firmware modules as the driver runs them: each exports its HAL
//! objects when the board registers, registers its TRAM regions, writes
//! its configuration registers (all of them in `force_write`, the changed
//! ones each `write`), and turns the TRAM words into pins (`read`) and
//! pins into TRAM words (`write`).

pub mod encoder;
pub mod ioport;
pub mod led;
pub mod pwmgen;
pub mod raw;
pub mod sserial;
pub mod stepgen;
pub mod watchdog;

use crate::tram::Tram;
use crate::transport::{Transport, TransportError};

/// Where a realtime function's messages go: a message is said once per
/// event (a watchdog bite, a clamped parameter), never every cycle.
pub use crate::log::BoardLog as Notify;

/// What a module needs while the board registers.
pub struct Export<'a, F> {
    /// The component that owns the board's HAL objects: where its pins
    /// and parameters are made, in whichever host.
    pub comp: &'a F,
    /// The board's name prefix (`hm2_5i25.0`).
    pub prefix: &'a str,
    /// The TRAM to register regions in.
    pub tram: &'a mut Tram,
}

impl<F> Export<'_, F> {
    /// `<prefix>.<rest>`.
    pub fn name(&self, rest: &str) -> String {
        format!("{}.{rest}", self.prefix)
    }
}

/// Queues one register write (configuration writes during a cycle).
#[inline]
pub fn put(t: &mut dyn Transport, addr: u32, value: u32) -> Result<(), TransportError> {
    t.queue_write(addr, &[value])
}
