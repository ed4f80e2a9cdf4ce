//! hm2_eth against the UDP simulator on 127.0.0.1 (each test a port of
//! its own): every LBP16 command form, identification and loading, a
//! whole cycle in one datagram each way, loss, delay and duplication at
//! configured rates with the packet-error counters, the safe state at
//! the limit and the recovery, and a board that never answers.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::net::UdpSocket;
use std::time::Duration;

use common::eth::{serve, EthRig};
use common::{with_core, Named, Rig, PERIOD};
use hal_core::{Host, HostConfig, Value};
use hostmot2::eth::hal::{probe, HM2_ETH_MODULE};
use hostmot2::eth::EthTransport;
use hostmot2::lbp16::{addr, enable, space, Command, Width};
use hostmot2::sim::boards;
use hostmot2::sim::eth_server::Faults;
use hostmot2::sim::machine::{self, Machine};
use hostmot2::transport::{Transport, TransportError};

const DDR_P1: usize = 0x1104;

fn u16s(b: &[u8]) -> Vec<u16> {
    b.chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect()
}

#[test]
fn every_lbp16_command_form_over_udp() {
    let server = serve("7i96s", Faults::default());
    let mut t = EthTransport::connect(server.addr()).unwrap();
    // 32-bit HostMot2 reads, with and without increment.
    let r = t
        .exchange(|q| {
            q.hm2_read(0x100, 3)?;
            q.push_read(
                Command {
                    increment: false,
                    ..Command::read(space::HM2, Width::W32, 3)
                },
                0x100,
            )
        })
        .unwrap()
        .to_vec();
    assert_eq!(&r[..4], &0x55AA_CAFEu32.to_le_bytes());
    assert_eq!(&r[4..12], b"HOSTMOT2");
    assert_eq!(&r[12..16], &r[16..20], "no increment: the same register");
    assert_eq!(&r[16..20], &r[20..24]);
    // 32-bit writes land; a write-only datagram gets no reply.
    let mut w = hostmot2::lbp16::Request::new();
    w.hm2_write(0x0200, &[0x8000_0000]).unwrap();
    assert_eq!(w.reply_len(), 0);
    t.write(0x0200, &[0x4000_0000]).unwrap();
    let mut led = [0u32];
    t.read(0x0200, &mut led).unwrap();
    assert_eq!(led[0], 0x4000_0000);
    // 16-bit spaces: name, versions, MAC, timers, counters.
    let r = t
        .exchange(|q| {
            q.read16(space::BOARD_INFO, addr::INFO_NAME, 8)?;
            q.read16(space::BOARD_INFO, addr::INFO_LBP16_VERSION, 3)?;
            q.read16(space::ETH_EEPROM, addr::EEPROM_MAC, 3)?;
            q.write16(space::TIMER, addr::TIMER_READ_TAG, &[0x1234, 0x5678])?;
            q.read16(space::TIMER, addr::TIMER_READ_TAG, 2)?;
            q.read16(space::COMM_CTRL, addr::CTRL_RX_PACKETS, 1)
        })
        .unwrap()
        .to_vec();
    assert_eq!(&r[..6], b"7I96S\0");
    let w = u16s(&r[16..]);
    assert_eq!(&w[..3], &[3, 16, 1], "LBP16 3, firmware 16, IP from EEPROM");
    assert_eq!(&w[6..8], &[0x1234, 0x5678], "scratch reads back");
    assert!(w[8] >= 3, "packets counted");
    // 8-bit reads of a 16-bit space, byte-addressed.
    let r = t
        .exchange(|q| q.push_read(Command::read(space::BOARD_INFO, Width::W8, 5), 0))
        .unwrap()
        .to_vec();
    assert_eq!(r, b"7I96S");
    // Flash: the ID; page reads are erased flash.
    let r = t
        .exchange(|q| {
            q.push_read(
                Command::read(space::FPGA_FLASH, Width::W32, 1),
                addr::FLASH_ID,
            )?;
            q.push_read(
                Command::read(space::FPGA_FLASH, Width::W32, 1),
                addr::FLASH_DATA,
            )
        })
        .unwrap()
        .to_vec();
    assert_eq!(r, [0x14, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF]);
    // Every info area names its memory.
    for (sp, name) in [
        (space::HM2, b"HostMot2"),
        (space::ETH_EEPROM, b"EEPROM  "),
        (space::FPGA_FLASH, b"FPGAFLSH"),
        (space::TIMER, b"Timers  "),
        (space::COMM_CTRL, b"LBPCtrl "),
        (space::BOARD_INFO, b"BoardID "),
    ] {
        let mut area = [0u16; 8];
        t.read16(sp, true, 0, &mut area).unwrap();
        let bytes: Vec<u8> = area.iter().flat_map(|w| w.to_le_bytes()).collect();
        assert_eq!(&bytes[8..16], name, "space {sp}");
    }
    // EEPROM writes need the enable in the same datagram.
    let r = t
        .exchange(|q| {
            q.write16(space::COMM_CTRL, addr::CTRL_WRITE_ENABLE, &[enable::EEPROM])?;
            q.write16(space::ETH_EEPROM, addr::EEPROM_IP, &[0x0102, 0x0A00])?;
            q.read16(space::ETH_EEPROM, addr::EEPROM_IP, 2)
        })
        .unwrap()
        .to_vec();
    assert_eq!(u16s(&r), [0x0102, 0x0A00]);
    t.write16(space::ETH_EEPROM, addr::EEPROM_IP, &[0, 0])
        .unwrap();
    let mut ip = [0u16; 2];
    t.read16(space::ETH_EEPROM, false, addr::EEPROM_IP, &mut ip)
        .unwrap();
    assert_eq!(ip, [0x0102, 0x0A00], "refused without the enable");
    let mut errs = [0u16; 1];
    t.read16(space::COMM_CTRL, false, addr::CTRL_WRITE_ERRORS, &mut errs)
        .unwrap();
    assert_eq!(errs[0], 2);
    // A long read is split into several commands in one datagram.
    let mut big = vec![0u32; 200];
    t.read(0x400, &mut big).unwrap();
    assert_eq!(big[0], 3, "IDROM type");
    // A reset makes the watchdog bite.
    t.write16(space::COMM_CTRL, addr::CTRL_RESET, &[1]).unwrap();
    t.read(0x100, &mut led).unwrap();
    assert_eq!(server.shared().with(|b| b.resets()), 1);
}

fn verbose(h: Host) -> Host {
    h.rt_log().set_level(hal_core::MsgLevel::All);
    h
}

fn history(h: &Host) -> Vec<String> {
    h.flush_rt_log();
    h.rt_log().history().into_iter().map(|(_, t)| t).collect()
}

#[test]
fn boards_are_identified_from_space_7_and_load_with_linuxcncs_names() {
    let a = serve("7i96s", Faults::default());
    let b = serve("7i96s", Faults::default());
    let c = serve("7i76e", Faults::default());
    let mut t = EthTransport::connect(a.addr()).unwrap();
    let found = probe(&mut t).unwrap();
    assert_eq!(found.name, "7I96S");
    assert_eq!(found.mac, [0x00, 0x60, 0x1B, 0x16, 0x00, 0x01]);

    let h = verbose(with_core("hm2-eth-load"));
    let ips = format!("board_ip={},{},{}", a.addr(), c.addr(), b.addr());
    h.loadrt(
        &HM2_ETH_MODULE,
        &[
            ips.as_str(),
            "config=num_encoders=0 num_stepgens=3,,num_stepgens=1",
        ],
    )
    .unwrap();
    assert_eq!(h.loaded_components(), ["hostmot2", "hm2_eth"]);
    let inst = h.instance();
    let functs: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
    for board in ["hm2_7i96s.0", "hm2_7i96s.1", "hm2_7i76e.0"] {
        for f in ["read-request", "read", "write", "pet_watchdog"] {
            let name = format!("{board}.{f}");
            assert!(functs.contains(&name), "{name} in {functs:?}");
        }
        assert!(
            !functs.contains(&format!("{board}.read_gpio")),
            "not thread-safe"
        );
        for (param, v) in [
            ("packet-read-timeout", Value::S32(80)),
            ("packet-error-limit", Value::S32(10)),
            ("packet-error-increment", Value::S32(2)),
            ("packet-error-decrement", Value::S32(1)),
            ("io_error", Value::Bit(false)),
        ] {
            assert_eq!(
                inst.param_value(&format!("{board}.{param}")).unwrap(),
                v,
                "{board}.{param}"
            );
        }
        for (pin, v) in [
            ("packet-error", Value::Bit(false)),
            ("packet-error-total", Value::U32(0)),
            ("packet-error-level", Value::S32(0)),
            ("packet-error-exceeded", Value::Bit(false)),
        ] {
            assert_eq!(
                inst.pin_value(&format!("{board}.{pin}")).unwrap(),
                v,
                "{board}.{pin}"
            );
        }
    }
    assert!(inst
        .pin("hm2_7i96s.0.stepgen.02.position-fb")
        .unwrap()
        .is_some());
    assert!(inst
        .pin("hm2_7i96s.0.stepgen.03.position-fb")
        .unwrap()
        .is_none());
    assert!(inst
        .pin("hm2_7i96s.1.stepgen.00.position-fb")
        .unwrap()
        .is_some());
    assert!(inst
        .pin("hm2_7i96s.1.stepgen.01.position-fb")
        .unwrap()
        .is_none());
    assert!(inst
        .pin("hm2_7i76e.0.stepgen.04.position-fb")
        .unwrap()
        .is_some());
    assert!(inst.pin("hm2_7i96s.0.gpio.050.in").unwrap().is_some());
    assert!(inst.pin("hm2_7i96s.0.led.CR04").unwrap().is_some());
    let log = history(&h);
    assert!(
        log.iter().any(|l| l == "hm2_eth: discovered 7I96S"),
        "{log:?}"
    );
    assert!(
        log.iter().any(|l| l == "hm2_eth: discovered 7I76E-16"),
        "{log:?}"
    );
    // Unloading makes each board safe: its pins released.
    a.shared().with(|b| b.model().write32(DDR_P1, 0x1FFFF));
    h.unloadrt("hm2_eth").unwrap();
    common::eth::sync(&a);
    assert_eq!(a.shared().with(|b| b.model().read32(DDR_P1)), 0);
}

#[test]
fn refused_loads_say_why_and_leave_nothing() {
    let h = with_core("hm2-eth-refused");
    let server = serve("7i96s", Faults::default());
    let ip = format!("board_ip={}", server.addr());
    let twice = format!("board_ip={0},{0}", server.addr());
    let same = format!(
        "item 1 \"{0}\": the same board as item 0 ({0}): list each board once",
        server.addr()
    );
    for (args, want) in [
        (vec![], "parameter 'board_ip': no board given"),
        (
            vec!["board_ip=192.168.1"],
            "parameter 'board_ip': item 0 \"192.168.1\": not an IP address",
        ),
        (vec![ip.as_str(), "board_rtnet=evl"], "only posix sockets"),
        (vec![twice.as_str()], same.as_str()),
        (vec![ip.as_str(), "firewall=ufw"], "firewall"),
        (
            vec![ip.as_str(), "config=num_stepgens=6"],
            "num_stepgens=6, but only 5 are available",
        ),
    ] {
        let e = h.loadrt(&HM2_ETH_MODULE, &args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert_eq!(h.loaded_components(), ["hostmot2"], "{args:?}");
    }
    // Without hostmot2.
    let bare = Host::create(HostConfig::for_tests("hm2-eth-bare")).unwrap();
    let e = bare.loadrt(&HM2_ETH_MODULE, &[ip.as_str()]).unwrap_err();
    assert!(e.to_string().contains("loadrt hostmot2 first"));
}

#[test]
fn a_board_that_never_answers_fails_the_load_naming_its_address() {
    let silent = UdpSocket::bind("127.0.0.1:0").unwrap();
    let addr = silent.local_addr().unwrap();
    let h = with_core("hm2-eth-silent");
    let arg = format!("board_ip={addr}");
    let e = h
        .loadrt(&HM2_ETH_MODULE, &[arg.as_str()])
        .unwrap_err()
        .to_string();
    assert!(e.contains(&addr.to_string()), "{e}");
    assert!(e.contains("no reply from"), "{e}");
    assert_eq!(h.loaded_components(), ["hostmot2"]);
    assert!(history(&h).iter().any(|l| l.contains(&addr.to_string())));
    drop(silent);
}

/// The stepper machine's first axis commanded to `to` units for `n`
/// cycles; the step generator's feedback of each cycle.
fn run_axis(
    mut cycle: impl FnMut(),
    set: impl Fn(&str, Value),
    get: impl Fn(&str) -> Value,
    n: usize,
) -> Vec<f64> {
    set("stepgen.00.position-scale", Value::Float(100.0));
    set("stepgen.00.maxaccel", Value::Float(0.0));
    set("stepgen.00.steplen", Value::U32(2000));
    set("stepgen.00.stepspace", Value::U32(2000));
    set("stepgen.00.enable", Value::Bit(true));
    let mut out = Vec::new();
    for k in 0..n {
        set(
            "stepgen.00.position-cmd",
            Value::Float(0.01 * k.min(200) as f64),
        );
        cycle();
        match get("stepgen.00.position-fb") {
            Value::Float(f) => out.push(f),
            v => panic!("{v:?}"),
        }
    }
    out
}

#[test]
fn a_whole_cycle_is_one_datagram_each_way_and_matches_the_pci_simulator() {
    let mut eth = EthRig::new("hm2-eth-cycle", "7i96s", "num_encoders=0");
    // A round trip: everything sent before has been executed.
    eth.board.read_request();
    eth.board.read();
    let before = eth.server.shared().counts.snapshot();
    eth.server.shared().with(|b| b.record(true));
    eth.board.write(PERIOD);
    eth.board.read_request();
    eth.board.read();
    let after = eth.server.shared().counts.snapshot();
    assert_eq!(after[0] - before[0], 2, "a write and a request datagram");
    assert_eq!(after[1] - before[1], 1, "one reply");
    let kinds: Vec<bool> = eth
        .server
        .shared()
        .with(|b| b.take_recorded())
        .iter()
        .map(|d| hostmot2::lbp16::parse(d).flatten().all(|c| c.cmd.write))
        .collect();
    assert_eq!(kinds, [true, false], "the writes, then the request");
    eth.board.write(PERIOD);
    let fb_eth = {
        let r = &mut eth;
        let host = r.host.instance();
        let prefix = r.prefix.clone();
        let set = |n: &str, v| {
            let full = format!("{prefix}.{n}");
            if host.set_param(&full, v).is_err() {
                host.set_pin(&full, v).unwrap();
            }
        };
        let get = |n: &str| host.pin_value(&format!("{prefix}.{n}")).unwrap();
        let board = &mut r.board;
        run_axis(
            || {
                board.read_request();
                board.read();
                board.write(PERIOD);
            },
            set,
            get,
            300,
        )
    };
    // The same firmware and machine on the PCI simulator.
    let spec = boards::preset("7i96s").unwrap();
    let mut pci = Rig::new(
        "hm2-eth-cycle-pci",
        spec,
        Box::new(machine::preset("7i96s")),
        "num_encoders=0",
    );
    pci.cycle();
    let fb_pci = {
        let host = pci.host.instance();
        let prefix = pci.prefix.clone();
        let set = |n: &str, v| {
            let full = format!("{prefix}.{n}");
            if host.set_param(&full, v).is_err() {
                host.set_pin(&full, v).unwrap();
            }
        };
        let get = |n: &str| host.pin_value(&format!("{prefix}.{n}")).unwrap();
        let board = &mut pci.board;
        let sim = pci.sim.clone();
        run_axis(
            || {
                sim.advance(PERIOD as u64);
                board.read();
                board.write(PERIOD);
            },
            set,
            get,
            300,
        )
    };
    assert_eq!(fb_eth, fb_pci, "same positions every cycle");
    assert!((fb_eth.last().unwrap() - 2.0).abs() < 1e-9);
    let steps = eth.server.shared().with(|b| {
        b.model().world::<Machine>().unwrap().steppers[0]
            .axis
            .position()
    });
    assert!((steps - 2.0).abs() < 1e-9, "{steps}");
    assert_eq!(eth.pin("packet-error-total"), Value::U32(0));
}

fn counts(r: &EthRig) -> [u64; 7] {
    r.server.shared().counts.snapshot()
}

fn total(r: &EthRig) -> u32 {
    match r.pin("packet-error-total") {
        Value::U32(v) => v,
        v => panic!("{v:?}"),
    }
}

#[test]
fn lost_requests_and_replies_are_counted_and_tolerated() {
    let mut r = EthRig::new("hm2-eth-loss", "7i96s", "");
    r.set_param("packet-error-limit", Value::S32(1000));
    r.cycles(3);
    // Each lost read request or reply is one error, found by the
    // timeout.
    r.server.shared().set_faults(Faults {
        drop_requests: 0.05,
        drop_replies: 0.1,
        seed: 11,
        ..Faults::default()
    });
    r.cycles(150);
    r.server.shared().set_faults(Faults::default());
    let c = counts(&r);
    let (dropped_requests, dropped_replies) = (c[2], c[3]);
    assert!(dropped_requests > 0 && dropped_replies > 0, "{c:?}");
    assert_eq!(
        total(&r) as u64,
        dropped_requests + dropped_replies,
        "{c:?}"
    );
    // Each lost write datagram is one error too, found by the next
    // reply's write tag (its data is still used).
    r.server.shared().set_faults(Faults {
        drop_writes: 0.1,
        seed: 12,
        ..Faults::default()
    });
    r.cycles(150);
    r.server.shared().set_faults(Faults::default());
    r.cycles(1);
    let dropped_writes = counts(&r)[6];
    assert!(dropped_writes > 0);
    assert_eq!(
        total(&r) as u64,
        dropped_requests + dropped_replies + dropped_writes
    );
    assert_eq!(r.param("io_error"), Value::Bit(false), "tolerated");
    // Clean cycles bring the level down to 0.
    r.cycles(200);
    assert_eq!(r.pin("packet-error-level"), Value::S32(0));
    assert_eq!(r.pin("packet-error"), Value::Bit(false));
}

#[test]
fn late_replies_are_errors_and_duplicates_are_dropped() {
    let mut r = EthRig::new("hm2-eth-late", "7i96s", "");
    r.set_param("packet-error-limit", Value::S32(1000));
    // A generous timeout while duplicates are checked: on a loaded
    // machine an honest reply can take longer than 20 ms, and that would
    // be counted as an error the duplicates did not cause.
    r.set_param("packet-read-timeout", Value::S32(500_000_000));
    r.cycles(2);
    r.server.shared().set_faults(Faults {
        duplicate: 0.5,
        seed: 3,
        ..Faults::default()
    });
    r.cycles(60);
    assert!(counts(&r)[5] > 10, "duplicates sent");
    assert_eq!(total(&r), 0, "a duplicate is discarded, never an error");
    // Replies held back past the 20 ms timeout: each an error, and the
    // late copy is discarded when it arrives in a later cycle.
    r.set_param("packet-read-timeout", Value::S32(20_000_000));
    r.server.shared().set_faults(Faults {
        delay_rate: 0.2,
        delay: Duration::from_millis(60),
        seed: 5,
        ..Faults::default()
    });
    r.cycles(40);
    r.server.shared().set_faults(Faults::default());
    let delayed = counts(&r)[4];
    assert!(delayed > 0);
    r.cycles(5);
    assert_eq!(total(&r) as u64, delayed);
    assert_eq!(r.param("io_error"), Value::Bit(false));
}

#[test]
fn at_the_limit_outputs_go_safe_and_clearing_io_error_recovers() {
    let mut r = EthRig::new("hm2-eth-limit", "7i96s", "");
    r.set_param("packet-read-timeout", Value::S32(5_000_000));
    r.set_param("stepgen.00.position-scale", Value::Float(100.0));
    r.set_param("stepgen.00.maxaccel", Value::Float(0.0));
    r.set_pin("stepgen.00.enable", Value::Bit(true));
    r.set_pin("stepgen.00.velocity-cmd", Value::Float(1.0));
    r.set_pin("stepgen.00.control-type", Value::Bit(true));
    r.cycles(5);
    let ddr = r.reg(DDR_P1);
    assert_eq!(ddr & 0x3FF, 0x3FF, "step/dir driven");
    assert_ne!(r.reg(0x2000), 0, "stepping");
    // The network goes away: five errors in a row reach the limit.
    r.server.shared().set_faults(Faults {
        drop_replies: 1.0,
        ..Faults::default()
    });
    for k in 1..=5 {
        r.cycle();
        assert_eq!(r.pin("packet-error-level"), Value::S32(2 * k));
    }
    assert_eq!(r.pin("packet-error-exceeded"), Value::Bit(true));
    assert_eq!(r.param("io_error"), Value::Bit(true));
    // The board sends nothing more; let the checks below get through.
    r.server.shared().set_faults(Faults::default());
    assert_eq!(r.reg(DDR_P1), 0, "every pin released");
    assert_eq!(r.reg(0x2000), 0, "no step rate");
    assert!(r
        .server
        .shared()
        .with(|b| b.model().pin_driven(17))
        .is_none());
    let msgs = r.messages();
    assert!(
        msgs.iter()
            .any(|m| m.contains("packet-error-limit reached")),
        "{msgs:?}"
    );
    // Nothing is sent while io_error holds.
    r.sync();
    let before = counts(&r)[0];
    r.cycles(3);
    r.sync();
    assert_eq!(counts(&r)[0], before + 2, "only the second sync's requests");
    // Packets return; the user clears io_error and the watchdog's bit.
    r.set_param("io_error", Value::Bit(false));
    r.cycles(2);
    r.set_pin("watchdog.has_bit", Value::Bit(false));
    r.cycles(3);

    assert_eq!(r.pin("packet-error-level"), Value::S32(0));
    assert_eq!(r.pin("packet-error-exceeded"), Value::Bit(false));
    assert_eq!(r.reg(DDR_P1) & 0x3FF, 0x3FF, "driven again");
    assert_ne!(r.reg(0x2000), 0, "stepping again");
}

#[test]
fn short_long_and_foreign_replies_never_pass_for_data() {
    // A board that answers everything with junk of every length.
    let junk = UdpSocket::bind("127.0.0.1:0").unwrap();
    let addr = junk.local_addr().unwrap();
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = stop.clone();
    let th = std::thread::spawn(move || {
        junk.set_read_timeout(Some(Duration::from_millis(20)))
            .unwrap();
        let mut buf = [0u8; 2048];
        let mut k = 0usize;
        while !flag.load(std::sync::atomic::Ordering::Relaxed) {
            if let Ok((n, from)) = junk.recv_from(&mut buf) {
                k += 1;
                let len = [0, 1, n, 22, 4 * n, 1500][k % 6];
                let reply: Vec<u8> = (0..len).map(|i| (i * 7 + k) as u8).collect();
                let _ = junk.send_to(&reply, from);
            }
        }
    });
    let mut t = EthTransport::connect(addr).unwrap();
    t.set_cycle_period(PERIOD);
    t.reserve(4, 8, 4, 8);
    for _ in 0..12 {
        t.queue_read(0x100, 3).unwrap();
        t.send_queued_reads().unwrap_or(());
        let mut out = [0u32; 3];
        let e = t.receive_queued_reads(&mut out).unwrap_err();
        assert!(
            matches!(
                e,
                TransportError::Lost | TransportError::PacketErrors { .. }
            ),
            "{e:?}"
        );
        assert_eq!(out, [0; 3], "nothing copied");
    }
    let mut w = [0u32; 1];
    let e = t.read(0x100, &mut w).unwrap_err();
    assert!(matches!(e, TransportError::NoReply { .. }), "{e:?}");
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    th.join().unwrap();
}

/// A request that cannot be sent (the board's port refuses: ICMP port
/// unreachable, reported on the next send) loses that cycle: the receive
/// that follows says so, rather than that its queue no longer matches.
#[test]
fn a_request_that_never_left_reads_as_lost() {
    let gone = UdpSocket::bind("127.0.0.1:0").unwrap();
    let addr = gone.local_addr().unwrap();
    drop(gone);
    let mut t = EthTransport::connect(addr).unwrap();
    t.set_cycle_period(PERIOD);
    t.reserve(4, 8, 4, 8);
    // The first request goes out and draws the refusal; a later send
    // reports it.
    let mut refused = false;
    for _ in 0..50 {
        t.queue_read(0x100, 3).unwrap();
        if t.send_queued_reads().is_err() {
            refused = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(refused, "no send to a closed port was refused");
    let mut out = [7u32; 3];
    let e = t.receive_queued_reads(&mut out).unwrap_err();
    assert!(matches!(e, TransportError::Lost), "{e:?}");
    assert_eq!(out, [7; 3], "nothing copied");
}
