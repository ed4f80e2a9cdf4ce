//! The fuzz bodies of `hostmot2::fuzzing` on 100,000 generated cases each:
//! random and mutated register images into the IDROM loader, and config
//! strings. Then fewer mutated images registered all the way on a HAL
//! instance, which must not panic either.

use hal_core::{Host, HostConfig, MsgLevel, RtLog};
use hostmot2::board::Board;
use hostmot2::firmware::{self, Debug};
use hostmot2::fuzzing;
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
            fuzzing::idrom_image(&data);
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
            fuzzing::config_string(&s);
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
            let case = fuzzing::decode(&data);
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

#[test]
fn replies_to_cycle_requests_are_taken_only_when_they_are_the_reply() {
    let bytes = prop::collection::vec(any::<u8>(), 0..200);
    runner(100_000)
        .run(&bytes, |data| {
            fuzzing::eth_reply(&data);
            Ok(())
        })
        .unwrap();
}

#[test]
fn request_datagrams_to_the_simulated_board_never_panic() {
    // Mostly well-formed commands, some cut short or garbled.
    let command = (
        any::<u16>(),
        any::<u16>(),
        prop::collection::vec(any::<u8>(), 0..24),
    )
        .prop_map(|(w, a, d)| {
            let mut v = (w | 0x4000).to_le_bytes().to_vec();
            v.extend(a.to_le_bytes());
            v.extend(d);
            v
        });
    let datagram = prop_oneof![
        prop::collection::vec(command, 0..6).prop_map(|v| v.concat()),
        prop::collection::vec(any::<u8>(), 0..64),
    ];
    runner(100_000)
        .run(&datagram, |data| {
            fuzzing::lbp16_request(&data);
            Ok(())
        })
        .unwrap();
}

#[test]
fn card_records_are_read_or_refused() {
    let bytes = prop::collection::vec(any::<u8>(), 0..300);
    runner(100_000)
        .run(&bytes, |data| {
            fuzzing::sserial_records(&data);
            Ok(())
        })
        .unwrap();
}

#[test]
fn hostile_cards_load_checked_or_are_refused_by_port_and_channel() {
    let bytes = prop::collection::vec(any::<u8>(), 0..300);
    runner(2_000)
        .run(&bytes, |data| {
            fuzzing::sserial_card(&data);
            Ok(())
        })
        .unwrap();
}

/// The real receive path over a loopback socket: each case answers one
/// cycle's request with up to three hostile datagrams (random bytes,
/// short or long copies of the reply, the reply with another cycle's
/// tag) and maybe the genuine reply after them; the transport returns
/// the genuine data exactly when the genuine reply came, never a
/// hostile datagram's.
#[test]
fn hostile_datagrams_on_the_socket_never_pass_for_the_reply() {
    use hostmot2::eth::EthTransport;
    use hostmot2::lbp16::{parse, space};
    use hostmot2::transport::{Transport, TransportError};
    use std::net::UdpSocket;

    let board = UdpSocket::bind("127.0.0.1:0").unwrap();
    board
        .set_read_timeout(Some(std::time::Duration::from_secs(5)))
        .unwrap();
    let mut t = EthTransport::connect(board.local_addr().unwrap()).unwrap();
    t.set_cycle_period(1_000_000);
    t.reserve(2, 64, 2, 64);
    let t = std::cell::RefCell::new(t);
    let case = (
        1usize..40,
        prop::collection::vec((0u8..4, prop::collection::vec(any::<u8>(), 0..200)), 0..4),
        any::<bool>(),
    );
    runner(5_000)
        .run(&case, |(words, hostile, genuine)| {
            let mut t = t.borrow_mut();
            t.queue_read(0x1000, words).unwrap();
            t.send_queued_reads().unwrap_or(());
            let mut buf = [0u8; 2048];
            let (n, from) = board.recv_from(&mut buf).unwrap();
            let tag = parse(&buf[..n])
                .flatten()
                .find(|c| c.cmd.write && c.cmd.space == space::TIMER && c.addr == 0x10)
                .map(|c| [c.data[0], c.data[1], c.data[2], c.data[3]])
                .expect("the read tag");
            let data: Vec<u32> = (0..words as u32)
                .map(|i| i.wrapping_mul(0x9E37_79B9))
                .collect();
            let mut reply: Vec<u8> = data.iter().flat_map(|w| w.to_le_bytes()).collect();
            reply.extend([0, 0]);
            reply.extend(tag);
            reply.extend([0, 0, 0, 0]);
            for (kind, bytes) in &hostile {
                let d = match kind {
                    0 => bytes.clone(),
                    1 => reply[..bytes.len().min(reply.len() - 1)].to_vec(),
                    2 => [&reply[..], &bytes[..]].concat(),
                    _ => {
                        let mut r = reply.clone();
                        let at = r.len() - 8;
                        r[at] = r[at].wrapping_add(1 + bytes.first().copied().unwrap_or(0) % 200);
                        r
                    }
                };
                if d != reply {
                    board.send_to(&d, from).unwrap();
                }
            }
            if genuine {
                board.send_to(&reply, from).unwrap();
            }
            let mut out = vec![0u32; words];
            match t.receive_queued_reads(&mut out) {
                Ok(()) => {
                    assert!(genuine, "a hostile datagram taken for the reply");
                    assert_eq!(out, data);
                }
                Err(TransportError::Lost | TransportError::PacketErrors { .. }) => {
                    assert!(!genuine, "the genuine reply refused")
                }
                Err(e) => panic!("{e}"),
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn epp_ports_with_edited_reads_fail_cleanly_and_recover() {
    let bytes = prop::collection::vec(any::<u8>(), 0..100);
    runner(5_000)
        .run(&bytes, |data| {
            fuzzing::epp_port(&data);
            Ok(())
        })
        .unwrap();
    // Untouched, both boards load.
    fuzzing::epp_port(&[0]);
    fuzzing::epp_port(&[1]);
    fuzzing::epp_port(&[3]);
}

#[test]
fn spi_messages_are_served_or_refused_with_a_reason() {
    let bytes = prop::collection::vec(any::<u8>(), 0..200);
    runner(1_000)
        .run(&bytes, |data| {
            fuzzing::spi_frames(&data);
            Ok(())
        })
        .unwrap();
    // A read of the cookie, then a write burst; and a junk word.
    fuzzing::spi_frames(&[0x01, 0x00, 0xA8, 0x10, 0, 0, 0, 0]);
    fuzzing::spi_frames(&[0x0C, 0x00, 0xB8, 0x20, 1, 2, 3, 4, 5, 6, 7, 8]);
    fuzzing::spi_frames(&[0x12, 0x34, 0x56, 0x78]);
}
