//! The fuzz bodies of `hostmot2::fuzz` on 100,000 generated cases each:
//! random and mutated register images into the IDROM loader, and config
//! strings. Then fewer mutated images registered all the way on a HAL
//! instance, which must not panic either.

use hal_core::{Host, HostConfig, MsgLevel, RtLog};
use hostmot2::board::Board;
use hostmot2::firmware::{self, Debug};
use hostmot2::fuzz;
use hostmot2::image::ImageTransport;
use hostmot2::log::{BoardLog, MessageLog};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

fn runner(cases: u32) -> TestRunner {
    TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    })
}

#[test]
fn idrom_loader_survives_random_and_mutated_images() {
    let bytes = prop::collection::vec(any::<u8>(), 0..400);
    runner(100_000)
        .run(&bytes, |data| {
            fuzz::idrom_image(&data);
            Ok(())
        })
        .unwrap();
}

const WORDS: &[&str] = &[
    "num_encoders=",
    "num_stepgens=",
    "num_pwmgens=",
    "num_leds=",
    "stepgen_width=",
    "enable_raw",
    "firmware=",
    "sserial_port_0=",
    "sserial_port_9=",
    "ssi_chan_1=",
    "num_3pwmgens=",
    "-1",
    "0x10",
    "017",
    "99999999999",
    "x",
    "=",
    " ",
    "  ",
    "\t",
];

#[test]
fn config_strings_are_parsed_or_refused_with_a_reason() {
    let token = prop_oneof![
        prop::sample::select(WORDS).prop_map(str::to_string),
        prop::collection::vec(32u8..127, 0..6).prop_map(|b| String::from_utf8(b).unwrap()),
        prop::collection::vec(any::<char>(), 0..3).prop_map(|c| c.into_iter().collect()),
    ];
    let text = prop::collection::vec(token, 0..8).prop_map(|v| v.concat());
    runner(100_000)
        .run(&text, |s| {
            fuzz::config_string(&s);
            Ok(())
        })
        .unwrap();
}

#[test]
fn mutated_boards_register_or_refuse_without_panicking() {
    let host = Host::create(HostConfig::for_tests("hm2-fuzz-reg")).unwrap();
    let log = RtLog::new(64);
    log.set_level(MsgLevel::None);
    let bytes = prop::collection::vec(any::<u8>(), 0..60);
    runner(300)
        .run(&bytes, |data| {
            let case = fuzz::decode(&data);
            let mut t = ImageTransport::new(case.image, "fuzz");
            let mut msgs = MessageLog::default();
            let config = hostmot2::config::Config::default();
            if let Ok(fw) = firmware::load(&case.llio, &config, Debug::default(), &mut t, &mut msgs)
            {
                let b = host.new_rt_component("hm2_fuzz").unwrap();
                let board = Board::register(
                    b.component(),
                    case.llio.clone(),
                    fw,
                    &config,
                    Box::new(t),
                    BoardLog::new(log.clone(), &case.llio.name),
                    &mut msgs,
                );
                if let Ok(mut board) = board {
                    for _ in 0..3 {
                        board.read();
                        board.write(1_000_000);
                    }
                    board.go_safe();
                }
                // Dropped unready: everything it made goes.
                drop(b);
                assert!(host.instance().components().unwrap().is_empty());
            }
            Ok(())
        })
        .unwrap();
}
