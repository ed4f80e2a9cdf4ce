//! The bus the driver talks through: register access to one parallel port.
//!
//! [`PortIo`] is a register-level interface (data, status, control, ECR,
//! claim/release; the data direction is control bit 5). It has three backends:
//!
//! * [`ppdev::PpdevPort`]: `/dev/parportN` through the ppdev ioctls. Needs
//!   no privilege beyond access to the device node (group `lp`). Every
//!   access is a system call, and the control register cannot be read back
//!   live, so `x` mode and `epp` are refused on it.
//! * [`raw::RawPort`]: `inb`/`outb` after `ioperm`, through the driver
//!   layer's [`IopermPorts`](hal_driver::bus::IopermPorts). Needs
//!   `CAP_SYS_RAWIO`; the permission is per thread and taken on the first
//!   access in each.
//! * [`crate::sim::SimPort`]: the register-level simulator, a
//!   [`SimBoard`](hal_driver::sim::SimBoard) on the same port bus.
//!
//! The raw backend and the simulator both reach the registers through a
//! [`PortBus`] at the port's addresses ([`PortAt`]).
//!
//! Realtime functions call the accessors; they take `&self` so the
//! functions of one port can run in different threads. Accessors never
//! fail visibly (a realtime function has nobody to report to): a failed
//! system call reads as 0xFF and is counted in [`PortIo::errors`], which
//! the driver reports once, when it releases the port.

pub mod ppdev;
pub mod raw;

use hal_driver::bus::{PortBus, PortRange};

use crate::cfg::CfgError;
use crate::regs;

/// What went wrong opening or setting up a port.
#[derive(Debug, thiserror::Error)]
pub enum PortError {
    /// The device node does not exist.
    #[error("{path} does not exist (is the parport_pc and ppdev kernel module loaded?)")]
    NoDevice {
        /// The `/dev/parportN` node looked for.
        path: String,
    },
    /// Opening the device node failed.
    #[error("cannot open {path}: {source}{hint}")]
    Open {
        /// The device node.
        path: String,
        /// The error the kernel returned.
        source: std::io::Error,
        /// How to get access when it was refused (the group and udev
        /// rule); empty otherwise.
        hint: &'static str,
    },
    /// An ioctl failed during setup.
    #[error("{op} on {path} failed: {source}")]
    Ioctl {
        /// The ioctl (`PPCLAIM`, `PPSETMODE`, ...).
        op: &'static str,
        /// The device node.
        path: String,
        /// The error the kernel returned.
        source: std::io::Error,
    },
    /// Raw port I/O is not permitted.
    #[error("no permission for raw port I/O at {addr:#x}: {reason}")]
    NoPermission {
        /// The port's base address.
        addr: u16,
        /// What `ioperm` said and how to grant the permission.
        reason: String,
    },
    /// The backend cannot do what the port's mode needs.
    #[error("{0}")]
    Unsupported(String),
    /// The port's address could not be determined.
    #[error("{0}")]
    NotFound(String),
    /// Another entry of the same cfg string names this port too.
    #[error("it is the same port as port {other} ({other_spec}): {shared}")]
    SamePort {
        /// The other entry's index.
        other: usize,
        /// The other entry as written (address and mode).
        other_spec: String,
        /// What the two share: the device node or the base address.
        shared: String,
    },
    /// Setting up one port of the cfg string failed: which one, and why.
    #[error("port {index} ({spec}): {source}")]
    Port {
        /// The port's index in the cfg string.
        index: usize,
        /// The entry as written (address and mode).
        spec: String,
        /// Why it failed.
        #[source]
        source: Box<PortError>,
    },
    /// The cfg string given to the bring-up tool was refused.
    #[error(transparent)]
    Cfg(#[from] CfgError),
    /// A `parport-tool set` argument is not `PIN=LEVEL`.
    #[error("'{arg}': expected PIN=0|1")]
    NotPinLevel {
        /// The argument as given.
        arg: String,
    },
    /// A `parport-tool set` pin is not a number.
    #[error("'{text}' is not a pin number")]
    NotAPin {
        /// The pin as given.
        text: String,
    },
    /// A `parport-tool set` level is neither 0 nor 1.
    #[error("'{text}': use 0 or 1")]
    NotALevel {
        /// The level as given.
        text: String,
    },
    /// A pin the tool was asked to drive is not an output of the port.
    #[error("pin {pin} is not an output in {mode} mode")]
    NotAnOutput {
        /// The DB-25 pin number.
        pin: u8,
        /// The port's mode (`in`, `out`, `epp`, `x`).
        mode: &'static str,
    },
    /// The loopback self-test has no wire to check in this mode.
    #[error("nothing to test in {mode} mode; use out or x")]
    NothingToTest {
        /// The port's mode.
        mode: &'static str,
    },
    /// The tool could not catch the exit signals it stops on.
    #[error("catching the exit signals: {source}")]
    Signals {
        /// What HAL's signal set-up said.
        #[source]
        source: hal_core::HalError,
    },
}

/// Register access to one parallel port.
pub trait PortIo: Send + Sync {
    /// Reads the data register.
    fn read_data(&self) -> u8;
    /// Writes the data register (the output latch).
    fn write_data(&self, v: u8);
    /// Reads the status register (raw, before the 0x80 correction).
    fn read_status(&self) -> u8;
    /// Reads the control register (raw, before the 0x0B correction).
    fn read_control(&self) -> u8;
    /// Writes the control register (raw). Bit 5 sets the data direction.
    fn write_control(&self, v: u8);
    /// Whether the port has an extended control register (a known
    /// `base_hi`) this backend can write.
    fn has_ecr(&self) -> bool;
    /// Writes the ECR at `base_hi + 2`.
    fn write_ecr(&self, v: u8) -> Result<(), PortError>;
    /// Takes the port for exclusive use; must precede any access.
    fn claim(&self) -> Result<(), PortError>;
    /// Gives the port back (also done when the backend is dropped).
    fn release(&self);
    /// A description for messages: backend and device or address.
    fn describe(&self) -> String;
    /// How many accesses failed since the port was opened (the driver
    /// reports a non-zero count when it lets the port go).
    fn errors(&self) -> u64;
}

/// Where one port's registers sit on an I/O bus: `base` (data, status,
/// control, EPP) and `base_hi` (the ECP registers, when known). The
/// register accesses of [`PortIo`] through any [`PortBus`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortAt {
    /// The data register's address.
    pub base: u16,
    /// The ECP registers' address, when known.
    pub base_hi: Option<u16>,
}

impl PortAt {
    /// The I/O ranges the port occupies: 8 ports at `base`, 3 at
    /// `base_hi`. An error when one runs past 0xffff.
    pub fn ranges(&self) -> Result<Vec<PortRange>, hal_driver::DriverError> {
        let mut r = vec![PortRange::new(self.base, regs::BASE_SPAN)?];
        if let Some(hi) = self.base_hi {
            r.push(PortRange::new(hi, regs::HI_SPAN)?);
        }
        Ok(r)
    }

    /// Reads the data register.
    #[inline]
    pub fn read_data(&self, bus: &impl PortBus) -> u8 {
        bus.inb(self.base.wrapping_add(regs::DATA))
    }

    /// Writes the data register.
    #[inline]
    pub fn write_data(&self, bus: &impl PortBus, v: u8) {
        bus.outb(self.base.wrapping_add(regs::DATA), v)
    }

    /// Reads the status register.
    #[inline]
    pub fn read_status(&self, bus: &impl PortBus) -> u8 {
        bus.inb(self.base.wrapping_add(regs::STATUS))
    }

    /// Reads the control register.
    #[inline]
    pub fn read_control(&self, bus: &impl PortBus) -> u8 {
        bus.inb(self.base.wrapping_add(regs::CONTROL))
    }

    /// Writes the control register.
    #[inline]
    pub fn write_control(&self, bus: &impl PortBus, v: u8) {
        bus.outb(self.base.wrapping_add(regs::CONTROL), v)
    }

    /// Writes the ECR; false (nothing written) without a `base_hi`.
    pub fn write_ecr(&self, bus: &impl PortBus, v: u8) -> bool {
        match self.base_hi {
            Some(hi) => {
                bus.outb(hi.wrapping_add(regs::ECR), v);
                true
            }
            None => false,
        }
    }
}
