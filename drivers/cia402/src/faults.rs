//! The drive-side faults every fieldbus detects the same way, each a
//! static [`Fault`] (code and reason) for the shared layer's
//! [`hal_driver::fault::FaultLatch`]. The code is what the `fault-code`
//! pin shows; a fieldbus declares its communication faults with codes of
//! its own that do not clash with these (6, 7, 10).

use hal_driver::fault::Fault;

/// A drive sent an emergency message with an error.
pub static EMCY: Fault = Fault::new(6, "EMCY received");
/// The statusword shows Fault (or Fault reaction active).
pub static DRIVE_FAULT: Fault = Fault::new(7, "drive in Fault");
/// Drive-internal homing ended in a homing error.
pub static HOMING: Fault = Fault::new(10, "drive-internal homing error");
