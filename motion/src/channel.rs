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
//! command is answered with [`Reject::Malformed`] and never executed; a
//! corrupt answer or snapshot is reported to the client as an error.
//!
//! Command record, word by word: 0 version ([`CMD_VERSION`]), 1 serial
//! (non-zero), 2 opcode, 3 joint or axis number (i32 sign-extended; zero
//! for commands without one), 4..=12 up to nine float arguments (unused
//! ones zero), 13 and 14 reserved (zero), 15 checksum.
//!
//! Answer record: 0 version ([`REPLY_VERSION`]), 1 serial, 2 result code
//! (0 accepted, else [`reject_code`]), 3 and 4 integer details, 5..=7
//! float details, 8 checksum.

use std::fmt;
use std::sync::atomic::Ordering::*;
use std::time::{Duration, Instant};

use hal_core::{HalError, Instance, Region, RingReader, RingWriter, SeqLockReader};

use crate::command::{Command, Direction, Feature, Quantity, Reject};
use crate::core::{MotionCore, MotionState, MAX_JOINTS};
use crate::homing::{ConfigProblem, HomeFlags, HomeState, HomingConfig};
use crate::kins::{Pose, AXIS_LETTERS, NUM_AXES};

/// Name of the command ring region.
pub const CMD_RING: &str = "motmod.command";
/// Name of the answer ring region.
pub const REPLY_RING: &str = "motmod.reply";
/// Name of the status snapshot region.
pub const STATUS: &str = "motmod.status";
/// Name of the sender-lock region.
pub const LOCK: &str = "motmod.command-lock";

/// Words per command record.
pub const CMD_WORDS: usize = 16;
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
/// Words of the status snapshot.
pub const STATUS_WORDS: usize = AXES_START + NUM_AXES * AXIS_WORDS;

/// Version word of a command record: "MOTCMD" and format 1.
pub const CMD_VERSION: u64 = 0x4d4f_5443_4d44_0001;
/// Version word of an answer record: "MOTREP" and format 1.
pub const REPLY_VERSION: u64 = 0x4d4f_5452_4550_0001;
/// Version word of the status snapshot: "MOTSTA" and format 2 (format 2
/// added the axis blocks and the mode flags).
pub const STATUS_VERSION: u64 = 0x4d4f_5453_5441_0002;

/// Float argument words of a command record.
const ARGS: usize = 4;
/// Commands the handler takes per servo period at most.
pub const MAX_PER_PERIOD: usize = 4;

/// Why a record read from shared memory was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireError {
    /// The version word is not the one this build speaks.
    BadVersion { found: u64 },
    /// The checksum does not match the other words.
    BadChecksum,
    /// Serial number zero (reserved for "none").
    ZeroSerial,
    /// An opcode no command has.
    UnknownOpcode { opcode: u64 },
    /// A joint word that is not a sign-extended i32, or non-zero for a
    /// command without a joint.
    BadJoint { value: u64 },
    /// A word the command does not use is not zero.
    UnusedWordSet { index: usize },
    /// A result or reason code no answer has.
    UnknownCode { code: u64 },
    /// The status snapshot's header is inconsistent.
    BadStatus,
    /// A word that carries a whole number holds a fraction or a value out
    /// of range.
    BadInteger { index: usize },
}

impl WireError {
    fn code(self) -> (u64, u64) {
        match self {
            WireError::BadVersion { found } => (1, found),
            WireError::BadChecksum => (2, 0),
            WireError::ZeroSerial => (3, 0),
            WireError::UnknownOpcode { opcode } => (4, opcode),
            WireError::BadJoint { value } => (5, value),
            WireError::UnusedWordSet { index } => (6, index as u64),
            WireError::UnknownCode { code } => (7, code),
            WireError::BadStatus => (8, 0),
            WireError::BadInteger { index } => (9, index as u64),
        }
    }

    fn from_code(code: u64, detail: u64) -> Option<WireError> {
        Some(match code {
            1 => WireError::BadVersion { found: detail },
            2 => WireError::BadChecksum,
            3 => WireError::ZeroSerial,
            4 => WireError::UnknownOpcode { opcode: detail },
            5 => WireError::BadJoint { value: detail },
            6 => WireError::UnusedWordSet {
                index: usize::try_from(detail).ok()?,
            },
            7 => WireError::UnknownCode { code: detail },
            8 => WireError::BadStatus,
            9 => WireError::BadInteger {
                index: usize::try_from(detail).ok()?,
            },
            _ => return None,
        })
    }
}

impl fmt::Display for WireError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            WireError::BadVersion { found } => write!(
                f,
                "version word {found:#018x} is not {CMD_VERSION:#018x} (client and controller differ)"
            ),
            WireError::BadChecksum => f.write_str("checksum mismatch (corrupt record)"),
            WireError::ZeroSerial => f.write_str("serial number 0"),
            WireError::UnknownOpcode { opcode } => write!(f, "unknown opcode {opcode}"),
            WireError::BadJoint { value } => write!(f, "bad joint word {value:#x}"),
            WireError::UnusedWordSet { index } => write!(f, "unused word {index} is not zero"),
            WireError::UnknownCode { code } => write!(f, "unknown result code {code}"),
            WireError::BadStatus => f.write_str("inconsistent status snapshot"),
            WireError::BadInteger { index } => {
                write!(f, "word {index} does not hold a whole number in range")
            }
        }
    }
}

impl std::error::Error for WireError {}

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

/// (opcode, takes a joint, number of float arguments) of a command, and
/// its joint and arguments.
fn shape(cmd: &Command) -> (u64, Option<i32>, [f64; NUM_AXES], usize) {
    let mut a = [0.0; NUM_AXES];
    let mut put = |v: &[f64]| {
        a[..v.len()].copy_from_slice(v);
        v.len()
    };
    match *cmd {
        Command::Abort => (1, None, a, 0),
        Command::Enable => (2, None, a, 0),
        Command::Disable => (3, None, a, 0),
        Command::Free => (4, None, a, 0),
        Command::Teleop => (5, None, a, 0),
        Command::Coord => (6, None, a, 0),
        Command::JogCont { joint, vel } => {
            let n = put(&[vel]);
            (7, Some(joint), a, n)
        }
        Command::JogIncr { joint, vel, offset } => {
            let n = put(&[vel, offset]);
            (8, Some(joint), a, n)
        }
        Command::JogAbs { joint, vel, pos } => {
            let n = put(&[vel, pos]);
            (9, Some(joint), a, n)
        }
        Command::JogAbort { joint } => (10, Some(joint), a, 0),
        Command::JointActivate { joint } => (11, Some(joint), a, 0),
        Command::JointDeactivate { joint } => (12, Some(joint), a, 0),
        Command::OverrideLimits { joint } => (13, Some(joint), a, 0),
        Command::Scale { scale } => {
            let n = put(&[scale]);
            (14, None, a, n)
        }
        Command::EnableAmplifier { joint } => (15, Some(joint), a, 0),
        Command::DisableAmplifier { joint } => (16, Some(joint), a, 0),
        Command::SetJointPositionLimits { joint, min, max } => {
            let n = put(&[min, max]);
            (17, Some(joint), a, n)
        }
        Command::SetJointVelLimit { joint, vel } => {
            let n = put(&[vel]);
            (18, Some(joint), a, n)
        }
        Command::SetJointAccLimit { joint, acc } => {
            let n = put(&[acc]);
            (19, Some(joint), a, n)
        }
        Command::SetJointMinFerror { joint, ferror } => {
            let n = put(&[ferror]);
            (20, Some(joint), a, n)
        }
        Command::SetJointMaxFerror { joint, ferror } => {
            let n = put(&[ferror]);
            (21, Some(joint), a, n)
        }
        Command::SetJointBacklash { joint, backlash } => {
            let n = put(&[backlash]);
            (22, Some(joint), a, n)
        }
        Command::SetJointMotorOffset { joint, offset } => {
            let n = put(&[offset]);
            (23, Some(joint), a, n)
        }
        Command::SetWorldHome { pose } => {
            let n = put(&pose.0);
            (24, None, a, n)
        }
        Command::Home { joint } => (25, Some(joint), a, 0),
        Command::Unhome { joint } => (26, Some(joint), a, 0),
        Command::SetJointHomingParams { joint, config } => {
            let n = put(&[
                config.offset,
                config.home,
                config.final_vel,
                config.search_vel,
                config.latch_vel,
                f64::from(config.flags.bits()),
                f64::from(config.sequence),
                if config.volatile_home { 1.0 } else { 0.0 },
            ]);
            (27, Some(joint), a, n)
        }
        Command::UpdateJointHomingParams {
            joint,
            offset,
            home,
            sequence,
        } => {
            let n = put(&[offset, home, f64::from(sequence)]);
            (28, Some(joint), a, n)
        }

        Command::AxisJogCont { axis, vel } => {
            let n = put(&[vel]);
            (29, Some(axis), a, n)
        }
        Command::AxisJogIncr { axis, vel, offset } => {
            let n = put(&[vel, offset]);
            (30, Some(axis), a, n)
        }
        Command::AxisJogAbs { axis, vel, pos } => {
            let n = put(&[vel, pos]);
            (31, Some(axis), a, n)
        }
        Command::AxisJogAbort { axis } => (32, Some(axis), a, 0),
        Command::SetAxisPositionLimits { axis, min, max } => {
            let n = put(&[min, max]);
            (33, Some(axis), a, n)
        }
        Command::SetAxisVelLimit { axis, vel } => {
            let n = put(&[vel]);
            (34, Some(axis), a, n)
        }
        Command::SetAxisAccLimit { axis, acc } => {
            let n = put(&[acc]);
            (35, Some(axis), a, n)
        }
    }
}

/// The float arguments of `opcode` that carry integers, with their
/// ranges: such an argument must be a whole number in range.
fn integer_args(opcode: u64) -> &'static [(usize, f64, f64)] {
    const U32: f64 = u32::MAX as f64;
    const I32_MIN: f64 = i32::MIN as f64;
    const I32_MAX: f64 = i32::MAX as f64;
    match opcode {
        27 => &[(5, 0.0, U32), (6, I32_MIN, I32_MAX), (7, 0.0, 1.0)],
        28 => &[(2, I32_MIN, I32_MAX)],
        _ => &[],
    }
}

/// Builds the command of `opcode` from its joint and float arguments; also
/// says whether it takes a joint and how many floats.
fn build(opcode: u64, j: i32, a: &[f64; NUM_AXES]) -> Option<(Command, bool, usize)> {
    let c = |cmd, joint, n| Some((cmd, joint, n));
    match opcode {
        1 => c(Command::Abort, false, 0),
        2 => c(Command::Enable, false, 0),
        3 => c(Command::Disable, false, 0),
        4 => c(Command::Free, false, 0),
        5 => c(Command::Teleop, false, 0),
        6 => c(Command::Coord, false, 0),
        7 => c(
            Command::JogCont {
                joint: j,
                vel: a[0],
            },
            true,
            1,
        ),
        8 => c(
            Command::JogIncr {
                joint: j,
                vel: a[0],
                offset: a[1],
            },
            true,
            2,
        ),
        9 => c(
            Command::JogAbs {
                joint: j,
                vel: a[0],
                pos: a[1],
            },
            true,
            2,
        ),
        10 => c(Command::JogAbort { joint: j }, true, 0),
        11 => c(Command::JointActivate { joint: j }, true, 0),
        12 => c(Command::JointDeactivate { joint: j }, true, 0),
        13 => c(Command::OverrideLimits { joint: j }, true, 0),
        14 => c(Command::Scale { scale: a[0] }, false, 1),
        15 => c(Command::EnableAmplifier { joint: j }, true, 0),
        16 => c(Command::DisableAmplifier { joint: j }, true, 0),
        17 => c(
            Command::SetJointPositionLimits {
                joint: j,
                min: a[0],
                max: a[1],
            },
            true,
            2,
        ),
        18 => c(
            Command::SetJointVelLimit {
                joint: j,
                vel: a[0],
            },
            true,
            1,
        ),
        19 => c(
            Command::SetJointAccLimit {
                joint: j,
                acc: a[0],
            },
            true,
            1,
        ),
        20 => c(
            Command::SetJointMinFerror {
                joint: j,
                ferror: a[0],
            },
            true,
            1,
        ),
        21 => c(
            Command::SetJointMaxFerror {
                joint: j,
                ferror: a[0],
            },
            true,
            1,
        ),
        22 => c(
            Command::SetJointBacklash {
                joint: j,
                backlash: a[0],
            },
            true,
            1,
        ),
        23 => c(
            Command::SetJointMotorOffset {
                joint: j,
                offset: a[0],
            },
            true,
            1,
        ),
        24 => c(Command::SetWorldHome { pose: Pose(*a) }, false, NUM_AXES),
        25 => c(Command::Home { joint: j }, true, 0),
        26 => c(Command::Unhome { joint: j }, true, 0),
        // The integer arguments were checked by `decode_command`.
        27 => c(
            Command::SetJointHomingParams {
                joint: j,
                config: HomingConfig {
                    offset: a[0],
                    home: a[1],
                    final_vel: a[2],
                    search_vel: a[3],
                    latch_vel: a[4],
                    flags: HomeFlags::from_bits_retain(a[5] as u32),
                    sequence: a[6] as i32,
                    volatile_home: a[7] != 0.0,
                },
            },
            true,
            8,
        ),
        28 => c(
            Command::UpdateJointHomingParams {
                joint: j,
                offset: a[0],
                home: a[1],
                sequence: a[2] as i32,
            },
            true,
            3,
        ),
        29 => c(Command::AxisJogCont { axis: j, vel: a[0] }, true, 1),
        30 => c(
            Command::AxisJogIncr {
                axis: j,
                vel: a[0],
                offset: a[1],
            },
            true,
            2,
        ),
        31 => c(
            Command::AxisJogAbs {
                axis: j,
                vel: a[0],
                pos: a[1],
            },
            true,
            2,
        ),
        32 => c(Command::AxisJogAbort { axis: j }, true, 0),
        33 => c(
            Command::SetAxisPositionLimits {
                axis: j,
                min: a[0],
                max: a[1],
            },
            true,
            2,
        ),
        34 => c(Command::SetAxisVelLimit { axis: j, vel: a[0] }, true, 1),
        35 => c(Command::SetAxisAccLimit { axis: j, acc: a[0] }, true, 1),
        _ => None,
    }
}

/// The record of `cmd` with serial number `serial`.
pub fn encode_command(serial: u64, cmd: &Command) -> [u64; CMD_WORDS] {
    let (op, joint, args, n) = shape(cmd);
    let mut w = [0u64; CMD_WORDS];
    w[0] = CMD_VERSION;
    w[1] = serial;
    w[2] = op;
    w[3] = joint.map_or(0, |j| j as i64 as u64);
    for i in 0..n {
        w[ARGS + i] = args[i].to_bits();
    }
    w[CMD_WORDS - 1] = checksum(&w[..CMD_WORDS - 1]);
    w
}

/// Validates and decodes a command record. The error carries the serial
/// word as read (to address the answer) and what was wrong.
pub fn decode_command(w: &[u64; CMD_WORDS]) -> Result<(u64, Command), (u64, WireError)> {
    let serial = w[1];
    let err = |e| Err((serial, e));
    if w[0] != CMD_VERSION {
        return err(WireError::BadVersion { found: w[0] });
    }
    if checksum(&w[..CMD_WORDS - 1]) != w[CMD_WORDS - 1] {
        return err(WireError::BadChecksum);
    }
    if serial == 0 {
        return err(WireError::ZeroSerial);
    }
    let jw = w[3] as i64;
    let joint = i32::try_from(jw).map_err(|_| (serial, WireError::BadJoint { value: w[3] }))?;
    let mut a = [0.0; NUM_AXES];
    for (i, v) in a.iter_mut().enumerate() {
        *v = f64::from_bits(w[ARGS + i]);
    }
    for &(i, lo, hi) in integer_args(w[2]) {
        let v = a[i];
        if !(v.fract() == 0.0 && v >= lo && v <= hi) {
            return err(WireError::BadInteger { index: ARGS + i });
        }
    }
    let Some((cmd, takes_joint, n)) = build(w[2], joint, &a) else {
        return err(WireError::UnknownOpcode { opcode: w[2] });
    };
    if !takes_joint && w[3] != 0 {
        return err(WireError::BadJoint { value: w[3] });
    }
    if let Some(index) = (ARGS + n..CMD_WORDS - 1).find(|&i| w[i] != 0) {
        return err(WireError::UnusedWordSet { index });
    }
    Ok((serial, cmd))
}

fn dir_code(d: Direction) -> u64 {
    match d {
        Direction::Positive => 0,
        Direction::Negative => 1,
    }
}

/// The reason code of a rejection on the wire (never 0, which means
/// accepted).
pub fn reject_code(r: &Reject) -> u64 {
    encode_reject(r).0
}

/// (code, two integer details, three float details) of a rejection.
fn encode_reject(r: &Reject) -> (u64, [u64; 2], [f64; 3]) {
    let i = |v: i64| v as u64;
    match *r {
        Reject::NoSuchJoint { joint, num_joints } => {
            (1, [i(joint as i64), num_joints as u64], [0.0; 3])
        }
        Reject::JointInactive { joint } => (2, [joint as u64, 0], [0.0; 3]),
        Reject::EnableInputFalse => (3, [0; 2], [0.0; 3]),
        Reject::NotEnabled => (4, [0; 2], [0.0; 3]),
        Reject::NotFreeMode => (5, [0; 2], [0.0; 3]),
        Reject::JogInhibited => (6, [0; 2], [0.0; 3]),
        Reject::HomingActive => (7, [0; 2], [0.0; 3]),
        Reject::WheelJogActive { joint } => (8, [joint as u64, 0], [0.0; 3]),
        Reject::JointMoving { joint } => (9, [joint as u64, 0], [0.0; 3]),
        Reject::OnHardLimit { joint, dir } => (10, [joint as u64, dir_code(dir)], [0.0; 3]),
        Reject::PastSoftLimit { joint, dir } => (11, [joint as u64, dir_code(dir)], [0.0; 3]),
        Reject::TargetOutsideLimits {
            joint,
            target,
            min,
            max,
        } => (12, [joint as u64, 0], [target, min, max]),
        Reject::BadVelocity { vel } => (13, [0; 2], [vel, 0.0, 0.0]),
        Reject::BadValue { what, value } => (14, [0, what.code()], [value, 0.0, 0.0]),
        Reject::LimitsReversed { min, max } => (15, [0; 2], [min, max, 0.0]),
        Reject::Timeout => (16, [0; 2], [0.0; 3]),
        Reject::Unsupported { what } => (17, [0, what.code()], [0.0; 3]),
        Reject::Malformed { error } => {
            let (c, d) = error.code();
            (18, [c, d], [0.0; 3])
        }
        Reject::ActivateWhileEnabled { joint } => (19, [joint as u64, 0], [0.0; 3]),
        Reject::HomingInhibited => (20, [0; 2], [0.0; 3]),
        Reject::NothingToHome => (21, [0; 2], [0.0; 3]),
        Reject::HomeSequenceGap { missing } => (22, [i(missing.into()), 0], [0.0; 3]),
        Reject::AlreadyHomed { joint } => (23, [joint as u64, 0], [0.0; 3]),
        Reject::SharedHomeSwitchClosed { joint } => (24, [joint as u64, 0], [0.0; 3]),
        Reject::BadHomingConfig { joint, problem } => {
            (25, [joint as u64, problem.code()], [0.0; 3])
        }
        Reject::SynchronizedJoint { joint } => (26, [joint as u64, 0], [0.0; 3]),
        Reject::LockingIndexer { joint } => (27, [joint as u64, 0], [0.0; 3]),
        Reject::NotFreeOrDisabled => (28, [0; 2], [0.0; 3]),
        Reject::ExtraJointEnabled { joint } => (29, [joint as u64, 0], [0.0; 3]),
        Reject::NotInPosition => (30, [0; 2], [0.0; 3]),
        Reject::NotHomed => (31, [0; 2], [0.0; 3]),
        Reject::NotTeleopMode => (32, [0; 2], [0.0; 3]),
        Reject::JointJogInTeleop => (33, [0; 2], [0.0; 3]),
        Reject::NoSuchAxis { axis } => (34, [i(axis as i64), 0], [0.0; 3]),
        Reject::AxisNotInKinematics { axis } => (35, [axis as u64, 0], [0.0; 3]),
        Reject::MotionError => (36, [0; 2], [0.0; 3]),
        Reject::AxisWheelJogActive { axis } => (37, [axis as u64, 0], [0.0; 3]),
        Reject::AxisPastLimit { axis, dir } => (38, [axis as u64, dir_code(dir)], [0.0; 3]),
        Reject::AxisTargetOutsideLimits {
            axis,
            target,
            min,
            max,
        } => (39, [axis as u64, 0], [target, min, max]),
        Reject::KinematicsFailed => (40, [0; 2], [0.0; 3]),
        Reject::ModeChangeJump { joint, jump } => (41, [joint as u64, 0], [jump, 0.0, 0.0]),
    }
}

fn decode_reject(code: u64, n: [u64; 2], f: [f64; 3]) -> Option<Reject> {
    let joint = || usize::try_from(n[0]).ok();
    let dir = || match n[1] {
        0 => Some(Direction::Positive),
        1 => Some(Direction::Negative),
        _ => None,
    };
    Some(match code {
        1 => Reject::NoSuchJoint {
            joint: i32::try_from(n[0] as i64).ok()?,
            num_joints: usize::try_from(n[1]).ok()?,
        },
        2 => Reject::JointInactive { joint: joint()? },
        3 => Reject::EnableInputFalse,
        4 => Reject::NotEnabled,
        5 => Reject::NotFreeMode,
        6 => Reject::JogInhibited,
        7 => Reject::HomingActive,
        8 => Reject::WheelJogActive { joint: joint()? },
        9 => Reject::JointMoving { joint: joint()? },
        10 => Reject::OnHardLimit {
            joint: joint()?,
            dir: dir()?,
        },
        11 => Reject::PastSoftLimit {
            joint: joint()?,
            dir: dir()?,
        },
        12 => Reject::TargetOutsideLimits {
            joint: joint()?,
            target: f[0],
            min: f[1],
            max: f[2],
        },
        13 => Reject::BadVelocity { vel: f[0] },
        14 => Reject::BadValue {
            what: Quantity::from_code(n[1])?,
            value: f[0],
        },
        15 => Reject::LimitsReversed {
            min: f[0],
            max: f[1],
        },
        16 => Reject::Timeout,
        17 => Reject::Unsupported {
            what: Feature::from_code(n[1])?,
        },
        18 => Reject::Malformed {
            error: WireError::from_code(n[0], n[1])?,
        },
        19 => Reject::ActivateWhileEnabled { joint: joint()? },
        20 => Reject::HomingInhibited,
        21 => Reject::NothingToHome,
        22 => Reject::HomeSequenceGap {
            missing: i32::try_from(n[0] as i64).ok()?,
        },
        23 => Reject::AlreadyHomed { joint: joint()? },
        24 => Reject::SharedHomeSwitchClosed { joint: joint()? },
        25 => Reject::BadHomingConfig {
            joint: joint()?,
            problem: ConfigProblem::from_code(n[1])?,
        },
        26 => Reject::SynchronizedJoint { joint: joint()? },
        27 => Reject::LockingIndexer { joint: joint()? },
        28 => Reject::NotFreeOrDisabled,
        29 => Reject::ExtraJointEnabled { joint: joint()? },
        30 => Reject::NotInPosition,
        31 => Reject::NotHomed,
        32 => Reject::NotTeleopMode,
        33 => Reject::JointJogInTeleop,
        34 => Reject::NoSuchAxis {
            axis: i32::try_from(n[0] as i64).ok()?,
        },
        35 => Reject::AxisNotInKinematics { axis: joint()? },
        36 => Reject::MotionError,
        37 => Reject::AxisWheelJogActive { axis: joint()? },
        38 => Reject::AxisPastLimit {
            axis: joint()?,
            dir: dir()?,
        },
        39 => Reject::AxisTargetOutsideLimits {
            axis: joint()?,
            target: f[0],
            min: f[1],
            max: f[2],
        },
        40 => Reject::KinematicsFailed,
        41 => Reject::ModeChangeJump {
            joint: joint()?,
            jump: f[0],
        },
        _ => return None,
    })
}

/// The answer record for the command `serial`.
pub fn encode_reply(serial: u64, result: &Result<(), Reject>) -> [u64; REPLY_WORDS] {
    let mut w = [0u64; REPLY_WORDS];
    w[0] = REPLY_VERSION;
    w[1] = serial;
    if let Err(r) = result {
        let (code, n, f) = encode_reject(r);
        w[2] = code;
        w[3] = n[0];
        w[4] = n[1];
        for i in 0..3 {
            w[5 + i] = f[i].to_bits();
        }
    }
    w[REPLY_WORDS - 1] = checksum(&w[..REPLY_WORDS - 1]);
    w
}

/// Validates and decodes an answer record: (serial, result).
pub fn decode_reply(w: &[u64; REPLY_WORDS]) -> Result<(u64, Result<(), Reject>), WireError> {
    if w[0] != REPLY_VERSION {
        return Err(WireError::BadVersion { found: w[0] });
    }
    if checksum(&w[..REPLY_WORDS - 1]) != w[REPLY_WORDS - 1] {
        return Err(WireError::BadChecksum);
    }
    if w[2] == 0 {
        if let Some(index) = (3..REPLY_WORDS - 1).find(|&i| w[i] != 0) {
            return Err(WireError::UnusedWordSet { index });
        }
        return Ok((w[1], Ok(())));
    }
    let f = [
        f64::from_bits(w[5]),
        f64::from_bits(w[6]),
        f64::from_bits(w[7]),
    ];
    let r = decode_reject(w[2], [w[3], w[4]], f).ok_or(WireError::UnknownCode { code: w[2] })?;
    Ok((w[1], Err(r)))
}

/// Status flag bits of the header word 3.
mod flag {
    pub const ENABLED: u64 = 1;
    pub const IN_POSITION: u64 = 2;
    pub const ERROR: u64 = 4;
    pub const ON_SOFT_LIMIT: u64 = 8;
    pub const JOG_ACTIVE: u64 = 16;
    pub const HOMING_ACTIVE: u64 = 32;
    pub const ALL_HOMED: u64 = 64;
    pub const ENABLE_INPUT: u64 = 128;
    /// The TELEOP flag (kept while disabled: the mode entered on enable).
    pub const TELEOP_MODE: u64 = 256;
    /// The COORD flag (likewise).
    pub const COORD_MODE: u64 = 512;
}

/// Status flag bits of an axis's first word.
mod aflag {
    pub const IN_KINEMATICS: u64 = 1;
    pub const TP_ENABLE: u64 = 2;
    pub const KB_JOG: u64 = 4;
    pub const WHEEL_JOG: u64 = 8;
    pub const MOVING: u64 = 16;
}

/// Status flag bits of a joint's first word.
mod jflag {
    pub const ACTIVE: u64 = 1;
    pub const AMP_ENABLED: u64 = 2;
    pub const IN_POSITION: u64 = 4;
    pub const ERROR: u64 = 8;
    pub const POS_HARD_LIMIT: u64 = 16;
    pub const NEG_HARD_LIMIT: u64 = 32;
    pub const FOLLOWING_ERROR: u64 = 64;
    pub const FAULTED: u64 = 128;
    pub const HOMED: u64 = 256;
    pub const HOMING: u64 = 512;
    pub const JOGGING: u64 = 1024;
    /// Bits 16..24 hold the homing state number.
    pub const HOME_STATE_SHIFT: u32 = 16;
}

/// The last command the channel answered: its serial and result code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LastCommand {
    /// Serial number (0: none yet).
    pub serial: u64,
    /// 0 accepted, else the [`reject_code`].
    pub code: u64,
}

/// Fills `out` (at least [`STATUS_WORDS`] long) with the snapshot of
/// `core`. Realtime-safe: no allocation.
pub fn fill_status(core: &MotionCore, last: LastCommand, served: u64, out: &mut [u64]) {
    out.iter_mut().for_each(|w| *w = 0);
    let n = core.num_joints().min(MAX_JOINTS);
    out[0] = STATUS_VERSION;
    out[1] = n as u64;
    out[2] = match core.state() {
        MotionState::Disabled => 0,
        MotionState::Free => 1,
        MotionState::Teleop => 2,
        MotionState::Coord => 3,
    };
    let bit = |b: bool, f: u64| if b { f } else { 0 };
    out[3] = bit(core.is_enabled(), flag::ENABLED)
        | bit(core.in_position(), flag::IN_POSITION)
        | bit(core.error(), flag::ERROR)
        | bit(core.on_soft_limit(), flag::ON_SOFT_LIMIT)
        | bit(core.jog_is_active(), flag::JOG_ACTIVE)
        | bit(core.homing_active(), flag::HOMING_ACTIVE)
        | bit(core.is_all_homed(), flag::ALL_HOMED)
        | bit(core.inputs.enable, flag::ENABLE_INPUT)
        | bit(core.teleop_mode(), flag::TELEOP_MODE)
        | bit(core.coord_mode(), flag::COORD_MODE);
    out[4] = core.heartbeat();
    out[5] = last.serial;
    out[6] = last.code;
    out[7] = core.scale().to_bits();
    out[8] = core.override_limit_mask() as u64;
    out[9] = served;
    // Read through references: this runs every servo cycle.
    for j in 0..n {
        let s = core.joint_ref(j);
        let w = &mut out[STATUS_HEADER + j * JOINT_WORDS..][..JOINT_WORDS];
        w[0] = bit(s.active, jflag::ACTIVE)
            | bit(s.enabled, jflag::AMP_ENABLED)
            | bit(s.inpos, jflag::IN_POSITION)
            | bit(s.error, jflag::ERROR)
            | bit(s.phl, jflag::POS_HARD_LIMIT)
            | bit(s.nhl, jflag::NEG_HARD_LIMIT)
            | bit(s.ferror_flag, jflag::FOLLOWING_ERROR)
            | bit(s.fault, jflag::FAULTED)
            | bit(s.homed, jflag::HOMED)
            | bit(core.joint_homing(j), jflag::HOMING)
            | bit(s.kb_jog_active, jflag::JOGGING)
            | ((core.home_state(j).number() as u64 & 0xff) << jflag::HOME_STATE_SHIFT);
        w[1] = s.pos_cmd.to_bits();
        w[2] = s.pos_fb.to_bits();
        w[3] = s.vel_cmd.to_bits();
        w[4] = s.ferror.to_bits();
        w[5] = s.ferror_limit.to_bits();
        w[6] = s.cfg.min_pos_limit.to_bits();
        w[7] = s.cfg.max_pos_limit.to_bits();
    }
    let (pose, _) = core.carte_pos_cmd();
    for (a, &p) in pose.0.iter().enumerate() {
        let s = core.axis_ref(a);
        let tp = &s.teleop_tp;
        let w = &mut out[AXES_START + a * AXIS_WORDS..][..AXIS_WORDS];
        w[0] = bit(core.axis_in_kinematics(a), aflag::IN_KINEMATICS)
            | bit(tp.enable, aflag::TP_ENABLE)
            | bit(s.kb_jog_active, aflag::KB_JOG)
            | bit(s.wheel_jog_active, aflag::WHEEL_JOG)
            | bit(tp.active, aflag::MOVING);
        w[1] = p.to_bits();
        w[2] = tp.curr_vel.to_bits();
        w[3] = s.cfg.min_pos_limit.to_bits();
        w[4] = s.cfg.max_pos_limit.to_bits();
    }
}

/// One world axis in a [`MotionStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisState {
    /// The kinematics compute this axis.
    pub in_kinematics: bool,
    /// Teleop planner enabled.
    pub tp_enable: bool,
    /// A keyboard (command) jog moves the axis.
    pub kb_jogging: bool,
    /// The jog wheel moves the axis.
    pub wheel_jogging: bool,
    /// The teleop planner moves.
    pub moving: bool,
    /// Commanded position (the world pose's coordinate).
    pub pos_cmd: f64,
    /// Teleop velocity.
    pub vel_cmd: f64,
    /// Position limits.
    pub min_limit: f64,
    pub max_limit: f64,
}

/// One joint in a [`MotionStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointState {
    pub active: bool,
    /// Amplifier enabled (`joint.N.amp-enable-out`).
    pub amp_enabled: bool,
    pub in_position: bool,
    pub error: bool,
    pub pos_hard_limit: bool,
    pub neg_hard_limit: bool,
    /// Following error tripped.
    pub following_error: bool,
    /// Amplifier fault.
    pub faulted: bool,
    pub homed: bool,
    pub homing: bool,
    /// A keyboard jog of this joint is active.
    pub jogging: bool,
    /// The homing state (`joint.N.home-state`).
    pub home_state: HomeState,
    /// Commanded position.
    pub pos_cmd: f64,
    /// Position feedback.
    pub pos_fb: f64,
    /// Commanded velocity.
    pub vel_cmd: f64,
    /// Following error and its current limit.
    pub ferror: f64,
    pub ferror_limit: f64,
    /// Soft limits.
    pub min_limit: f64,
    pub max_limit: f64,
}

/// A consistent copy of the controller's status.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MotionStatus {
    /// True when enabled (amplifiers on).
    pub enabled: bool,
    /// "DISABLED", "FREE", "TELEOP" or "COORD".
    pub mode: &'static str,
    /// The TELEOP flag: in teleop mode, or entering it on enable.
    pub teleop_mode: bool,
    /// The COORD flag: in coordinated mode, or entering it on enable.
    pub coord_mode: bool,
    pub in_position: bool,
    pub error: bool,
    pub on_soft_limit: bool,
    pub jog_active: bool,
    pub homing_active: bool,
    pub all_homed: bool,
    /// `motion.enable` as last read.
    pub enable_input: bool,
    /// Servo cycles run.
    pub heartbeat: u64,
    /// The last command answered through the channel.
    pub last: LastCommand,
    /// Commands answered through the channel.
    pub served: u64,
    /// The free-mode SCALE.
    pub scale: f64,
    /// Joints whose hard limits are overridden.
    pub override_mask: u64,
    pub joints: Vec<JointState>,
    /// The nine world axes, X Y Z A B C U V W.
    pub axes: Vec<AxisState>,
}

/// Decodes a snapshot, validating its header.
pub fn decode_status(w: &[u64]) -> Result<MotionStatus, WireError> {
    if w.len() < STATUS_WORDS {
        return Err(WireError::BadStatus);
    }
    if w[0] != STATUS_VERSION {
        return Err(WireError::BadVersion { found: w[0] });
    }
    let n = usize::try_from(w[1]).map_err(|_| WireError::BadStatus)?;
    if n > MAX_JOINTS {
        return Err(WireError::BadStatus);
    }
    let mode = match w[2] {
        0 => "DISABLED",
        1 => "FREE",
        2 => "TELEOP",
        3 => "COORD",
        _ => return Err(WireError::BadStatus),
    };
    let f = |i: usize| f64::from_bits(w[i]);
    let h = w[3];
    let joints = (0..n)
        .map(|j| {
            let b = STATUS_HEADER + j * JOINT_WORDS;
            let fl = w[b];
            let on = |m: u64| fl & m != 0;
            Ok(JointState {
                active: on(jflag::ACTIVE),
                amp_enabled: on(jflag::AMP_ENABLED),
                in_position: on(jflag::IN_POSITION),
                error: on(jflag::ERROR),
                pos_hard_limit: on(jflag::POS_HARD_LIMIT),
                neg_hard_limit: on(jflag::NEG_HARD_LIMIT),
                following_error: on(jflag::FOLLOWING_ERROR),
                faulted: on(jflag::FAULTED),
                homed: on(jflag::HOMED),
                homing: on(jflag::HOMING),
                jogging: on(jflag::JOGGING),
                home_state: HomeState::from_number(((fl >> jflag::HOME_STATE_SHIFT) & 0xff) as i32)
                    .ok_or(WireError::BadStatus)?,
                pos_cmd: f(b + 1),
                pos_fb: f(b + 2),
                vel_cmd: f(b + 3),
                ferror: f(b + 4),
                ferror_limit: f(b + 5),
                min_limit: f(b + 6),
                max_limit: f(b + 7),
            })
        })
        .collect::<Result<Vec<_>, WireError>>()?;
    let axes = (0..NUM_AXES)
        .map(|a| {
            let b = AXES_START + a * AXIS_WORDS;
            let on = |m: u64| w[b] & m != 0;
            AxisState {
                in_kinematics: on(aflag::IN_KINEMATICS),
                tp_enable: on(aflag::TP_ENABLE),
                kb_jogging: on(aflag::KB_JOG),
                wheel_jogging: on(aflag::WHEEL_JOG),
                moving: on(aflag::MOVING),
                pos_cmd: f(b + 1),
                vel_cmd: f(b + 2),
                min_limit: f(b + 3),
                max_limit: f(b + 4),
            }
        })
        .collect();
    Ok(MotionStatus {
        enabled: h & flag::ENABLED != 0,
        mode,
        teleop_mode: h & flag::TELEOP_MODE != 0,
        coord_mode: h & flag::COORD_MODE != 0,
        in_position: h & flag::IN_POSITION != 0,
        error: h & flag::ERROR != 0,
        on_soft_limit: h & flag::ON_SOFT_LIMIT != 0,
        jog_active: h & flag::JOG_ACTIVE != 0,
        homing_active: h & flag::HOMING_ACTIVE != 0,
        all_homed: h & flag::ALL_HOMED != 0,
        enable_input: h & flag::ENABLE_INPUT != 0,
        heartbeat: w[4],
        last: LastCommand {
            serial: w[5],
            code: w[6],
        },
        scale: f(7),
        override_mask: w[8],
        served: w[9],
        joints,
        axes,
    })
}

/// Short name of a result code, for status displays.
pub fn result_name(code: u64) -> &'static str {
    match code {
        0 => "accepted",
        1 => "rejected: no such joint",
        2 => "rejected: joint inactive",
        3 => "rejected: enable input false",
        4 => "rejected: not enabled",
        5 => "rejected: not in free mode",
        6 => "rejected: jog inhibited",
        7 => "rejected: homing active",
        8 => "rejected: wheel jog active",
        9 => "rejected: joint moving",
        10 => "rejected: on hard limit",
        11 => "rejected: past soft limit",
        12 => "rejected: target outside limits",
        13 => "rejected: bad velocity",
        14 => "rejected: bad value",
        15 => "rejected: limits reversed",
        16 => "rejected: timeout",
        17 => "rejected: unsupported",
        18 => "rejected: malformed",
        19 => "rejected: activate while enabled",
        20 => "rejected: homing inhibited",
        21 => "rejected: nothing to home",
        22 => "rejected: home sequence gap",
        23 => "rejected: already homed",
        24 => "rejected: shared home switch closed",
        25 => "rejected: bad homing configuration",
        26 => "rejected: synchronised joint",
        27 => "rejected: locking indexer",
        28 => "rejected: not free or disabled",
        29 => "rejected: extra joint enabled",
        30 => "rejected: not in position",
        31 => "rejected: not homed",
        32 => "rejected: not in teleop mode",
        33 => "rejected: joint jog in teleop mode",
        34 => "rejected: no such axis",
        35 => "rejected: axis not in kinematics",
        36 => "rejected: motion error",
        37 => "rejected: axis wheel jog active",
        38 => "rejected: axis past limit",
        39 => "rejected: axis target outside limits",
        40 => "rejected: kinematics failed",
        41 => "rejected: mode change would jump",
        _ => "unknown",
    }
}

impl fmt::Display for MotionStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let yn = |b: bool| if b { "yes" } else { "no" };
        writeln!(
            f,
            "mode {}  enabled {}  enable-input {}  in-position {}  error {}  scale {}",
            self.mode,
            yn(self.enabled),
            yn(self.enable_input),
            yn(self.in_position),
            yn(self.error),
            self.scale
        )?;
        writeln!(
            f,
            "jog-active {}  on-soft-limit {}  all-homed {}  override-mask {:#x}  heartbeat {}",
            yn(self.jog_active),
            yn(self.on_soft_limit),
            yn(self.all_homed),
            self.override_mask,
            self.heartbeat
        )?;
        if !self.enabled && (self.teleop_mode || self.coord_mode) {
            let m = if self.teleop_mode { "TELEOP" } else { "COORD" };
            writeln!(f, "mode on enable: {m}")?;
        }
        if self.last.serial == 0 {
            writeln!(f, "last command: none")?;
        } else {
            writeln!(
                f,
                "last command: serial {} {} (code {})",
                self.last.serial,
                result_name(self.last.code),
                self.last.code
            )?;
        }
        writeln!(
            f,
            "joint active amp homed {:>12} {:>12} {:>12} {:>10}  flags",
            "pos-cmd", "pos-fb", "vel-cmd", "ferror"
        )?;
        for (n, j) in self.joints.iter().enumerate() {
            let mut flags = String::new();
            for (on, name) in [
                (j.in_position, "inpos"),
                (j.jogging, "jogging"),
                (j.homing, "homing"),
                (j.error, "error"),
                (j.pos_hard_limit, "+hard-limit"),
                (j.neg_hard_limit, "-hard-limit"),
                (j.following_error, "ferror"),
                (j.faulted, "amp-fault"),
            ] {
                if on {
                    flags.push(' ');
                    flags.push_str(name);
                }
            }
            if j.home_state != HomeState::Idle {
                flags.push_str(" home-state=");
                flags.push_str(j.home_state.name());
            }
            writeln!(
                f,
                "{n:<5} {:<6} {:<3} {:<5} {:>12.6} {:>12.6} {:>12.6} {:>10.6} {}",
                yn(j.active),
                yn(j.amp_enabled),
                yn(j.homed),
                j.pos_cmd,
                j.pos_fb,
                j.vel_cmd,
                j.ferror,
                flags.trim_start()
            )?;
        }
        if self.axes.iter().any(|a| a.in_kinematics) {
            writeln!(
                f,
                "axis {:>12} {:>12} {:>12} {:>12}  flags",
                "pos-cmd", "vel-cmd", "min-limit", "max-limit"
            )?;
        }
        for (a, x) in self.axes.iter().enumerate() {
            if !x.in_kinematics {
                continue;
            }
            let mut flags = String::new();
            for (on, name) in [
                (x.moving, "moving"),
                (x.kb_jogging, "jogging"),
                (x.wheel_jogging, "wheel"),
            ] {
                if on {
                    flags.push(' ');
                    flags.push_str(name);
                }
            }
            writeln!(
                f,
                "{:<4} {:>12.6} {:>12.6} {:>12} {:>12} {}",
                AXIS_LETTERS[a].to_ascii_uppercase(),
                x.pos_cmd,
                x.vel_cmd,
                limit_text(x.min_limit),
                limit_text(x.max_limit),
                flags.trim_start()
            )?;
        }
        Ok(())
    }
}

/// A limit for the status table: huge values (the ±1e99 "no limit"
/// default) in exponent form, which `{}` would spell out in 100 digits.
fn limit_text(v: f64) -> String {
    if v.abs() >= 1e9 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A command the controller accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Accepted {
    /// Its serial number.
    pub serial: u64,
}

/// A command the controller refused (or that got no answer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rejected {
    /// Its serial number.
    pub serial: u64,
    /// Why.
    pub reason: Reject,
}

impl Rejected {
    /// The reason code on the wire.
    pub fn code(&self) -> u64 {
        reject_code(&self.reason)
    }
}

impl fmt::Display for Rejected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "rejected (serial {}, code {}): {}",
            self.serial,
            self.code(),
            self.reason
        )
    }
}

impl std::error::Error for Rejected {}

/// Errors reaching the channel at all.
#[derive(Debug)]
pub enum ClientError {
    /// The instance is not running, or has no `motmod` loaded.
    Hal(HalError),
    /// The status snapshot could not be read consistently or is corrupt.
    Status(WireError),
}

impl fmt::Display for ClientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClientError::Hal(HalError::NotFound { kind: "region", .. }) => {
                f.write_str("motmod is not loaded in this HAL instance")
            }
            ClientError::Hal(e) => write!(f, "{e}"),
            ClientError::Status(e) => write!(f, "status: {e}"),
        }
    }
}

impl std::error::Error for ClientError {}

impl From<HalError> for ClientError {
    fn from(e: HalError) -> Self {
        ClientError::Hal(e)
    }
}

/// A sender of commands and reader of status from any process attached to
/// the instance. One client at a time holds the sender lock while it sends
/// a command and waits for its answer.
pub struct MotionClient {
    cmd: RingWriter,
    reply: RingReader,
    status: SeqLockReader,
    lock: Region,
    timeout: Duration,
    _inst: Instance,
}

impl std::fmt::Debug for MotionClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MotionClient")
            .field("timeout", &self.timeout)
            .finish()
    }
}

/// A per-process counter so clients of one process hold distinct tokens.
static NEXT_TOKEN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl MotionClient {
    /// Attaches to the running HAL instance `instance` and its `motmod`.
    pub fn attach(instance: &str) -> Result<MotionClient, ClientError> {
        MotionClient::open(&Instance::attach(instance)?)
    }

    /// Opens the channel of the `motmod` of an instance already attached.
    pub fn open(inst: &Instance) -> Result<MotionClient, ClientError> {
        Ok(MotionClient {
            cmd: RingWriter::open(inst, CMD_RING)?,
            reply: RingReader::open(inst, REPLY_RING)?,
            status: SeqLockReader::open(inst, STATUS)?,
            lock: inst.region(LOCK)?,
            timeout: crate::motmod::COMMAND_TIMEOUT,
            _inst: inst.clone(),
        })
    }

    /// Sets how long [`send`](Self::send) waits for an answer.
    pub fn with_timeout(mut self, timeout: Duration) -> MotionClient {
        self.timeout = timeout;
        self
    }

    /// Takes the sender lock (word 0 of the lock region), breaking it if
    /// its holder's process is gone. False on timeout.
    fn lock(&self, token: u64, deadline: Instant) -> bool {
        let w = &self.lock.words()[0];
        loop {
            match w.compare_exchange(0, token, Acquire, Relaxed) {
                Ok(_) => return true,
                Err(holder) => {
                    let pid = holder >> 32;
                    let alive = std::path::Path::new(&format!("/proc/{pid}")).exists();
                    if !alive {
                        let _ = w.compare_exchange(holder, 0, AcqRel, Relaxed);
                        continue;
                    }
                }
            }
            if Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    fn unlock(&self, token: u64) {
        let _ = self.lock.words()[0].compare_exchange(token, 0, Release, Relaxed);
    }

    /// Sends `cmd` and waits for its answer. [`Reject::Timeout`] if the
    /// controller did not answer in time (its thread is not running, or
    /// another sender held the channel).
    pub fn send(&mut self, cmd: Command) -> Result<Accepted, Rejected> {
        let deadline = Instant::now() + self.timeout;
        let token = (u64::from(std::process::id()) << 32)
            | (NEXT_TOKEN.fetch_add(1, Relaxed) & 0xffff_ffff).max(1);
        if !self.lock(token, deadline) {
            return Err(Rejected {
                serial: 0,
                reason: Reject::Timeout,
            });
        }
        let r = self.send_locked(cmd, deadline);
        self.unlock(token);
        r
    }

    fn send_locked(&mut self, cmd: Command, deadline: Instant) -> Result<Accepted, Rejected> {
        // Drop answers left by a sender that gave up waiting.
        let mut buf = [0u64; REPLY_WORDS];
        while self.reply.pop(&mut buf) {}
        let serial = {
            let s = self.lock.words()[1].fetch_add(1, AcqRel).wrapping_add(1);
            if s == 0 {
                self.lock.words()[1].fetch_add(1, AcqRel).wrapping_add(1)
            } else {
                s
            }
        };
        let timeout = Rejected {
            serial,
            reason: Reject::Timeout,
        };
        let rec = encode_command(serial, &cmd);
        while !self.cmd.push(&rec) {
            if Instant::now() > deadline {
                return Err(timeout);
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        loop {
            while self.reply.pop(&mut buf) {
                match decode_reply(&buf) {
                    Ok((s, r)) if s == serial => {
                        return match r {
                            Ok(()) => Ok(Accepted { serial }),
                            Err(reason) => Err(Rejected { serial, reason }),
                        }
                    }
                    // Someone else's or corrupt: not ours.
                    _ => {}
                }
            }
            if Instant::now() > deadline {
                return Err(timeout);
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    /// A consistent snapshot of the controller's status.
    pub fn status(&self) -> Result<MotionStatus, ClientError> {
        let mut w = [0u64; STATUS_WORDS];
        if !self.status.read(&mut w) {
            return Err(ClientError::Status(WireError::BadStatus));
        }
        decode_status(&w).map_err(ClientError::Status)
    }
}

#[cfg(test)]
mod tests;
