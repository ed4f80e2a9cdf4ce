//! USB pendant drivers for the HAL suite.
//!
//! * [`xhc`]: LinuxCNC's `xhc-hb04` user component for the XHC-HB04
//!   wireless MPG pendant (USB 10ce:eb70), through Linux's hidraw.

pub mod error;
#[cfg(feature = "fuzzing")]
pub mod fuzzing;
pub mod xhc;

pub use error::{Result, UsbError};
