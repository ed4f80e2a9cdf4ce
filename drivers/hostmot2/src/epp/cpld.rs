//! The 7I43's CPLD: with the card jumpered to load its FPGA from the
//! parallel port, the CPLD answers the port's EPP cycles until the FPGA
//! is configured, and LinuxCNC's `hm2_7i43` loads `firmware=` through it.
//!
//! The CPLD decodes one address bit (EPP addresses are single bytes here):
//!
//! | address | read | write |
//! |---|---|---|
//! | [`CPLD_DATA`] (0) | bit 0: the FPGA is the 400k-gate part | a configuration byte, bit-reversed as the card wires it |
//! | [`CPLD_CONTROL`] (1) | bit 0: the FPGA's DONE | bit 0: /PROGRAM (0 clears the FPGA and holds it) |
//!
//! Once DONE rises the FPGA takes the port. A HostMot2 design gives it
//! back when [`RELEASE_KEY`] is written at byte address [`RELEASE_AT`],
//! which is why a reset writes that first: on a running board it hands
//! the port to the CPLD, on a board whose CPLD already answers it only
//! reaches the control register (and holds the FPGA, which the reset does
//! next anyway).

use std::time::Duration;

use hal_driver::bus::PortBus;

use super::reg;
use super::transport::{clear_timeout, timed_out};
use crate::fpga::{FpgaError, ProgramStep};

/// The CPLD's data register.
pub const CPLD_DATA: u8 = 0;
/// The CPLD's control register.
pub const CPLD_CONTROL: u8 = 1;
/// The byte address a HostMot2 design on the 7I43 watches for
/// [`RELEASE_KEY`].
pub const RELEASE_AT: u16 = 0x7F7F;
/// The byte that makes a running design hand the port to the CPLD.
pub const RELEASE_KEY: u8 = 0x5A;
/// The 7I43-4's FPGA.
pub const PART_400K: &str = "3s400tq144";
/// The 7I43-2's FPGA.
pub const PART_200K: &str = "3s200tq144";

/// How long /PROGRAM is held low (Xilinx asks for at least 300 ns).
const PROGRAM_PULSE: Duration = Duration::from_micros(1);
/// How long the FPGA is given to clear before the stream (2 ms, as the
/// part's data sheet and LinuxCNC wait).
const CLEAR_TIME: Duration = Duration::from_millis(2);

/// The CPLD of the 7I43 on the parallel port at `base`, reached over `bus`.
pub struct Cpld<'a> {
    bus: &'a dyn PortBus,
    base: u16,
}

impl<'a> Cpld<'a> {
    /// The CPLD behind the port at `base` (already set up for EPP).
    pub fn new(bus: &'a dyn PortBus, base: u16) -> Cpld<'a> {
        Cpld { bus, base }
    }

    fn address(&self, a: u8) {
        self.bus.outb(self.base.wrapping_add(reg::EPP_ADDRESS), a);
    }

    fn write(&self, v: u8) {
        self.bus.outb(self.base.wrapping_add(reg::EPP_DATA), v);
    }

    fn read(&self) -> u8 {
        self.bus.inb(self.base.wrapping_add(reg::EPP_DATA))
    }

    /// Fails `step` if the port saw an EPP timeout, clearing it.
    fn check(&self, step: ProgramStep, what: &str) -> Result<(), FpgaError> {
        if timed_out(self.bus, self.base) {
            clear_timeout(self.bus, self.base);
            return Err(FpgaError::Program {
                step,
                reason: format!(
                    "EPP timeout {what} (the card did not answer on the port at {:#x}: is it \
                     powered, cabled, and jumpered to load its FPGA from the parallel port?)",
                    self.base
                ),
            });
        }
        Ok(())
    }

    /// Hands the port to the CPLD and clears the FPGA: the release key
    /// for a running design, then a /PROGRAM pulse; afterwards DONE must
    /// be low.
    pub fn reset(&self) -> Result<(), FpgaError> {
        for _ in 0..2 {
            let [lo, hi] = RELEASE_AT.to_le_bytes();
            self.address(lo);
            self.address(hi);
            self.write(RELEASE_KEY);
        }
        // A running design may not answer the key's cycles in time; what
        // counts is that the CPLD answers from here on.
        clear_timeout(self.bus, self.base);
        self.address(CPLD_CONTROL);
        self.write(0);
        std::thread::sleep(PROGRAM_PULSE);
        self.write(1);
        std::thread::sleep(CLEAR_TIME);
        let done = self.read() & 1 != 0;
        self.check(ProgramStep::Reset, "while clearing the FPGA")?;
        if done {
            return Err(FpgaError::Program {
                step: ProgramStep::Reset,
                reason: "DONE is still high after the CPLD's /PROGRAM pulse: the CPLD does not \
                         hold the FPGA (is the card jumpered to load its FPGA from its EEPROM?)"
                    .into(),
            });
        }
        Ok(())
    }

    /// The FPGA part the CPLD reports (after [`reset`](Self::reset)).
    pub fn fpga_part(&self) -> Result<&'static str, FpgaError> {
        self.address(CPLD_DATA);
        let big = self.read() & 1 != 0;
        self.check(
            ProgramStep::Reset,
            "while asking the CPLD for the FPGA's size",
        )?;
        Ok(if big { PART_400K } else { PART_200K })
    }

    /// Streams `bitstream` into the FPGA (after [`reset`](Self::reset)).
    pub fn program(&self, bitstream: &[u8]) -> Result<(), FpgaError> {
        self.address(CPLD_DATA);
        for &b in bitstream {
            self.write(b.reverse_bits());
        }
        self.check(ProgramStep::Load, "while sending the firmware")
    }
}
