//! `canservo`: a CANopen master for CiA 402 servo drives over SocketCAN.
//!
//! ```text
//! loadrt canservo iface=can0 nodes=1,2,3 scale=1000,1000,400 drive_file=x.sdo,y.sdo,z.sdo
//! addf canservo.read servo-thread
//! addf motion-command-handler servo-thread
//! addf motion-controller servo-thread
//! addf canservo.write servo-thread
//! net x-pos-cmd joint.0.motor-pos-cmd => canservo.0.position-cmd
//! net x-pos-fb  canservo.0.position-fb => joint.0.motor-pos-fb
//! net x-enable  joint.0.amp-enable-out => canservo.0.enable
//! net x-fault   canservo.0.amp-fault => joint.0.amp-fault-in
//! net x-home    joint.0.index-enable <=> canservo.0.home
//! ```
//!
//! # The name
//!
//! LinuxCNC has no CANopen driver, so there is no historic name to keep.
//! `canservo` says what it drives (servo drives on CAN) the way
//! `hal_parport`, `hal_motenc` and `hostmot2` say theirs, and is the name
//! the project's design gives it; pins are `canservo.<N>.<name>` with N
//! the drive's place in `nodes=` (not its node id, so a HAL file survives
//! renumbering a drive), functions `canservo.read` and `canservo.write`.
//!
//! # What it does
//!
//! At `loadrt`, each drive is brought up in hardware.md §6.11's order
//! ([`startup`]): NMT reset communication and the boot-up message, the
//! identity (0x1000 must be a CiA 402 device; 0x1018 becomes read-only
//! params), heartbeat producer (0x1017) and consumer of the master's
//! heartbeat (0x1016), the PDO mapping by SDO (RPDO1: controlword,
//! target, mode; TPDO1: statusword, position, mode display; TPDO2:
//! velocity, error code; all type 1 synchronous), the interpolation
//! period (0x60C2), the mode of operation (0x6060 checked in 0x6061), the
//! drive's own file of SDO writes ([`drivefile`]), then NMT start. A
//! drive that does not answer is a load error naming the node and what
//! it did not answer; nothing stays loaded.
//!
//! Each servo period `canservo.write` sends the RPDOs and then SYNC, and
//! the next `canservo.read` takes the TPDOs the drives sent after it
//! ([`engine`]). Neither can block: the realtime endpoint is a
//! **non-blocking socket** (see [`bus::SocketCanBus`] for why not a
//! helper thread with a hand-off: SYNC must leave at the start of the
//! period, not whenever a helper thread runs). SDO after start-up (error
//! history after a fault, polling the error register, bringing a node up
//! again after a communication fault) runs in a non-realtime helper
//! thread on its own socket (`helper`).
//!
//! The CiA 402 power state machine follows the `enable` pin both ways
//! ([`power`]); faults (bus-off, controller errors, no ACK, a missed
//! heartbeat, a node leaving Operational, an EMCY, the drive in Fault,
//! missing TPDOs, failed sends) trip the drive's fault latch in the
//! period they show, quick-stop and then disable it, and say why on
//! `fault-code` and in one log line; recovery takes a `fault-reset`
//! edge and a new `enable` edge ([`engine`] has the details). Drive-
//! internal homing (CiA 402 mode 6, the method from the drive file) runs
//! on the `home` pin with the index-enable handshake, with `position-fb`
//! echoing `position-cmd` meanwhile so the motion core's following error
//! stays calm.
//!
//! `backend=sim` puts simulated CiA 402 drives ([`sim`]) on an in-process
//! bus ([`bus::SimBus`]) that runs on the HAL thread's time; the same
//! drives run as their own process on a real or virtual CAN interface
//! with the `canservo-sim` binary.
//!
//! # Crate layout
//!
//! * [`frame`], [`regs`], [`codes`]: frames, the CANopen identifier and
//!   object map, SDO abort and EMCY codes with their meanings.
//! * [`bus`]: the bus trait and its SocketCAN and simulated backends.
//! * [`sdo`]: SDO client and server. [`drivefile`]: the per-drive file.
//! * [`startup`]: the typed start-up. [`power`]: the CiA 402 state
//!   machine, with a typed API for stepping a drive by hand.
//! * [`engine`]: the realtime read/write. `helper`: the non-realtime
//!   helper. `config`: the `loadrt` parameters. [`hal`]: the HAL
//!   binding and [`MODULE`].
//! * [`sim`]: the simulated drive. `rig` (feature `testing`): drives, bus and engine
//!   on simulated time. [`decode`]: frames in words, for the bring-up tool.
//!   `fuzzing` (feature `fuzzing`): the fuzz targets' bodies.

pub mod bus;
pub mod codes;
mod config;
pub mod decode;
pub mod drivefile;
pub mod engine;
mod error;
pub mod frame;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
mod helper;
pub mod power;
pub mod regs;
#[cfg(any(test, feature = "testing"))]
pub mod rig;
pub mod sdo;
pub mod sim;
pub mod startup;
pub mod tool;
pub mod tool_args;
mod units;

pub use config::MAX_DRIVES;
pub use error::{Error, Result};
pub use hal::{MODULE, SIM_ONLY_MODULE};
