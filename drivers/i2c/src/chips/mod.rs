//! The chip drivers: what the bus's helper thread does with each chip.
//!
//! A [`Chip`] sets its chip up ([`Chip::init`], outputs in their safe
//! state), then once per helper cycle ([`Chip::cycle`]) writes the
//! command the realtime `write` function published, if it changed, and
//! reads the chip's inputs into its sample, which the realtime `read`
//! function picks up. Every few hundred milliseconds a chip with a
//! configuration to lose checks that it still has it (a chip that lost
//! power for a moment comes back with its power-up registers, without a
//! transfer ever failing). The helper thread ([`crate::worker`]) handles
//! failures: fault latch, retries, re-initialisation.

pub mod ads1115;
pub mod mcp23017;
pub mod pca9685;

use std::fmt;

use crate::bus::{BusError, I2cBus};

pub use ads1115::{AdcSample, AdcSettings, Ads1115Chip};
pub use mcp23017::{DioCmd, Mcp23017Chip};
pub use pca9685::{Pca9685Chip, PwmCmd};

/// Helper cycles between configuration checks.
pub const CHECK_EVERY: u32 = 256;

/// Why a chip stopped working.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChipFault {
    /// A transfer failed.
    Bus(BusError),
    /// The chip answers but no longer has the configuration the driver
    /// gave it (it was power-cycled or reset).
    LostConfig,
    /// A conversion did not finish in ten times its nominal time.
    Stuck,
}

impl From<BusError> for ChipFault {
    fn from(e: BusError) -> Self {
        ChipFault::Bus(e)
    }
}

impl fmt::Display for ChipFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChipFault::Bus(e) => write!(f, "{e}"),
            ChipFault::LostConfig => {
                write!(f, "the chip lost its configuration (power cycled or reset)")
            }
            ChipFault::Stuck => write!(f, "a conversion never finished"),
        }
    }
}

impl std::error::Error for ChipFault {}

/// A command the realtime side publishes, with its safe form.
pub trait Command: Copy + Default + Send + 'static {
    /// The same command with every output in its safe state.
    fn safe(&self) -> Self;
}

impl Command for () {
    fn safe(&self) -> Self {}
}

/// One chip, as the helper thread drives it.
pub trait Chip: Send + 'static {
    /// What the realtime `write` function publishes.
    type Cmd: Command;
    /// What the helper thread publishes for the realtime `read` function.
    type Sample: Copy + Default + Send + 'static;

    /// The chip's 7-bit address.
    fn address(&self) -> u8;

    /// Sets the chip up from whatever state it is in, its outputs at
    /// `safe` (a command's safe form); also at `loadrt`, where a failure
    /// fails the load.
    fn init(&mut self, bus: &dyn I2cBus, safe: &Self::Cmd) -> Result<(), ChipFault>;

    /// One helper cycle at `now_ns`: outputs to `cmd` (only what
    /// changed), inputs into `sample`.
    fn cycle(
        &mut self,
        bus: &dyn I2cBus,
        cmd: &Self::Cmd,
        now_ns: u64,
        sample: &mut Self::Sample,
    ) -> Result<(), ChipFault>;
}

/// Counts helper cycles to the next configuration check.
#[derive(Debug, Clone, Copy, Default)]
pub struct CheckTimer(u32);

impl CheckTimer {
    /// Whether this cycle checks: every [`CHECK_EVERY`]th; after a set-up
    /// (which wrote the configuration) the first check comes
    /// [`CHECK_EVERY`] − 1 cycles later.
    pub fn due(&mut self) -> bool {
        let due = self.0 == 0;
        self.0 = (self.0 + 1) % CHECK_EVERY;
        due
    }

    /// Starts over (after an initialisation).
    pub fn restart(&mut self) {
        self.0 = 1;
    }
}
