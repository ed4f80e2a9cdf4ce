//! The wire codes of rejections: each [`Reject`] as a reason code with two
//! integer and three float details, and back. Code 0 means accepted.

use super::{Direction, Feature, Quantity, Reject, WireError};
use crate::homing::ConfigProblem;

/// A rejection as it travels: reason code, integer details, float
/// details.
pub type RejectWire = (u64, [u64; 2], [f64; 3]);

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
pub fn encode_reject(r: &Reject) -> RejectWire {
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
        Reject::NotCoordMode => (42, [0; 2], [0.0; 3]),
        Reject::QueueFull { capacity } => (43, [capacity as u64, 0], [0.0; 3]),
        Reject::Aborting => (44, [0; 2], [0.0; 3]),
        Reject::OutsideAxisLimits {
            axis,
            value,
            min,
            max,
        } => (45, [axis as u64, 0], [value, min, max]),
        Reject::OutsideJointLimits {
            joint,
            value,
            min,
            max,
        } => (46, [joint as u64, 0], [value, min, max]),
        Reject::EndUnreachable => (47, [0; 2], [0.0; 3]),
        Reject::HardLimitTripped { joint } => (48, [joint as u64, 0], [0.0; 3]),
        Reject::BadArc => (49, [0; 2], [0.0; 3]),
        Reject::NotPaused => (50, [0; 2], [0.0; 3]),
        Reject::StillMoving => (51, [0; 2], [0.0; 3]),
        Reject::ProbeAlreadyThere { trip_on_clear } => {
            (52, [u64::from(trip_on_clear), 0], [0.0; 3])
        }
        Reject::NeedsJerkLimit { jerk } => (53, [0; 2], [jerk, 0.0, 0.0]),
        Reject::CompNotIncreasing {
            joint,
            nominal,
            previous,
        } => (54, [joint as u64, 0], [nominal, previous, 0.0]),
        Reject::CompTableFull { joint } => (55, [joint as u64, 0], [0.0; 3]),
        Reject::MustBeDisabled => (56, [0; 2], [0.0; 3]),
    }
}

/// The rejection of a reason code and its details; `None` if the code
/// or a detail is not one a rejection has.
pub fn decode_reject(code: u64, n: [u64; 2], f: [f64; 3]) -> Option<Reject> {
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
        42 => Reject::NotCoordMode,
        43 => Reject::QueueFull { capacity: joint()? },
        44 => Reject::Aborting,
        45 => Reject::OutsideAxisLimits {
            axis: joint()?,
            value: f[0],
            min: f[1],
            max: f[2],
        },
        46 => Reject::OutsideJointLimits {
            joint: joint()?,
            value: f[0],
            min: f[1],
            max: f[2],
        },
        47 => Reject::EndUnreachable,
        48 => Reject::HardLimitTripped { joint: joint()? },
        49 => Reject::BadArc,
        50 => Reject::NotPaused,
        51 => Reject::StillMoving,
        52 => Reject::ProbeAlreadyThere {
            trip_on_clear: match n[0] {
                0 => false,
                1 => true,
                _ => return None,
            },
        },
        53 => Reject::NeedsJerkLimit { jerk: f[0] },
        54 => Reject::CompNotIncreasing {
            joint: joint()?,
            nominal: f[0],
            previous: f[1],
        },
        55 => Reject::CompTableFull { joint: joint()? },
        56 => Reject::MustBeDisabled,
        _ => return None,
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
        42 => "rejected: not in coordinated mode",
        43 => "rejected: queue full",
        44 => "rejected: aborting",
        45 => "rejected: outside axis limits",
        46 => "rejected: outside joint limits",
        47 => "rejected: end unreachable",
        48 => "rejected: hard limit tripped",
        49 => "rejected: bad arc",
        50 => "rejected: not paused",
        51 => "rejected: still moving",
        52 => "rejected: probe already there",
        53 => "rejected: needs a jerk limit",
        54 => "rejected: compensation not increasing",
        55 => "rejected: compensation table full",
        56 => "rejected: must be disabled",
        _ => "unknown",
    }
}
