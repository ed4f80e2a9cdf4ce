//! Command and answer records: a [`Command`] as [`CMD_WORDS`] words and
//! back, an answer as [`REPLY_WORDS`] words and back, each validated word
//! by word.

use super::{checksum, ARGS, CMD_VERSION, CMD_WORDS, MAX_ARGS, REPLY_VERSION, REPLY_WORDS};
use crate::command::{codes, Command, LineKind, ProbeType, Reject, TermCond, WireError};
use crate::homing::{HomeFlags, HomingConfig};
use crate::kins::{Pose, NUM_AXES};

/// (opcode, takes a joint, number of float arguments) of a command, and
/// its joint and arguments.
pub(super) fn shape(cmd: &Command) -> (u64, Option<i32>, [f64; MAX_ARGS], usize) {
    let mut a = [0.0; MAX_ARGS];
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
        Command::Line { end, vel, kind, id } => {
            let n = put_pose(&mut a, &end, &[vel, kind.code() as f64]);
            (36, Some(id), a, n)
        }
        Command::Circle {
            end,
            center,
            normal,
            turns,
            vel,
            id,
        } => {
            let extra = [
                center[0],
                center[1],
                center[2],
                normal[0],
                normal[1],
                normal[2],
                f64::from(turns),
                vel,
            ];
            let n = put_pose(&mut a, &end, &extra);
            (37, Some(id), a, n)
        }
        Command::Dwell { seconds, id } => {
            let n = put(&[seconds]);
            (38, Some(id), a, n)
        }
        Command::Probe {
            end,
            vel,
            probe,
            id,
        } => {
            let n = put_pose(&mut a, &end, &[vel, probe.bits() as f64]);
            (39, Some(id), a, n)
        }
        Command::ClearProbeFlags => (40, None, a, 0),
        Command::SetTermCond { cond, tolerance } => {
            let n = put(&[cond.code() as f64, tolerance]);
            (41, None, a, n)
        }
        Command::Pause => (42, None, a, 0),
        Command::Resume => (43, None, a, 0),
        Command::Step => (44, None, a, 0),
        Command::FeedScale { scale } => {
            let n = put(&[scale]);
            (45, None, a, n)
        }
        Command::RapidScale { scale } => {
            let n = put(&[scale]);
            (46, None, a, n)
        }
        Command::SetMaxFeedOverride { scale } => {
            let n = put(&[scale]);
            (47, None, a, n)
        }
        Command::FeedScaleEnable { on } => {
            let n = put(&[f64::from(u8::from(on))]);
            (48, None, a, n)
        }
        Command::FeedHoldEnable { on } => {
            let n = put(&[f64::from(u8::from(on))]);
            (49, None, a, n)
        }
        Command::AdaptiveFeedEnable { on } => {
            let n = put(&[f64::from(u8::from(on))]);
            (50, None, a, n)
        }
        Command::SpindleScaleEnable { on } => {
            let n = put(&[f64::from(u8::from(on))]);
            (51, None, a, n)
        }
        Command::SetVelLimit { vel } => {
            let n = put(&[vel]);
            (52, None, a, n)
        }
        Command::SetAccLimit { acc } => {
            let n = put(&[acc]);
            (53, None, a, n)
        }
        Command::SetJerkLimit { jerk } => {
            let n = put(&[jerk]);
            (54, None, a, n)
        }
        Command::SetPlannerType { planner } => {
            let n = put(&[f64::from(planner)]);
            (55, None, a, n)
        }
        Command::SetJointJerkLimit { joint, jerk } => {
            let n = put(&[jerk]);
            (56, Some(joint), a, n)
        }
        Command::SetAxisJerkLimit { axis, jerk } => {
            let n = put(&[jerk]);
            (57, Some(axis), a, n)
        }
        Command::SetJointComp {
            joint,
            nominal,
            forward,
            reverse,
        } => {
            let n = put(&[nominal, forward, reverse]);
            (58, Some(joint), a, n)
        }
        Command::ClearJointComp { joint } => (59, Some(joint), a, 0),
    }
}

/// Puts a pose and then `extra` into the argument words; returns how many.
fn put_pose(a: &mut [f64; MAX_ARGS], p: &Pose, extra: &[f64]) -> usize {
    a[..NUM_AXES].copy_from_slice(&p.0);
    a[NUM_AXES..NUM_AXES + extra.len()].copy_from_slice(extra);
    NUM_AXES + extra.len()
}

/// The pose in argument words `from..from + 9`.
fn pose(a: &[f64; MAX_ARGS], from: usize) -> Pose {
    let mut p = Pose::ZERO;
    p.0.copy_from_slice(&a[from..from + NUM_AXES]);
    p
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
        36 => &[(10, 0.0, 1.0)],
        37 => &[(15, I32_MIN, I32_MAX)],
        39 => &[(10, 0.0, 3.0)],
        41 => &[(0, 0.0, 2.0)],
        48..=51 => &[(0, 0.0, 1.0)],
        55 => &[(0, I32_MIN, I32_MAX)],
        _ => &[],
    }
}

/// Builds the command of `opcode` from its joint and float arguments; also
/// says whether it takes a joint and how many floats.
fn build(opcode: u64, j: i32, a: &[f64; MAX_ARGS]) -> Option<(Command, bool, usize)> {
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
        24 => c(Command::SetWorldHome { pose: pose(a, 0) }, false, NUM_AXES),
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
        // The integer arguments were checked by `decode_command`.
        36 => c(
            Command::Line {
                end: pose(a, 0),
                vel: a[9],
                kind: LineKind::from_code(a[10] as u64)?,
                id: j,
            },
            true,
            11,
        ),
        37 => c(
            Command::Circle {
                end: pose(a, 0),
                center: [a[9], a[10], a[11]],
                normal: [a[12], a[13], a[14]],
                turns: a[15] as i32,
                vel: a[16],
                id: j,
            },
            true,
            17,
        ),
        38 => c(
            Command::Dwell {
                seconds: a[0],
                id: j,
            },
            true,
            1,
        ),
        39 => c(
            Command::Probe {
                end: pose(a, 0),
                vel: a[9],
                probe: ProbeType::from_bits(a[10] as u64)?,
                id: j,
            },
            true,
            11,
        ),
        40 => c(Command::ClearProbeFlags, false, 0),
        41 => c(
            Command::SetTermCond {
                cond: TermCond::from_code(a[0] as u64)?,
                tolerance: a[1],
            },
            false,
            2,
        ),
        42 => c(Command::Pause, false, 0),
        43 => c(Command::Resume, false, 0),
        44 => c(Command::Step, false, 0),
        45 => c(Command::FeedScale { scale: a[0] }, false, 1),
        46 => c(Command::RapidScale { scale: a[0] }, false, 1),
        47 => c(Command::SetMaxFeedOverride { scale: a[0] }, false, 1),
        48 => c(Command::FeedScaleEnable { on: a[0] != 0.0 }, false, 1),
        49 => c(Command::FeedHoldEnable { on: a[0] != 0.0 }, false, 1),
        50 => c(Command::AdaptiveFeedEnable { on: a[0] != 0.0 }, false, 1),
        51 => c(Command::SpindleScaleEnable { on: a[0] != 0.0 }, false, 1),
        52 => c(Command::SetVelLimit { vel: a[0] }, false, 1),
        53 => c(Command::SetAccLimit { acc: a[0] }, false, 1),
        54 => c(Command::SetJerkLimit { jerk: a[0] }, false, 1),
        55 => c(
            Command::SetPlannerType {
                planner: a[0] as i32,
            },
            false,
            1,
        ),
        56 => c(
            Command::SetJointJerkLimit {
                joint: j,
                jerk: a[0],
            },
            true,
            1,
        ),
        57 => c(
            Command::SetAxisJerkLimit {
                axis: j,
                jerk: a[0],
            },
            true,
            1,
        ),
        58 => c(
            Command::SetJointComp {
                joint: j,
                nominal: a[0],
                forward: a[1],
                reverse: a[2],
            },
            true,
            3,
        ),
        59 => c(Command::ClearJointComp { joint: j }, true, 0),
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
    let mut a = [0.0; MAX_ARGS];
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

/// The answer record for the command `serial`.
pub fn encode_reply(serial: u64, result: &Result<(), Reject>) -> [u64; REPLY_WORDS] {
    let mut w = [0u64; REPLY_WORDS];
    w[0] = REPLY_VERSION;
    w[1] = serial;
    if let Err(r) = result {
        let (code, n, f) = codes::encode_reject(r);
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
    let r =
        codes::decode_reject(w[2], [w[3], w[4]], f).ok_or(WireError::UnknownCode { code: w[2] })?;
    Ok((w[1], Err(r)))
}
