//! `hm2_7i43` and `hm2_7i90`: Mesa's parallel-port cards, reached by EPP
//! (Enhanced Parallel Port) cycles on a PC parallel port.
//!
//! ```text
//! loadrt hostmot2
//! loadrt hm2_7i43 ioaddr=0x378 config="num_encoders=4 num_pwmgens=4 num_stepgens=4"
//! addf hm2_7i43.0.read servo-thread
//! addf hm2_7i43.0.write servo-thread
//! ```
//!
//! # The port
//!
//! The driver talks to the port's registers at `ioaddr` (and its ECP
//! extended control register at `ioaddr_hi + 2`) through the shared
//! driver layer's port bus, with raw port I/O as `hal_parport` does in
//! its `epp` mode ([`IopermPorts`](hal_driver::bus::IopermPorts): needs
//! `CAP_SYS_RAWIO`), or through the simulated port of
//! [`sim::epp`](crate::sim::epp) with `sim=`. Setting up, it selects
//! EPP mode in the ECR ([`ecr::EPP`]), raises nInit in the control
//! register ([`CONTROL_EPP`]) and clears a stale EPP timeout.
//!
//! An access to the board's 32-bit registers is one EPP address cycle
//! pair (the byte address, low byte then high, with
//! [`AUTO_INCREMENT`] set) and then four data cycles per register, or
//! one 32-bit port access per register with `epp_wide=1` (the port chip
//! splits it into the four cycles). After each burst the status
//! register's timeout bit ([`STATUS_TIMEOUT`]) says whether the board
//! answered; a timeout is cleared and the transfer fails (`io_error`).
//! EPP carries 15 address bits: the board's registers lie below 0x8000.
//!
//! # Parameters
//!
//! LinuxCNC's: `ioaddr` (port addresses, one per board; default 0x378
//! for the first), `ioaddr_hi` (the ECR's block: 0 means `ioaddr +
//! 0x400`, -1 that the port has no ECR to set), `epp_wide` (0: byte
//! cycles only), `config` (hostmot2 config strings) and `debug_epp`;
//! and `sim`, as `hm2_pci` has it: `sim=7i43` (or `7i90`) runs a
//! simulated board behind a simulated port instead.
//!
//! # What is not here
//!
//! A 7I43 given `firmware=` is loaded through its CPLD ([`cpld`]) as
//! LinuxCNC's hm2_7i43 does, the FPGA's size (7I43-2 or 7I43-4) taken
//! from the CPLD and checked against the bitfile's part; without it the
//! FPGA is assumed loaded already (from the card's EEPROM). LinuxCNC
//! resets the FPGA at every load to ask the CPLD for the size; here the
//! reset happens only when there is firmware to load, so a card running
//! from its EEPROM is left running. The 7I90 loads from its flash and
//! ignores `firmware=`. `debug_epp` does not print every cycle (that would be a print in a
//! realtime function): the load says so, and the simulator's access log
//! shows the cycles.
//!
//! # Modules
//!
//! [`transport`] (the EPP transport), [`cpld`] (the 7I43's FPGA loader),
//! [`hal`] (the two `loadrt` modules).

pub mod cpld;
pub mod hal;
pub mod load;
pub mod transport;

pub use transport::EppTransport;

use std::sync::Arc;

/// A board on a parallel port, set up for EPP: its transport and, when
/// simulated, the board behind the simulated port (whose time the HAL
/// `read` function moves).
#[derive(Debug)]
pub struct EppSource {
    /// The transport.
    pub transport: EppTransport,
    /// The simulated board, if it is one.
    pub sim: Option<Arc<crate::sim::SimHm2>>,
    /// The simulated port, if it is one (a 7I43 loaded through its CPLD
    /// gets the simulator's HostMot2 for its new design here).
    pub sim_port: Option<Arc<hal_driver::sim::SimBoard<crate::sim::epp::EppPortModel>>>,
    /// A 7I43: `firmware=` is loaded through its CPLD ([`cpld`]).
    pub has_cpld: bool,
    /// The FPGA part the CPLD reported, once asked.
    pub fpga_part: Option<&'static str>,
}

/// Register offsets from the port's base address.
pub mod reg {
    /// SPP data register.
    pub const DATA: u16 = 0;
    /// Status register (bit 0: EPP timeout).
    pub const STATUS: u16 = 1;
    /// Control register.
    pub const CONTROL: u16 = 2;
    /// EPP address register: a write is an address cycle.
    pub const EPP_ADDRESS: u16 = 3;
    /// EPP data register: each byte read or written is a data cycle.
    pub const EPP_DATA: u16 = 4;
    /// The last byte of the EPP data block (32-bit accesses at
    /// [`EPP_DATA`] span it).
    pub const EPP_DATA_LAST: u16 = 7;
    /// The ECR's offset from `ioaddr_hi`.
    pub const ECR_HI: u16 = 2;
    /// Registers at the base.
    pub const SPAN: u16 = 8;
    /// Registers at `ioaddr_hi`.
    pub const SPAN_HI: u16 = 3;
}

/// Values of the ECP extended control register.
pub mod ecr {
    /// The mode field (bits 7..5).
    pub const MODE_MASK: u8 = 0xE0;
    /// Plain (SPP) mode, as a port comes up.
    pub const SPP: u8 = 0x14;
    /// EPP mode (mode field 100), interrupts and DMA off.
    pub const EPP: u8 = 0x94;
}

/// The status register's EPP timeout bit.
pub const STATUS_TIMEOUT: u8 = 0x01;
/// Status bits the simulated port shows besides the timeout bit.
pub const STATUS_IDLE: u8 = 0x78;
/// The control register for EPP transfers: nInit high (no reset),
/// strobes released, data lines driven by the port chip.
pub const CONTROL_EPP: u8 = 0x04;
/// Address bit 15: the board steps the address after each data cycle.
pub const AUTO_INCREMENT: u16 = 0x8000;
/// The byte address bits an EPP address carries.
pub const ADDRESS_MASK: u16 = 0x7FFF;
/// `ioaddr_hi` = 0: the ECR block is this far above `ioaddr`.
pub const HI_OFFSET: u16 = 0x400;
