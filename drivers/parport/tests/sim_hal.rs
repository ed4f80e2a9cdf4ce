//! hal_parport loaded into a HAL host on the simulated backend: every
//! pin, invert, reset and reset-time, the cfg forms and the bad ones.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::Arc;

use common::*;
use hal_core::Value;
use hal_parport::clock::MonotonicClock;
use hal_parport::load_cfg;
use hal_parport::regs;
use hal_parport::select::SysPaths;

const OUT_PINS: [u8; 12] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 14, 16, 17];
const STATUS_PINS: [u8; 5] = [10, 11, 12, 13, 15];

fn pin_names(host: &hal_core::Host) -> Vec<String> {
    host.instance()
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .collect()
}

#[test]
fn out_mode_drives_every_output_pin_with_invert() {
    let host = host("out");
    loadrt(&host, "0 sim").unwrap();
    let sim = sim(&host, 0);
    run(&host, 1_000_000, &["parport.0.read", "parport.0.write"]);
    cycles(&sim, 2);
    for p in OUT_PINS {
        assert!(!sim.level(p), "pin {p} starts low");
    }
    for p in OUT_PINS {
        set(&host, &format!("parport.0.pin-{p:02}-out"), true);
        cycles(&sim, 2);
        for q in OUT_PINS {
            assert_eq!(sim.level(q), q == p, "pin {q} while {p} is set");
        }
        setp(
            &host,
            &format!("parport.0.pin-{p:02}-out-invert"),
            Value::Bit(true),
        );
        cycles(&sim, 2);
        assert!(!sim.level(p), "pin {p} inverted");
        set(&host, &format!("parport.0.pin-{p:02}-out"), false);
        cycles(&sim, 2);
        assert!(sim.level(p), "pin {p} FALSE inverted is high");
        setp(
            &host,
            &format!("parport.0.pin-{p:02}-out-invert"),
            Value::Bit(false),
        );
        cycles(&sim, 2);
        assert!(!sim.level(p));
    }
    host.stop();
}

#[test]
fn out_mode_reads_every_status_pin() {
    let host = host("status");
    loadrt(&host, "0x378 out sim").unwrap();
    let sim = sim(&host, 0);
    run(&host, 1_000_000, &["parport.read-all"]);
    cycles(&sim, 2);
    for p in STATUS_PINS {
        assert!(
            bit(&host, &format!("parport.0.pin-{p:02}-in")),
            "floating pin {p} is high"
        );
        assert!(!bit(&host, &format!("parport.0.pin-{p:02}-in-not")));
    }
    for p in STATUS_PINS {
        sim.set_input(p, false);
        cycles(&sim, 2);
        for q in STATUS_PINS {
            let high = q != p;
            assert_eq!(
                bit(&host, &format!("parport.0.pin-{q:02}-in")),
                high,
                "{q} ({p} low)"
            );
            assert_eq!(bit(&host, &format!("parport.0.pin-{q:02}-in-not")), !high);
        }
        sim.set_input(p, true);
    }
    host.stop();
}

#[test]
fn in_mode_reads_data_pins_and_keeps_the_direction_bit() {
    let host = host("in");
    loadrt(&host, "1 in sim").unwrap();
    let sim = sim(&host, 0);
    assert_eq!(sim.base_addr(), 0x278);
    assert_eq!(
        sim.control_latch() & regs::CONTROL_DIR_IN,
        regs::CONTROL_DIR_IN
    );
    let names = pin_names(&host);
    for p in 2..=9 {
        assert!(names.contains(&format!("parport.0.pin-{p:02}-in")));
        assert!(!names.contains(&format!("parport.0.pin-{p:02}-out")));
    }
    for p in [1, 14, 16, 17] {
        assert!(names.contains(&format!("parport.0.pin-{p:02}-out")));
    }
    let params: Vec<String> = host
        .instance()
        .params()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .collect();
    assert!(!params.contains(&"parport.0.reset-time".to_string()));
    assert!(!params.contains(&"parport.0.debug1".to_string()));
    run(
        &host,
        1_000_000,
        &["parport.0.read", "parport.0.write", "parport.0.reset"],
    );
    for p in 2..=9u8 {
        sim.set_input(p, false);
        cycles(&sim, 2);
        for q in 2..=9u8 {
            assert_eq!(bit(&host, &format!("parport.0.pin-{q:02}-in")), q != p);
            assert_eq!(bit(&host, &format!("parport.0.pin-{q:02}-in-not")), q == p);
        }
        sim.set_input(p, true);
    }
    set(&host, "parport.0.pin-16-out", true);
    cycles(&sim, 2);
    assert!(sim.level(16));
    assert_eq!(
        sim.control_latch() & regs::CONTROL_DIR_IN,
        regs::CONTROL_DIR_IN
    );
    host.stop();
}

#[test]
fn x_mode_reads_control_lines_through_the_loopback_plug() {
    let host = host("x");
    loadrt(&host, "2_x_simloop").unwrap();
    let sim = sim(&host, 0);
    run(&host, 1_000_000, &["parport.0.read", "parport.0.write"]);
    cycles(&sim, 2);
    // Data D5..D7 and D4 are wired to pins 1, 14, 16, 17; all low now.
    for p in [1, 14, 16, 17] {
        assert!(!bit(&host, &format!("parport.0.pin-{p:02}-in")), "pin {p}");
        assert!(bit(&host, &format!("parport.0.pin-{p:02}-in-not")));
    }
    for (data, ctrl) in [(7, 1), (8, 14), (9, 16), (6, 17)] {
        set(&host, &format!("parport.0.pin-{data:02}-out"), true);
        cycles(&sim, 2);
        assert!(
            bit(&host, &format!("parport.0.pin-{ctrl:02}-in")),
            "{data} -> {ctrl}"
        );
        set(&host, &format!("parport.0.pin-{data:02}-out"), false);
    }
    // The common loopback: data 2..6 to status 15, 13, 12, 10, 11.
    for (data, st) in [(2, 15), (3, 13), (4, 12), (5, 10), (6, 11)] {
        set(&host, &format!("parport.0.pin-{data:02}-out"), true);
        cycles(&sim, 2);
        assert!(
            bit(&host, &format!("parport.0.pin-{st:02}-in")),
            "{data} -> {st}"
        );
        set(&host, &format!("parport.0.pin-{data:02}-out"), false);
        cycles(&sim, 2);
        assert!(
            !bit(&host, &format!("parport.0.pin-{st:02}-in")),
            "{data} -> {st}"
        );
    }
    host.stop();
}

#[test]
fn write_touches_the_hardware_only_on_change() {
    let host = host("change");
    loadrt(&host, "0 sim").unwrap();
    let sim = sim(&host, 0);
    assert!(
        sim.writes().is_empty(),
        "nothing written before the first cycle"
    );
    run(&host, 1_000_000, &["parport.0.read", "parport.0.write"]);
    cycles(&sim, 5);
    let w = sim.writes();
    assert_eq!(w.len(), 2, "first write of each register only: {w:?}");
    assert_eq!((w[0].addr, w[0].value), (0x378, 0x00));
    assert_eq!((w[1].addr, w[1].value), (0x37A, 0x0B));
    set(&host, "parport.0.pin-03-out", true);
    cycles(&sim, 5);
    let w = sim.writes();
    assert_eq!(w.len(), 3, "{w:?}");
    assert_eq!((w[2].addr, w[2].value), (0x378, 0x02));
    host.stop();
}

#[test]
fn read_all_and_write_all_cover_every_port() {
    let host = host("all");
    loadrt(&host, "0 sim 1 in sim 0x3f0 x sim").unwrap();
    let (s0, s1, s2) = (sim(&host, 0), sim(&host, 1), sim(&host, 2));
    run(&host, 1_000_000, &["parport.read-all", "parport.write-all"]);
    set(&host, "parport.0.pin-02-out", true);
    set(&host, "parport.1.pin-01-out", true);
    set(&host, "parport.2.pin-09-out", true);
    s1.set_input(5, false);
    s2.set_input(14, false);
    cycles(&s0, 2);
    cycles(&s2, 2);
    assert!(s0.level(2));
    assert!(s1.level(1));
    assert!(s2.level(9));
    assert!(!bit(&host, "parport.1.pin-05-in"));
    assert!(bit(&host, "parport.1.pin-06-in"));
    assert!(!bit(&host, "parport.2.pin-14-in"));
    assert!(bit(&host, "parport.2.pin-16-in"));
    host.stop();
}

#[test]
fn reset_returns_pins_to_invert_after_reset_time_and_clamps_it() {
    let host = host("reset");
    loadrt(&host, "0 sim").unwrap();
    let sim = sim(&host, 0);
    setp(&host, "parport.0.pin-02-out-reset", Value::Bit(true));
    setp(&host, "parport.0.pin-01-out-reset", Value::Bit(true));
    setp(&host, "parport.0.pin-01-out-invert", Value::Bit(true));
    setp(&host, "parport.0.reset-time", Value::U32(900_000));
    set(&host, "parport.0.pin-02-out", true);
    set(&host, "parport.0.pin-01-out", true);
    set(&host, "parport.0.pin-03-out", true);
    run(
        &host,
        1_000_000,
        &["parport.0.read", "parport.0.write", "parport.0.reset"],
    );
    cycles(&sim, 3);
    host.stop();
    assert_eq!(
        param(&host, "parport.0.reset-time"),
        Value::U32(250_000),
        "clamped to period/4 and written back"
    );
    // Pin 2 went high at each write and back low at each reset; pin 3
    // (no reset) stays high; pin 1 (inverted) returns to high.
    assert!(!sim.level(2));
    assert!(sim.level(3));
    assert!(sim.level(1));
    let data = sim.writes_to(regs::DATA);
    assert!(data.len() >= 4, "{data:?}");
    for pair in data.chunks(2).filter(|c| c.len() == 2) {
        assert_eq!(pair[0].value, 0x03);
        assert_eq!(pair[1].value, 0x02);
        let dt = pair[1].time_ns - pair[0].time_ns;
        assert!(dt >= 250_000, "reset {dt} ns after write");
    }
    let ctrl = sim.writes_to(regs::CONTROL);
    // Pin 1 inverted and TRUE = bit 0 clear; reset sets it back.
    assert!(ctrl.len() >= 2);
    assert_eq!(ctrl[0].value ^ regs::CONTROL_INVERTED, 0x00);
    assert_eq!(ctrl[1].value ^ regs::CONTROL_INVERTED, 0x01);
    assert!(ctrl[1].time_ns - ctrl[0].time_ns >= 250_000);
}

#[test]
fn safe_state_at_unload_drives_inactive_levels() {
    let host = host("safe");
    loadrt(&host, "0 sim 1 in sim").unwrap();
    let (s0, s1) = (sim(&host, 0), sim(&host, 1));
    for p in OUT_PINS {
        set(&host, &format!("parport.0.pin-{p:02}-out"), true);
    }
    for p in [4, 14] {
        setp(
            &host,
            &format!("parport.0.pin-{p:02}-out-invert"),
            Value::Bit(true),
        );
    }
    set(&host, "parport.1.pin-17-out", true);
    run(&host, 1_000_000, &["parport.write-all"]);
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    while s0.writes().is_empty() || s1.writes().len() < 2 {
        assert!(std::time::Instant::now() < end);
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    host.stop();
    assert!(s0.level(2) && s0.level(17));
    host.unloadrt("hal_parport").unwrap();
    for p in OUT_PINS {
        assert_eq!(s0.level(p), p == 4 || p == 14, "pin {p} after unload");
    }
    assert!(!s1.level(17));
    assert_eq!(
        s1.control_latch() & regs::CONTROL_DIR_IN,
        regs::CONTROL_DIR_IN
    );
    assert!(!s0.is_claimed(), "port released at unload");
    drop((s0, s1));
    assert!(hal_parport::sim::find(host.instance().name(), 0).is_none());
}

#[test]
fn every_cfg_form_exports_linuxcnc_names() {
    for (cfg, ports) in [
        ("0 sim", vec!["out"]),
        ("0x378 in sim", vec!["in"]),
        ("sim 0x278", vec![]),
        ("0X3BC E sim", vec!["epp"]),
        ("378_X_SIM", vec!["x"]),
        (
            "0 simloop out 1 sim i 2 sim x 3 EPP sim",
            vec!["out", "in", "x", "epp"],
        ),
        (
            "0 sim 1 sim 2 sim 3 sim 4 sim 5 sim 6 sim 7 sim",
            vec!["out"; 8],
        ),
    ] {
        let host = host("forms");
        let r = loadrt(&host, cfg);
        if ports.is_empty() {
            // "sim" where an address belongs is not an address.
            assert!(r.is_err(), "{cfg}");
            continue;
        }
        r.unwrap_or_else(|e| panic!("{cfg}: {e}"));
        let names = pin_names(&host);
        let functs: Vec<String> = host
            .instance()
            .functs()
            .unwrap()
            .into_iter()
            .map(|f| f.name)
            .collect();
        assert!(functs.contains(&"parport.read-all".to_string()));
        assert!(functs.contains(&"parport.write-all".to_string()));
        for (i, mode) in ports.iter().enumerate() {
            for f in ["read", "write", "reset"] {
                assert!(functs.contains(&format!("parport.{i}.{f}")), "{cfg}: {f}");
            }
            let has = |n: &str| names.contains(&format!("parport.{i}.{n}"));
            let (ins, outs): (Vec<u8>, Vec<u8>) = match *mode {
                "in" => (
                    vec![2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 15],
                    vec![1, 14, 16, 17],
                ),
                "x" => (
                    vec![1, 10, 11, 12, 13, 14, 15, 16, 17],
                    vec![2, 3, 4, 5, 6, 7, 8, 9],
                ),
                _ => (STATUS_PINS.to_vec(), OUT_PINS.to_vec()),
            };
            for p in &ins {
                assert!(has(&format!("pin-{p:02}-in")), "{cfg}: port {i} pin {p} in");
                assert!(has(&format!("pin-{p:02}-in-not")));
                assert!(!has(&format!("pin-{p:02}-out")));
            }
            for p in &outs {
                assert!(
                    has(&format!("pin-{p:02}-out")),
                    "{cfg}: port {i} pin {p} out"
                );
                assert!(!has(&format!("pin-{p:02}-in")));
            }
            if *mode == "epp" {
                assert_eq!(sim(&host, i).ecr(), regs::ECR_EPP_MODE, "{cfg}");
            } else {
                assert_eq!(sim(&host, i).ecr(), 0, "{cfg}");
            }
        }
        assert!(!names
            .iter()
            .any(|n| n.starts_with(&format!("parport.{}.", ports.len()))));
    }
}

#[test]
fn bad_cfg_strings_are_refused_and_nothing_stays_loaded() {
    for (cfg, want) in [
        ("", "no ports configured"),
        ("_ _", "no ports configured"),
        ("zz sim", "bad port address 'zz'"),
        ("0x378 sim 0x37g sim", "bad port address '0x37g'"),
        ("0x sim", "no hex digits"),
        ("0x10000 sim", "larger than 0xffff"),
        ("0 in out sim", "bad port address 'out'"),
        (
            "0 sim 1 sim 2 sim 3 sim 4 sim 5 sim 6 sim 7 sim 8 sim",
            "at most 8",
        ),
        ("0 sim 0 sim", "configured twice"),
        ("0 sim 0x378 sim", "same port as port 0"),
        ("0 sim 0 x ppdev", "configured twice"),
        ("1 sim 0x378 x ppdev", "PPRCONTROL"),
        ("1 sim 0x378 epp ppdev", "ECR"),
        ("1 sim 9 ppdev", "/dev/parport9 does not exist"),
        ("1 sim 0xbeef raw", "raw port I/O"),
    ] {
        let host = host("bad");
        let e = loadrt(&host, cfg).expect_err(cfg).to_string();
        assert!(e.contains(want), "{cfg:?}: {e}");
        assert!(e.contains("hal_parport"), "{e}");
        assert!(host.loaded_modules().is_empty(), "{cfg}");
        assert!(host.loaded_components().is_empty(), "{cfg}");
        assert!(host.instance().pins().unwrap().is_empty(), "{cfg}");
        assert!(host.instance().functs().unwrap().is_empty(), "{cfg}");
        assert!(hal_parport::sim::find(host.instance().name(), 0).is_none());
        // The same instance loads a good cfg afterwards.
        loadrt(&host, "1 sim").unwrap();
    }
}

#[test]
fn one_linux_port_named_twice_is_refused_before_it_is_claimed() {
    // A fake /proc and /dev with parport0 at 0x378. Its node is a plain
    // file, so claiming it would fail (ENOTTY); on a real port the second
    // PPCLAIM of one port blocks forever. The entries must be refused
    // before either is opened, naming both.
    let root = std::env::temp_dir().join(format!("pp-twice-{}", std::process::id()));
    let paths = SysPaths {
        dev: root.join("dev"),
        proc_parport: root.join("proc"),
    };
    std::fs::create_dir_all(paths.proc_parport.join("parport0")).unwrap();
    std::fs::create_dir_all(&paths.dev).unwrap();
    std::fs::write(
        paths.proc_parport.join("parport0").join("base-addr"),
        "888\t1912\n",
    )
    .unwrap();
    std::fs::write(paths.dev.join("parport0"), b"").unwrap();
    for (cfg, first, second) in [
        ("0 0x378", "parport0, out mode", "0x378, out mode"),
        ("0 x 0x378", "parport0, x mode", "0x378, out mode"),
        ("0x378 in 1 sim 0", "0x378, in mode", "parport0, out mode"),
    ] {
        let host = host("twice");
        let e = load_cfg(&host, cfg, &paths, Arc::new(MonotonicClock))
            .expect_err(cfg)
            .to_string();
        assert!(
            e.contains(&format!(
                "({second}): it is the same port as port 0 ({first})"
            )),
            "{cfg}: {e}"
        );
        assert!(e.contains("parport0"), "{cfg}: {e}");
        assert!(!e.contains("PPCLAIM"), "{cfg}: nothing was claimed: {e}");
        assert!(host.loaded_components().is_empty(), "{cfg}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn default_cfg_is_0x0278() {
    let host = host("default");
    let e = host.loadrt(&hal_parport::MODULE, &[] as &[&str]);
    // 0x278 without a Linux port is raw I/O; where ioperm is refused the
    // error names the port, where it works the port loads.
    match e {
        Ok(()) => assert!(host
            .instance()
            .pins()
            .unwrap()
            .iter()
            .any(|p| p.name == "parport.0.pin-02-out")),
        Err(e) => assert!(e.to_string().contains("0x278"), "{e}"),
    }
}
