//! The motion command channel in the HAL instance's shared memory, usable
//! from any process: commands in, answers out, status as a snapshot.
//!
//! `motmod` creates four named regions when it loads:
//! * [`CMD_RING`]: a ring of [`CMD_WORDS`]-word command records, written by
//!   clients and read by `motion-command-handler` each servo period;
//! * [`REPLY_RING`]: a ring of [`REPLY_WORDS`]-word answers, one per
//!   command read, accepted or rejected with a reason, carrying the
//!   command's serial number so the sender can match it;
//! * [`STATUS`]: a seqlock snapshot of [`STATUS_WORDS`] words published by
//!   `motion-controller` every cycle (see [`MotionStatus`]);
//! * [`LOCK`]: two words, the sender lock (the rings have one producer and
//!   one consumer, so one sender at a time owns both client ends) and the
//!   next serial number.
//!
//! Every record is plain `u64` words (floats as their IEEE bits, signed
//! integers two's complement) starting with a version word and, for
//! commands and answers, ending with a checksum over the other words.
//! Everything read from shared memory is validated: a corrupt or unknown
//! command is answered with [`Reject::Malformed`](crate::command::Reject::Malformed) and never executed; a
//! corrupt answer or snapshot is reported to the client as an error.
//!
//! Command record, word by word: 0 version ([`CMD_VERSION`]), 1 serial
//! (non-zero), 2 opcode, 3 joint or axis number, or the motion id of a
//! queued move (i32 sign-extended; zero for commands without one),
//! 4..=27 up to 24 float arguments (unused ones zero; a pose is nine of
//! them), 28..=30 reserved (zero), 31 checksum.
//!
//! Status header words 10 and 11: how many messages the controller
//! reported (see [`crate::Event`]) and the last one's wire word, so a
//! client in another process sees faults as they happen. The fault block
//! at [`FAULT_START`] keeps the last fault (see [`crate::Fault`]) when
//! later messages are not faults. The external-offset block at
//! [`EOFFSET_START`] follows it, then the path block at [`PATH_START`].
//!
//! The status format grows only at its end. A layout change of existing
//! words takes a new [`STATUS_VERSION`] (a reader refuses any other);
//! words appended keep the version: a reader copies the words it knows
//! (the snapshot region states its length), and a newer reader of an
//! older controller's shorter snapshot finds the appended words zero,
//! which reads as "not reported".
//!
//! Answer record: 0 version ([`REPLY_VERSION`]), 1 serial, 2 result code
//! (0 accepted, else [`reject_code`]), 3 and 4 integer details, 5..=7
//! float details, 8 checksum.

use crate::kins::NUM_AXES;
use crate::sizes::{MAX_IO, MAX_JOINTS, MAX_SPINDLES};

mod client;
mod records;
mod snapshot;

pub use crate::command::{reject_code, result_name, WireError};
pub use crate::status::{
    AxisState, EoffsetState, IoState, JointState, LastCommand, MotionStatus, SpindleState,
    TrajState,
};
pub use client::{Accepted, ClientError, MotionClient, Rejected, COMMAND_TIMEOUT};
pub use records::{decode_command, decode_reply, encode_command, encode_reply};
pub use snapshot::{decode_status, fill_status};

/// Name of the command ring region.
pub const CMD_RING: &str = "motmod.command";
/// Name of the answer ring region.
pub const REPLY_RING: &str = "motmod.reply";
/// Name of the status snapshot region.
pub const STATUS: &str = "motmod.status";
/// Name of the sender-lock region.
pub const LOCK: &str = "motmod.command-lock";

/// Words per command record.
pub const CMD_WORDS: usize = 32;
/// Words per answer record.
pub const REPLY_WORDS: usize = 9;
/// Depth of both rings (holds one record fewer).
pub const RING_DEPTH: usize = 16;
/// Words of the status header, before the per-joint blocks.
pub const STATUS_HEADER: usize = 12;
/// Words per joint in the status snapshot.
pub const JOINT_WORDS: usize = 8;
/// Where the per-axis blocks start, after the joint blocks.
pub const AXES_START: usize = STATUS_HEADER + MAX_JOINTS * JOINT_WORDS;
/// Words per world axis in the status snapshot.
pub const AXIS_WORDS: usize = 5;
/// Where the coordinated-planner block starts, after the axis blocks.
pub const TRAJ_START: usize = AXES_START + NUM_AXES * AXIS_WORDS;
/// Words of the coordinated-planner block.
pub const TRAJ_WORDS: usize = 37;
/// Where the spindle block starts (its first word: how many spindles),
/// after the coordinated-planner block.
pub const SPINDLES_START: usize = TRAJ_START + TRAJ_WORDS;
/// Words per spindle in the status snapshot.
pub const SPINDLE_WORDS: usize = 5;
/// Where the digital and analog I/O block starts: the counts (num_dio,
/// and num_aio shifted by 8), the digital inputs' and outputs' bits,
/// then the analog inputs and outputs.
pub const IO_START: usize = SPINDLES_START + 1 + MAX_SPINDLES * SPINDLE_WORDS;
/// Where the fault block starts, after the I/O block: appended to
/// format 4, whose snapshot ended here.
pub const FAULT_START: usize = IO_START + 3 + 2 * MAX_IO;
/// Where the external-offset block starts, after the fault block
/// (appended to format 4 too): a flags word (bit 0
/// `motion.eoffset-active`, bit 1 `motion.eoffset-limited`), the nine
/// applied offsets, then the nine requested ones, X to W.
pub const EOFFSET_START: usize = FAULT_START + crate::fault::FAULT_WORDS;
/// Words of the external-offset block.
pub const EOFFSET_WORDS: usize = 1 + 2 * NUM_AXES;
/// Where the path block starts, after the external-offset block
/// (appended to format 4): a flags word (bit 0 set by a controller that
/// reports the block, bits 8 to 15 the override enable bits, bits 16 to
/// 23 the kinematics type), then the executing move's distance to go per
/// axis, X to W.
pub const PATH_START: usize = EOFFSET_START + EOFFSET_WORDS;
/// Words of the path block.
pub const PATH_WORDS: usize = 1 + NUM_AXES;
/// Words of the status snapshot.
pub const STATUS_WORDS: usize = PATH_START + PATH_WORDS;

/// Version word of a command record: "MOTCMD" and format 2 (format 2
/// has 32 words, for the queueing commands' poses).
pub const CMD_VERSION: u64 = 0x4d4f_5443_4d44_0002;
/// Version word of an answer record: "MOTREP" and format 1.
pub const REPLY_VERSION: u64 = 0x4d4f_5452_4550_0001;
/// Version word of the status snapshot: "MOTSTA" and format 4 (format 2
/// added the axis blocks and the mode flags, format 3 the coordinated
/// planner block, format 4 the spindle and I/O blocks; the fault block
/// was appended to format 4, see the module).
pub const STATUS_VERSION: u64 = 0x4d4f_5453_5441_0004;

/// Float argument words of a command record.
pub(crate) const ARGS: usize = 4;
/// How many float arguments a command record carries.
pub(crate) const MAX_ARGS: usize = CMD_WORDS - ARGS - 4;
/// Commands the handler takes per servo period at most.
pub const MAX_PER_PERIOD: usize = 4;

/// The checksum of a record: a mixing fold over `words`. Each step is a
/// bijection of the running value for a fixed word and of the word for a
/// fixed running value, so changing any single word changes the result.
pub fn checksum(words: &[u64]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &w in words {
        h ^= w;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
        h ^= h >> 29;
    }
    h
}

#[cfg(test)]
mod eoffset_tests;
#[cfg(test)]
mod fault_tests;
#[cfg(test)]
pub(crate) mod tests;
