//! Wire-format tests: round trips and rejection of every corrupt word.

use super::snapshot::{aflag, flag, jflag};
use super::*;
use crate::command::{
    Command, Direction, Feature, LineKind, ProbeType, Quantity, Reject, TermCond,
};
use crate::homing::{ConfigProblem, HomeFlags, HomeState, HomingConfig};
use crate::kins::Pose;

/// One or more of every command, with values at the edges.
pub(crate) fn all_commands() -> Vec<Command> {
    // Long: one entry per command (opcodes 1 to 77), several at the edges.
    let mut pose = Pose::ZERO;
    for (i, v) in pose.0.iter_mut().enumerate() {
        *v = i as f64 * 1.5 - 3.0;
    }
    vec![
        Command::Abort,
        Command::Enable,
        Command::Disable,
        Command::Free,
        Command::Teleop,
        Command::Coord,
        Command::JogCont {
            joint: 2,
            vel: -3.5,
        },
        Command::JogIncr {
            joint: 1,
            vel: 10.0,
            offset: 0.25,
        },
        Command::JogAbs {
            joint: 0,
            vel: 4.0,
            pos: -7.125,
        },
        Command::JogAbort { joint: -1 },
        Command::JointActivate { joint: 15 },
        Command::JointDeactivate { joint: 3 },
        Command::OverrideLimits { joint: -1 },
        Command::Scale { scale: 0.5 },
        Command::EnableAmplifier { joint: 0 },
        Command::DisableAmplifier { joint: 1 },
        Command::SetJointPositionLimits {
            joint: 0,
            min: -10.0,
            max: 10.0,
        },
        Command::SetJointVelLimit {
            joint: 1,
            vel: 20.0,
        },
        Command::SetJointAccLimit {
            joint: 2,
            acc: 500.0,
        },
        Command::SetJointMinFerror {
            joint: 0,
            ferror: 0.01,
        },
        Command::SetJointMaxFerror {
            joint: 0,
            ferror: 0.1,
        },
        Command::SetJointBacklash {
            joint: 0,
            backlash: 0.002,
        },
        Command::SetJointMotorOffset {
            joint: 4,
            offset: -1e-3,
        },
        Command::SetWorldHome { pose },
        Command::JogCont {
            joint: i32::MIN,
            vel: f64::INFINITY,
        },
        Command::Home { joint: -1 },
        Command::Unhome { joint: -2 },
        Command::SetJointHomingParams {
            joint: 2,
            config: HomingConfig {
                offset: 1.5,
                home: -2.25,
                final_vel: 3.0,
                search_vel: -4.0,
                latch_vel: 0.5,
                flags: HomeFlags::USE_INDEX | HomeFlags::IGNORE_LIMITS,
                sequence: -3,
                volatile_home: true,
            },
        },
        Command::SetJointHomingParams {
            joint: 0,
            config: HomingConfig {
                flags: HomeFlags::all(),
                sequence: i32::MIN,
                ..HomingConfig::default()
            },
        },
        Command::UpdateJointHomingParams {
            joint: 1,
            offset: 0.1,
            home: 0.2,
            sequence: i32::MAX,
        },
        Command::AxisJogCont { axis: 2, vel: -1.5 },
        Command::AxisJogIncr {
            axis: 0,
            vel: 3.0,
            offset: 0.125,
        },
        Command::AxisJogAbs {
            axis: 8,
            vel: -2.0,
            pos: 12.5,
        },
        Command::AxisJogAbort { axis: -1 },
        Command::SetAxisPositionLimits {
            axis: 1,
            min: -1e99,
            max: 1e99,
        },
        Command::SetAxisVelLimit { axis: 3, vel: 7.5 },
        Command::SetAxisAccLimit {
            axis: i32::MAX,
            acc: 250.0,
        },
        Command::Line {
            end: pose,
            vel: 12.5,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Feed,
            id: 42,
        },
        Command::Line {
            end: pose,
            vel: 0.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Traverse,
            id: -1,
        },
        Command::Circle {
            end: pose,
            center: [1.0, -2.0, 0.5],
            normal: [0.0, 0.0, 1.0],
            turns: -3,
            vel: 4.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            id: i32::MAX,
        },
        Command::Dwell {
            seconds: 0.75,
            id: 7,
        },
        Command::Probe {
            end: pose,
            vel: 1.5,
            probe: ProbeType::G38_5,
            id: 8,
        },
        Command::ClearProbeFlags,
        Command::SetTermCond {
            cond: TermCond::Blend,
            tolerance: 0.01,
        },
        Command::Pause,
        Command::Resume,
        Command::Step,
        Command::FeedScale { scale: 1.25 },
        Command::RapidScale { scale: 0.5 },
        Command::SetMaxFeedOverride { scale: 2.0 },
        Command::FeedScaleEnable { on: true },
        Command::FeedHoldEnable { on: false },
        Command::AdaptiveFeedEnable { on: true },
        Command::SpindleScaleEnable { on: false },
        Command::SetVelLimit { vel: 100.0 },
        Command::SetAccLimit { acc: 1000.0 },
        Command::SetJerkLimit { jerk: 1e5 },
        Command::SetPlannerType { planner: 1 },
        Command::SetJointJerkLimit {
            joint: 2,
            jerk: 5e4,
        },
        Command::SetAxisJerkLimit { axis: 1, jerk: 0.0 },
        Command::SetAxisEoffsetRatio {
            axis: 2,
            ratio: 0.25,
        },
        Command::SetAxisLockingIndexer { axis: 4, joint: 4 },
        Command::SetJointComp {
            joint: 0,
            nominal: -1.0,
            forward: 0.005,
            reverse: -0.005,
        },
        Command::ClearJointComp { joint: 1 },
        Command::SpindleOn {
            spindle: 0,
            speed: -1200.5,
            wait: true,
        },
        Command::SpindleOn {
            spindle: -1,
            speed: 300.0,
            wait: false,
        },
        Command::SpindleOff { spindle: 2 },
        Command::SpindleScale {
            spindle: 0,
            scale: 1.25,
        },
        Command::SpindleBrake {
            spindle: 0,
            on: true,
        },
        Command::SpindleOrient {
            spindle: 0,
            angle: 92.5,
            mode: 2,
        },
        Command::SetFeedPerRev {
            spindle: 1,
            per_rev: 0.25,
        },
        Command::SpindleSync {
            spindle: 0,
            per_rev: 1.5,
            velocity_mode: false,
        },
        Command::SpindleSync {
            spindle: 1,
            per_rev: 0.0,
            velocity_mode: true,
        },
        Command::RigidTap {
            end: Pose([1.0, 2.0, -3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            vel: 2.5,
            scale: 1.5,
            id: 12,
        },
        Command::SpindleCss {
            spindle: 0,
            factor: 31830.98,
            x_offset: -2.5,
        },
        Command::SetDout {
            index: 63,
            on: true,
            now: false,
        },
        Command::SetAout {
            index: 2,
            value: -4.25,
            now: true,
        },
        Command::SetNumJoints { joints: 9 },
        Command::SetNumSpindles { spindles: 2 },
        Command::SetVel {
            vel: 0.0,
            ini_maxvel: 1.2,
        },
        Command::SetupArcBlends {
            enable: true,
            fallback: false,
            depth: 50,
            gap_cycles: 4,
            ramp_freq: 100.0,
        },
        Command::SetSpindleParams {
            spindle: -1,
            max_pos: 1e99,
            min_pos: 100.0,
            max_neg: -3000.0,
            min_neg: -0.5,
        },
        Command::SetToolOffset { offset: pose },
        Command::SetProbeErrInhibit {
            jog: true,
            home: false,
        },
    ]
}

#[test]
fn every_command_round_trips() {
    for (i, c) in all_commands().into_iter().enumerate() {
        let serial = 1000 + i as u64;
        let w = encode_command(serial, &c);
        assert_eq!(decode_command(&w), Ok((serial, c)), "{c:?}");
    }
}

#[test]
fn every_opcode_from_1_to_the_last_is_used() {
    let mut ops: Vec<u64> = all_commands().iter().map(Command::opcode).collect();
    ops.sort();
    ops.dedup();
    assert_eq!(ops, (1..=79).collect::<Vec<_>>());
}

#[test]
fn axis_commands_carry_the_axis_in_the_joint_word() {
    let w = encode_command(
        3,
        &Command::AxisJogIncr {
            axis: 4,
            vel: -1.0,
            offset: 0.5,
        },
    );
    assert_eq!((w[2], w[3]), (30, 4));
    assert_eq!(w[4], (-1.0f64).to_bits());
    assert_eq!(w[5], 0.5f64.to_bits());
    assert!(w[6..CMD_WORDS - 1].iter().all(|&x| x == 0));
    let w = encode_command(3, &Command::AxisJogAbort { axis: -2 });
    assert_eq!((w[2], w[3]), (32, (-2i64) as u64));
    // An axis word that is no i32 is refused like a joint word.
    let mut w = encode_command(3, &Command::AxisJogAbort { axis: 1 });
    w[3] = 1 << 35;
    assert_eq!(
        decode_command(&seal(w)),
        Err((3, WireError::BadJoint { value: 1 << 35 }))
    );
    // A float the command does not take.
    let mut w = encode_command(3, &Command::AxisJogCont { axis: 1, vel: 1.0 });
    w[5] = 1;
    assert_eq!(
        decode_command(&seal(w)),
        Err((3, WireError::UnusedWordSet { index: 5 }))
    );
}

#[test]
fn a_bit_flip_in_any_word_is_rejected() {
    for c in all_commands() {
        let good = encode_command(7, &c);
        for word in 0..CMD_WORDS {
            for bit in [0, 1, 31, 52, 63] {
                let mut w = good;
                w[word] ^= 1 << bit;
                let e = decode_command(&w).expect_err("corrupt record accepted");
                if word == 0 {
                    assert!(matches!(e.1, WireError::BadVersion { .. }), "{e:?}");
                } else {
                    assert_eq!(e.1, WireError::BadChecksum, "word {word} bit {bit}");
                }
            }
        }
    }
}

/// Recomputes the checksum, as a buggy but well-meaning sender would.
fn seal(mut w: [u64; CMD_WORDS]) -> [u64; CMD_WORDS] {
    w[CMD_WORDS - 1] = checksum(&w[..CMD_WORDS - 1]);
    w
}

#[test]
fn well_sealed_but_invalid_records_are_rejected_with_the_reason() {
    let good = encode_command(9, &Command::JogCont { joint: 1, vel: 2.0 });
    let mut w = good;
    w[1] = 0;
    assert_eq!(decode_command(&seal(w)), Err((0, WireError::ZeroSerial)));
    for op in [0u64, 900, 1000, u64::MAX] {
        let mut w = good;
        w[2] = op;
        assert_eq!(
            decode_command(&seal(w)),
            Err((9, WireError::UnknownOpcode { opcode: op }))
        );
    }
    let mut w = good;
    w[3] = 1 << 40;
    assert_eq!(
        decode_command(&seal(w)),
        Err((9, WireError::BadJoint { value: 1 << 40 }))
    );
    let mut w = encode_command(9, &Command::Enable);
    w[3] = 1;
    assert_eq!(
        decode_command(&seal(w)),
        Err((9, WireError::BadJoint { value: 1 }))
    );
    for index in 5..CMD_WORDS - 1 {
        let mut w = good;
        w[index] = 1;
        assert_eq!(
            decode_command(&seal(w)),
            Err((9, WireError::UnusedWordSet { index }))
        );
    }
    // Words carrying whole numbers must hold them.
    let homing = encode_command(
        9,
        &Command::SetJointHomingParams {
            joint: 0,
            config: HomingConfig::default(),
        },
    );
    for (index, v) in [
        (9, 0.5),
        (9, -1.0),
        (9, 4294967296.0),
        (10, 2147483648.0),
        (10, f64::NAN),
        (11, 2.0),
        (11, 0.25),
    ] {
        let mut w = homing;
        w[index] = f64::to_bits(v);
        assert_eq!(
            decode_command(&seal(w)),
            Err((9, WireError::BadInteger { index })),
            "{v}"
        );
    }
    // Random words never panic.
    let mut x: u64 = 0x1234_5678_9abc_def1;
    for _ in 0..10_000 {
        let mut w = [0u64; CMD_WORDS];
        for v in w.iter_mut() {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            *v = x;
        }
        w[0] = CMD_VERSION;
        assert!(decode_command(&w).is_err());
        let _ = decode_command(&seal(w));
        let mut r = [0u64; REPLY_WORDS];
        r.copy_from_slice(&w[..REPLY_WORDS]);
        r[0] = REPLY_VERSION;
        r[REPLY_WORDS - 1] = checksum(&r[..REPLY_WORDS - 1]);
        let _ = decode_reply(&r);
    }
}

fn all_rejects() -> Vec<Reject> {
    // Long: one entry per refusal (codes 1 to 56), several at the edges.
    let mut v = vec![
        Reject::NoSuchJoint {
            joint: -3,
            num_joints: 3,
        },
        Reject::JointInactive { joint: 2 },
        Reject::EnableInputFalse,
        Reject::NotEnabled,
        Reject::NotFreeMode,
        Reject::JogInhibited,
        Reject::HomingActive,
        Reject::WheelJogActive { joint: 1 },
        Reject::JointMoving { joint: 0 },
        Reject::OnHardLimit {
            joint: 1,
            dir: Direction::Negative,
        },
        Reject::PastSoftLimit {
            joint: 2,
            dir: Direction::Positive,
        },
        Reject::TargetOutsideLimits {
            joint: 0,
            target: 11.0,
            min: -10.0,
            max: 10.0,
        },
        Reject::BadVelocity { vel: 0.0 },
        Reject::LimitsReversed { min: 1.0, max: 0.0 },
        Reject::Timeout,
        Reject::ActivateWhileEnabled { joint: 1 },
        Reject::HomingInhibited,
        Reject::NothingToHome,
        Reject::HomeSequenceGap { missing: 2 },
        Reject::AlreadyHomed { joint: 1 },
        Reject::SharedHomeSwitchClosed { joint: 2 },
        Reject::SynchronizedJoint { joint: 0 },
        Reject::LockingIndexer { joint: 3 },
        Reject::NotFreeOrDisabled,
        Reject::ExtraJointEnabled { joint: 4 },
        Reject::NotInPosition,
        Reject::NotHomed,
        Reject::NotTeleopMode,
        Reject::JointJogInTeleop,
        Reject::NoSuchAxis { axis: -7 },
        Reject::NoSuchAxis { axis: i32::MAX },
        Reject::AxisNotInKinematics { axis: 5 },
        Reject::MotionError,
        Reject::AxisWheelJogActive { axis: 8 },
        Reject::AxisPastLimit {
            axis: 0,
            dir: Direction::Negative,
        },
        Reject::AxisPastLimit {
            axis: 1,
            dir: Direction::Positive,
        },
        Reject::AxisTargetOutsideLimits {
            axis: 2,
            target: -51.0,
            min: -50.0,
            max: 50.0,
        },
        Reject::KinematicsFailed,
        Reject::ModeChangeJump {
            joint: 3,
            jump: 0.25,
        },
        Reject::NotCoordMode,
        Reject::QueueFull { capacity: 2000 },
        Reject::Aborting,
        Reject::OutsideAxisLimits {
            axis: 8,
            value: 3.5,
            min: -1.0,
            max: 3.0,
        },
        Reject::OutsideJointLimits {
            joint: 15,
            value: -7.0,
            min: -6.0,
            max: 6.0,
        },
        Reject::EndUnreachable,
        Reject::HardLimitTripped { joint: 2 },
        Reject::BadArc,
        Reject::NotPaused,
        Reject::StillMoving,
        Reject::ProbeAlreadyThere {
            trip_on_clear: false,
        },
        Reject::ProbeAlreadyThere {
            trip_on_clear: true,
        },
        Reject::NeedsJerkLimit { jerk: 0.5 },
        Reject::CompNotIncreasing {
            joint: 1,
            nominal: 2.0,
            previous: 2.0,
        },
        Reject::CompTableFull { joint: 3 },
        Reject::MustBeDisabled,
        Reject::NoSuchSpindle {
            spindle: 3,
            num_spindles: 1,
        },
        Reject::NoSuchOutput { index: 9, count: 4 },
        Reject::NoUnlockPins { joint: 7 },
        Reject::IndexerNeedsRapid { axis: 4 },
        Reject::IndexerNotAlone { axis: 3 },
        Reject::IndexerJog { axis: 5, joint: 7 },
        Reject::RigidTapNotSynchronised,
        Reject::BadJointCount {
            count: 12,
            loaded: 3,
        },
        Reject::BadSpindleCount {
            count: 0,
            loaded: 1,
        },
        Reject::SpindleRangeReversed {
            low: 500.0,
            high: 100.0,
        },
    ];
    for code in 1..=9 {
        v.push(Reject::BadHomingConfig {
            joint: 1,
            problem: ConfigProblem::from_code(code).unwrap(),
        });
    }
    for what in Quantity::ALL {
        v.push(Reject::BadValue { what, value: -1.0 });
    }
    for what in Feature::ALL {
        v.push(Reject::Unsupported { what });
    }
    for error in [
        WireError::BadVersion { found: 3 },
        WireError::BadChecksum,
        WireError::ZeroSerial,
        WireError::UnknownOpcode { opcode: 99 },
        WireError::BadJoint { value: 1 << 40 },
        WireError::UnusedWordSet { index: 7 },
        WireError::UnknownCode { code: 77 },
        WireError::BadStatus,
        WireError::BadInteger { index: 10 },
    ] {
        v.push(Reject::Malformed { error });
    }
    v
}

#[test]
fn every_answer_round_trips_and_corruption_is_detected() {
    let ok = encode_reply(5, &Ok(()));
    assert_eq!(decode_reply(&ok), Ok((5, Ok(()))));
    for r in all_rejects() {
        let w = encode_reply(6, &Err(r));
        assert_eq!(decode_reply(&w), Ok((6, Err(r))), "{r:?}");
        assert_ne!(reject_code(&r), 0);
        assert_ne!(result_name(reject_code(&r)), "unknown");
        for word in 0..REPLY_WORDS {
            let mut c = w;
            c[word] ^= 1 << 17;
            assert!(decode_reply(&c).is_err(), "{r:?} word {word}");
        }
    }
    let mut w = encode_reply(6, &Ok(()));
    w[2] = 99;
    w[REPLY_WORDS - 1] = checksum(&w[..REPLY_WORDS - 1]);
    assert_eq!(decode_reply(&w), Err(WireError::UnknownCode { code: 99 }));
}

#[test]
fn status_snapshot_decodes_and_validates_its_header() {
    let mut w = [0u64; STATUS_WORDS];
    w[0] = STATUS_VERSION;
    w[1] = 2;
    w[2] = 1;
    w[3] = flag::ENABLED | flag::IN_POSITION;
    w[5] = 42;
    w[7] = 0.5f64.to_bits();
    w[STATUS_HEADER] = jflag::ACTIVE | jflag::AMP_ENABLED | (7 << jflag::HOME_STATE_SHIFT);
    w[STATUS_HEADER + 1] = 1.25f64.to_bits();
    let s = decode_status(&w).unwrap();
    assert!(s.enabled && s.in_position && !s.error);
    assert_eq!((s.mode, s.last.serial, s.scale), ("FREE", 42, 0.5));
    assert_eq!(s.joints.len(), 2);
    assert!(s.joints[0].active && s.joints[0].amp_enabled && !s.joints[1].active);
    assert_eq!(s.joints[0].pos_cmd, 1.25);
    assert_eq!(s.joints[0].home_state, HomeState::InitialSearchWait);
    assert_eq!(s.joints[1].home_state, HomeState::Idle);
    let text = s.to_string();
    assert!(text.contains("home-state=INITIAL_SEARCH_WAIT"), "{text}");
    assert!(text.contains("mode FREE  enabled yes"), "{text}");
    assert!(text.contains("last command: serial 42 accepted"), "{text}");
    // An older controller's snapshot has no path block: not reported.
    assert_eq!((s.traj.enables, s.traj.kinematics_type), (None, None));
    let mut path = w;
    path[PATH_START] = 1 | 0x0b << 8 | 4 << 16;
    path[PATH_START + 3] = (-2.5f64).to_bits();
    let s = decode_status(&path).unwrap();
    assert_eq!(
        (s.traj.enables, s.traj.kinematics_type),
        (Some(0x0b), Some(4))
    );
    assert_eq!(s.traj.dtg[2], -2.5);

    let mut bad = w;
    bad[0] ^= 1;
    assert!(matches!(
        decode_status(&bad),
        Err(WireError::BadVersion { .. })
    ));
    let mut bad = w;
    bad[1] = MAX_JOINTS as u64 + 1;
    assert_eq!(decode_status(&bad), Err(WireError::BadStatus));
    let mut bad = w;
    bad[2] = 7;
    assert_eq!(decode_status(&bad), Err(WireError::BadStatus));
    assert_eq!(decode_status(&w[..10]), Err(WireError::BadStatus));
    let mut bad = w;
    bad[STATUS_HEADER] |= 26 << jflag::HOME_STATE_SHIFT;
    assert_eq!(decode_status(&bad), Err(WireError::BadStatus));
}

#[test]
fn every_reason_code_from_1_to_the_last_is_used_and_named() {
    let mut codes: Vec<u64> = all_rejects().iter().map(reject_code).collect();
    codes.sort();
    codes.dedup();
    assert_eq!(codes, (1..=66).collect::<Vec<_>>());
    for c in codes {
        assert_ne!(result_name(c), "unknown", "{c}");
    }
    // Existing codes keep their numbers.
    assert_eq!(reject_code(&Reject::ActivateWhileEnabled { joint: 0 }), 19);
    assert_eq!(reject_code(&Reject::HomingInhibited), 20);
    assert_eq!(reject_code(&Reject::NotInPosition), 30);
    assert_eq!(reject_code(&Reject::KinematicsFailed), 40);
}

#[test]
fn status_modes_and_axes_decode() {
    let mut w = [0u64; STATUS_WORDS];
    w[0] = STATUS_VERSION;
    w[1] = 1;
    for (code, name) in [(0, "DISABLED"), (1, "FREE"), (2, "TELEOP"), (3, "COORD")] {
        w[2] = code;
        assert_eq!(decode_status(&w).unwrap().mode, name);
    }
    let mut bad = w;
    bad[2] = 4;
    assert_eq!(decode_status(&bad), Err(WireError::BadStatus));
    // The remembered mode while disabled.
    w[2] = 0;
    w[3] = flag::TELEOP_MODE;
    let s = decode_status(&w).unwrap();
    assert!(s.teleop_mode && !s.coord_mode);
    assert!(s.to_string().contains("mode on enable: TELEOP"), "{s}");
    // The axis blocks.
    let b = AXES_START + 2 * AXIS_WORDS;
    w[b] = aflag::IN_KINEMATICS | aflag::KB_JOG | aflag::MOVING;
    w[b + 1] = 1.5f64.to_bits();
    w[b + 2] = (-2.0f64).to_bits();
    w[b + 3] = (-1e99f64).to_bits();
    w[b + 4] = 10.0f64.to_bits();
    let s = decode_status(&w).unwrap();
    assert_eq!(s.axes.len(), NUM_AXES);
    let z = s.axes[2];
    assert!(z.in_kinematics && z.kb_jogging && z.moving && !z.wheel_jogging && !z.tp_enable);
    assert_eq!(
        (z.pos_cmd, z.vel_cmd, z.min_limit, z.max_limit),
        (1.5, -2.0, -1e99, 10.0)
    );
    assert!(!s.axes[0].in_kinematics);
    let text = s.to_string();
    assert!(
        text.lines().any(|l| l.starts_with("Z ")
            && l.contains("1.500000")
            && l.contains("-1e99")
            && l.contains("moving jogging")),
        "{text}"
    );
    assert!(!text.lines().any(|l| l.starts_with("X ")), "{text}");
}

#[test]
fn a_core_in_teleop_publishes_its_mode_and_axes() {
    use crate::kins::trivkins::Trivkins;
    use crate::kins::KinematicsType;
    use crate::{MotionConfig, MotionCore};
    let kins = std::sync::Arc::new(Trivkins::new("xz", KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: 2,
            ..MotionConfig::default()
        },
        kins,
    );
    for j in 0..2 {
        m.command(&Command::JointActivate { joint: j }).unwrap();
    }
    m.command(&Command::Teleop).unwrap();
    let mut w = [0u64; STATUS_WORDS];
    m.cycle(0.001);
    fill_status(&m, LastCommand::default(), 0, &mut w);
    let s = decode_status(&w).unwrap();
    assert_eq!(
        (s.mode, s.teleop_mode, s.enabled),
        ("DISABLED", true, false)
    );
    m.command(&Command::Enable).unwrap();
    m.cycle(0.001);
    m.command(&Command::AxisJogCont { axis: 2, vel: 0.5 })
        .unwrap();
    m.cycle(0.001);
    fill_status(&m, LastCommand::default(), 0, &mut w);
    let s = decode_status(&w).unwrap();
    assert_eq!((s.mode, s.teleop_mode, s.enabled), ("TELEOP", true, true));
    let in_kins: Vec<bool> = s.axes.iter().map(|a| a.in_kinematics).collect();
    assert_eq!(
        in_kins,
        [true, false, true, false, false, false, false, false, false]
    );
    let z = s.axes[2];
    assert!(z.kb_jogging && z.moving && z.tp_enable);
    assert_eq!(z.vel_cmd, 0.001, "A·T with the default acceleration 1");
    assert_eq!(z.pos_cmd, m.carte_pos_cmd().0 .0[2]);
    assert_eq!((z.min_limit, z.max_limit), (-1e99, 1e99));
    m.command(&Command::AxisJogAbort { axis: 2 }).unwrap();
    for _ in 0..10 {
        m.cycle(0.001);
    }
    m.command(&Command::Coord).unwrap();
    fill_status(&m, LastCommand::default(), 0, &mut w);
    let s = decode_status(&w).unwrap();
    assert_eq!(
        (s.mode, s.coord_mode, s.teleop_mode),
        ("COORD", true, false)
    );
}
