//! The faults the realtime side detects, each a static [`Fault`] (code
//! and reason) for the shared layer's [`hal_driver::fault::FaultLatch`].
//! The code is what the `fault-code` pin shows.

use hal_driver::fault::Fault;

/// The CAN controller went bus-off: every drive is lost.
pub static BUS_OFF: Fault = Fault::new(1, "CAN bus off: every drive on the bus is lost");
/// Controller trouble: buffer overflow, error passive, TX timeout.
pub static CONTROLLER: Fault = Fault::new(
    2,
    "CAN controller error (overflow, error passive or transmit timeout)",
);
/// Nobody acknowledges our frames.
pub static NO_ACK: Fault = Fault::new(
    3,
    "no acknowledge on the CAN bus: no other node is powered or connected",
);
/// A drive's heartbeat stopped.
pub static HEARTBEAT: Fault = Fault::new(4, "heartbeat missed");
/// A drive left Operational (rebooted, stopped, pre-operational).
pub static NMT_STATE: Fault = Fault::new(5, "node left NMT Operational (rebooted or stopped)");
// The drive-side faults (6 EMCY, 7 drive in Fault, 10 homing error) are
// the shared CiA 402 layer's, the same on every fieldbus.
pub use hal_cia402::faults::{DRIVE_FAULT, EMCY, HOMING};
/// The drive's TPDOs did not come after SYNC.
pub static TPDO_MISSING: Fault = Fault::new(8, "TPDO missing after SYNC");
/// Frames cannot be queued for sending.
pub static TX_FAILED: Fault = Fault::new(
    9,
    "frames cannot be sent (transmit queue full, bus off or interface down)",
);
/// The thread's period is not the one the drives were set up for.
pub static PERIOD: Fault = Fault::new(
    11,
    "servo thread period differs from loadrt period_ns (0x60C2 was set for that)",
);

/// Whether recovering from `fault` needs the node brought up again
/// (NMT reset, configuration, NMT start) rather than a CiA 402 fault
/// reset: the communication faults, after which the drive may have
/// rebooted or dropped out of Operational.
pub fn needs_restart(fault: &Fault) -> bool {
    [
        &BUS_OFF,
        &CONTROLLER,
        &NO_ACK,
        &HEARTBEAT,
        &NMT_STATE,
        &TPDO_MISSING,
        &TX_FAILED,
    ]
    .iter()
    .any(|f| std::ptr::eq(*f, fault))
}
