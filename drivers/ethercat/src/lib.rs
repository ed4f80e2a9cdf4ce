//! EtherCAT without a kernel module: everything below the HAL binding of
//! `lcec` (phase 2 binds it to HAL on the shared driver layer).
//!
//! * [`wire`]: frames and datagrams, mailbox and CoE (SDO, emergency),
//!   the SII layout. [`regs`]: the ESC register map.
//! * [`sim`]: a simulated segment of ESCs (registers, SII EEPROM, AL
//!   states with their checks, FMMUs, sync managers, mailbox with an SDO
//!   server, DC clock) with the EK1100, EL1008/EL1018, EL2008/EL2088,
//!   EL3102, EL4102, EL5101, EL7041, a generic slave and a CiA 402 servo.
//! * [`link`]: how frames travel: in process to a [`sim::Segment`], or a
//!   raw AF_PACKET socket on an interface.
//! * [`master`]: the master on EtherCrab: bring-up to OP from an lcec
//!   configuration, then a realtime `read`/`write` that never blocks.
//! * [`lcec`]: linuxcnc-ethercat's `ethercat-conf.xml` and the pins each
//!   slave will have.
//! * `fuzzing` (feature `fuzzing`): the fuzz targets' bodies and seeds.

#![deny(unsafe_code)]

pub mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod lcec;
pub mod link;
pub mod master;
pub mod regs;
pub mod sdo;
pub mod sim;
pub mod tool;
pub mod wire;

pub use error::{Error, Result};
