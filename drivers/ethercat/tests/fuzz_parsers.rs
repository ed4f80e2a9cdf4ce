//! The fuzz targets' bodies ([`hal_ethercat::fuzzing`]) over random and
//! mutated seed inputs (proptest, on stable), and the hostile cases by
//! hand: frames whose lengths lie, mailboxes that announce more than they
//! hold, SII images with broken categories, XML that is not
//! linuxcnc-ethercat's.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

use hal_ethercat::fuzzing;

/// Runs `body` over `cases` inputs: random bytes, and seeds with random
/// bytes written over them.
fn run(cases: u32, seeds: &[Vec<u8>], body: fn(&[u8])) {
    for s in seeds {
        body(s);
    }
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let edits = vec((any::<u16>(), any::<u8>()), 1..8);
    let strategy = (
        any::<usize>(),
        edits,
        vec(any::<u8>(), 0..300),
        any::<bool>(),
    );
    runner
        .run(&strategy, |(pick, edits, random, from_seed)| {
            let input = match seeds.get(pick % seeds.len().max(1)) {
                Some(seed) if from_seed && !seed.is_empty() => {
                    let mut s = seed.clone();
                    for (at, v) in edits {
                        let n = s.len();
                        s[usize::from(at) % n] = v;
                    }
                    s
                }
                _ => random,
            };
            body(&input);
            Ok(())
        })
        .unwrap();
}

#[test]
fn frames_from_the_wire() {
    run(3000, &fuzzing::seed_frames(), fuzzing::frames);
}

#[test]
fn mailbox_areas() {
    for m in fuzzing::seed_mailboxes() {
        let request = hal_ethercat::wire::coe::parse_request(&m).is_ok();
        assert!(request || hal_ethercat::wire::coe::parse_response(&m).is_ok());
    }
    run(5000, &fuzzing::seed_mailboxes(), fuzzing::mailbox);
}

#[test]
fn sii_images() {
    for s in fuzzing::seed_sii_images() {
        hal_ethercat::wire::sii::Sii::decode(&s, None).unwrap();
    }
    run(3000, &fuzzing::seed_sii_images(), fuzzing::sii);
}

#[test]
fn xml_configurations() {
    let seeds = vec![
        br#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1000"><slave idx="0" type="EK1100" name="D0"/><slave idx="1" type="EL1008" name="D1"/></master></masters>"#.to_vec(),
        br#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="-1"><slave idx="1" type="generic" vid="2" pid="0x3fa3052" name="g" configPdos="true"><syncManager idx="2" dir="out"><pdo idx="1600"><pdoEntry idx="7000" subIdx="1" bitLen="16" halType="complex"><complexEntry bitLen="1" halPin="a" halType="bit"/></pdoEntry></pdo></syncManager></slave></master></masters>"#.to_vec(),
    ];
    run(2000, &seeds, fuzzing::xml);
}

#[test]
fn hostile_frames_by_hand() {
    let mut f = fuzzing::seed_frames()[0].clone();
    // The EtherCAT length says more than the frame holds.
    f[14] = 0xFF;
    f[15] = 0x17;
    fuzzing::frames(&f);
    // A datagram length past the end, with the "more" bit set.
    let mut f = fuzzing::seed_frames()[3].clone();
    f[22] = 0xFF;
    f[23] = 0x87;
    fuzzing::frames(&f);
    // Only headers; a frame of another EtherType; nothing at all.
    fuzzing::frames(&f[..16]);
    let mut g = f.clone();
    g[12] = 0x08;
    fuzzing::frames(&g);
    fuzzing::frames(&[]);
}
