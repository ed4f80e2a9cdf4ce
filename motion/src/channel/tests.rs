//! Wire-format tests: round trips and rejection of every corrupt word.

use super::*;

fn all_commands() -> Vec<Command> {
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
fn every_opcode_from_1_to_28_is_used() {
    let mut ops: Vec<u64> = all_commands().iter().map(|c| shape(c).0).collect();
    ops.sort();
    ops.dedup();
    assert_eq!(ops, (1..=28).collect::<Vec<_>>());
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
    for op in [0u64, 29, 1000, u64::MAX] {
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
    ];
    for code in 1..=9 {
        v.push(Reject::BadHomingConfig {
            joint: 1,
            problem: ConfigProblem::from_code(code).unwrap(),
        });
    }
    for what in WHATS {
        v.push(Reject::BadValue { what, value: -1.0 });
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
