//! The bus traits: a set of GPIO chips to search ([`ChipSet`]) and a
//! request of lines on one chip ([`LineRequest`]), with a real backend
//! ([`crate::cdev`]) and a simulated one ([`crate::sim`]).
//!
//! In the driver layer's shape: `&self` accessors, an `errors()` count,
//! and no panics. A request's accessors return the kernel's errno on
//! failure (the realtime functions count it and trip their fault latch);
//! everything else happens at `loadrt` and returns a [`GpioError`].

use std::fmt;

use crate::cfg::{Bias, Direction, Drive};
use crate::error::GpioError;
use crate::regs::flags;

/// A chip as discovery found it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChipInfo {
    /// Where it is opened (`/dev/gpiochip0`; `sim:gpiochip0` for a
    /// simulated chip).
    pub path: String,
    /// The kernel's name (`gpiochip0`).
    pub name: String,
    /// The chip's label (`pinctrl-bcm2711`).
    pub label: String,
    /// Every line's name by offset; empty for an unnamed line.
    pub line_names: Vec<String>,
}

impl fmt::Display for ChipInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} [{}]", self.name, self.label)
    }
}

/// How one line is requested.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineSetting {
    /// The line's offset on its chip.
    pub offset: u32,
    /// Input or output.
    pub direction: Direction,
    /// Logical 1 is electrically low (`invert=` on an output).
    pub active_low: bool,
    /// Output drive.
    pub drive: Drive,
    /// Bias.
    pub bias: Bias,
}

impl LineSetting {
    /// The uAPI v2 flags this setting requests (hardware.md 7.1).
    pub fn flags(&self) -> u64 {
        let mut f = match self.direction {
            Direction::Input => flags::INPUT,
            Direction::Output => flags::OUTPUT,
        };
        if self.active_low {
            f |= flags::ACTIVE_LOW;
        }
        f |= match self.drive {
            Drive::PushPull => 0,
            Drive::OpenDrain => flags::OPEN_DRAIN,
            Drive::OpenSource => flags::OPEN_SOURCE,
        };
        f | match self.bias {
            Bias::AsIs => 0,
            Bias::Disabled => flags::BIAS_DISABLED,
            Bias::PullUp => flags::BIAS_PULL_UP,
            Bias::PullDown => flags::BIAS_PULL_DOWN,
        }
    }
}

/// A failed value access: the kernel's errno.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineError(pub i32);

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", std::io::Error::from_raw_os_error(self.0))
    }
}

/// Requested lines on one chip: one bulk access reads or writes all of
/// them. Bit k of the value words is the k-th line of the request in
/// ascending offset order; values are logical (active-low inverts).
pub trait LineRequest: Send + Sync {
    /// Reads the lines in `mask`; other bits of the result are 0.
    fn get(&self, mask: u64) -> Result<u64, LineError>;
    /// Sets the lines in `mask` to their bits of `bits` (outputs only).
    fn set(&self, bits: u64, mask: u64) -> Result<(), LineError>;
    /// How many accesses failed.
    fn errors(&self) -> u64;
    /// The chip and lines, for messages.
    fn describe(&self) -> String;
}

/// The GPIO chips a driver may use.
pub trait ChipSet {
    /// Every chip, each once, in a stable order.
    fn chips(&self) -> Result<Vec<ChipInfo>, GpioError>;
    /// Requests `lines` (distinct offsets, ascending) of `chip`, outputs
    /// starting at their inactive level.
    fn request(
        &self,
        chip: &ChipInfo,
        lines: &[LineSetting],
    ) -> Result<Box<dyn LineRequest>, GpioError>;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_give_the_kernel_flags() {
        let s = LineSetting {
            offset: 3,
            direction: Direction::Output,
            active_low: true,
            drive: Drive::OpenDrain,
            bias: Bias::PullUp,
        };
        assert_eq!(
            s.flags(),
            flags::OUTPUT | flags::ACTIVE_LOW | flags::OPEN_DRAIN | flags::BIAS_PULL_UP
        );
        let i = LineSetting {
            direction: Direction::Input,
            active_low: false,
            drive: Drive::PushPull,
            bias: Bias::Disabled,
            ..s
        };
        assert_eq!(i.flags(), flags::INPUT | flags::BIAS_DISABLED);
        assert_eq!(
            LineError(libc::ENODEV).to_string(),
            std::io::Error::from_raw_os_error(libc::ENODEV).to_string()
        );
    }
}
