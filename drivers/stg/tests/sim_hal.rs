//! `loadrt hal_stg backend=sim`: every register path through the HAL
//! pins and functions, on simulated Model I and Model II boards.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::Arc;

use common::*;
use hal_core::Value;
use hal_driver::sim::{AccessLog, Dir, SimBoard, SimClock, Width};
use hal_driver::testing::Flaky;
use hal_stg::detect::Model;
use hal_stg::dio::Dio;
use hal_stg::driver::Stg;
use hal_stg::open::Opened;
use hal_stg::regs;
use hal_stg::sim::StgModel;
use hal_stg::MODULE;

#[test]
fn linuxcnc_names_functions_and_dio_numbering() {
    let host = host("names");
    host.loadrt(&MODULE, &["backend=sim", "num_chan=4", "dio=IOIO"])
        .unwrap();
    let inst = host.instance();
    for k in 0..4 {
        for pin in [
            "counts",
            "position",
            "index-enable",
            "index-latch",
            "dac-value",
            "adc-value",
        ] {
            inst.pin_value(&format!("stg.{k}.{pin}")).unwrap();
        }
        for prm in [
            "position-scale",
            "dac-offset",
            "dac-gain",
            "adc-offset",
            "adc-gain",
        ] {
            inst.param_value(&format!("stg.{k}.{prm}")).unwrap();
        }
        assert!(
            inst.pin_value(&format!("stg.{k}.index-polarity")).is_err(),
            "Model I only"
        );
    }
    assert!(inst.pin_value("stg.4.counts").is_err());
    for n in 0..16 {
        inst.pin_value(&format!("stg.in-{n:02}")).unwrap();
        assert_eq!(
            inst.pin_value(&format!("stg.in-{n:02}-not")).unwrap(),
            Value::Bit(true)
        );
        inst.pin_value(&format!("stg.out-{n:02}")).unwrap();
        inst.param_value(&format!("stg.out-{n:02}-invert")).unwrap();
    }
    assert!(inst.pin_value("stg.in-16").is_err());
    let functs: Vec<(String, bool)> = inst
        .functs()
        .unwrap()
        .into_iter()
        .map(|f| (f.name, f.uses_fp))
        .collect();
    for f in [
        ("stg.capture-position", true),
        ("stg.write-dacs", true),
        ("stg.read-adcs", true),
        ("stg.di-read", false),
        ("stg.do-write", false),
    ] {
        assert!(functs.contains(&(f.0.to_string(), f.1)), "{f:?}");
    }
    host.unloadrt("hal_stg").unwrap();
    host.loadrt(&MODULE, &["backend=sim", "model=1"]).unwrap();
    assert_eq!(
        host.instance().pin_value("stg.7.index-polarity").unwrap(),
        Value::Bit(true)
    );
    assert_eq!(board(&host).with(|m| m.model()), Model::One);
}

/// Counts on `k`, then arms its index and waits until the driver takes
/// it; the count is then exactly the board's count since the index.
fn index_homes(model: &str, k: usize) {
    let host = host(&format!("index-{}", model.replace('=', "")));
    host.loadrt(&MODULE, &["backend=sim", model]).unwrap();
    let sim = board(&host);
    set(
        &host,
        &format!("stg.{k}.position-scale"),
        Value::Float(4000.0),
    );
    set(&host, &format!("stg.{k}.dac-value"), Value::Float(1.0));
    run(&host, &["stg.capture-position", "stg.write-dacs"]);
    let counts = |h: &hal_core::Host| s32(h, &format!("stg.{k}.counts"));
    wait("the motor turns", || counts(&host) > 3000);
    host.stop();
    assert_eq!(counts(&host) as u32, sim.with(|m| m.counter(k)));
    assert_eq!(
        float(&host, &format!("stg.{k}.position")),
        counts(&host) as f64 / 4000.0
    );
    set(&host, &format!("stg.{k}.index-enable"), Value::Bit(true));
    host.start().unwrap();
    wait("index-enable falls at the index", || {
        !bit(&host, &format!("stg.{k}.index-enable"))
    });
    host.stop();
    let (cntr, ol) = sim.with(|m| (m.counter(k), m.output_latch(k)));
    let since = counts(&host);
    assert!((0..1000).contains(&since), "{model}: {since}");
    let shaft = sim.with(|m| m.axis(k).encoder.count());
    // The index is every 4000 shaft counts; the count is from there.
    assert_eq!((shaft - since as i64).rem_euclid(4000), 0, "{model}");
    assert_eq!(cntr, ol, "each capture latches CNTR into OL");
    let latched = float(&host, &format!("stg.{k}.position-latched"));
    assert!(latched >= 1.0, "{model}: where the index was: {latched}");
}

#[test]
fn model2_index_enable_zeroes_the_count_at_the_index() {
    index_homes("model=2", 5);
}

#[test]
fn model1_index_enable_zeroes_the_count_at_the_index() {
    index_homes("model=1", 2);
}

#[test]
fn model1_watches_the_pair_of_an_armed_axis_with_its_polarity() {
    let host = host("model1-pairs");
    host.loadrt(&MODULE, &["backend=sim", "model=1"]).unwrap();
    let sim = board(&host);
    sim.with(|m| m.turn_to(7, 0.5));
    set(&host, "stg.7.index-enable", Value::Bit(true));
    set(&host, "stg.7.index-polarity", Value::Bit(false));
    run(&host, &["stg.capture-position"]);
    // Active-low level: leaving the index (the line is active off it)
    // latches at once, the shaft being off the index.
    wait("taken", || !bit(&host, "stg.7.index-enable"));
    // The watch went to pair 3 at the low level, and stays there.
    assert_eq!(sim.with(|m| m.intc()) & 0x70, 0x30);
    std::thread::sleep(std::time::Duration::from_millis(5));
    assert_eq!(sim.with(|m| m.intc()) & 0x70, 0x30);
}

#[test]
fn a_counter_wrapping_24_bits_is_extended() {
    let host = host("wrap");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host);
    run(&host, &["stg.capture-position"]);
    wait("a first capture", || sim.now_ns() > 0);
    // Across the 24-bit boundary in steps the driver can follow.
    for i in 1..=12 {
        let target = -(i as f64) * 400.0; // revolutions: 1.6 M counts each
        sim.with(|m| m.turn_to(0, target));
        let want = (target * 4000.0) as i64;
        wait("followed", || {
            let raw = float(&host, "stg.0.position");
            raw == want as f64
        });
    }
    // 12 x 1.6 M counts back: past what 24 bits hold, which the board's
    // own counter shows.
    let board = sim.with(|m| m.counter(0)) as i32;
    let board = (board << 8) >> 8;
    assert_eq!(float(&host, "stg.0.position"), -19_200_000.0);
    assert_eq!(board, -19_200_000 + (1 << 24));
}

#[test]
fn dac_words_for_volts_offset_and_gain_at_both_ends() {
    let host = host("dac");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host);
    let cases: [(f64, f64, f64, u16); 8] = [
        (10.0, 0.0, 1.0, 0xE000),
        (-10.0, 0.0, 1.0, 0xFFFF),
        (2.5, 0.0, 4.0, 0xE000),
        (3.0, 1.0, -5.0, 0xFFFF),
        (-1e6, 0.0, 1.0, 0xFFFF),
        (0.0, 0.0, 1.0, 0xF000),
        (2.5, 0.0, 1.0, 0xEC00),
        (1.0, 0.5, 2.0, regs::dac_code(1.0)),
    ];
    for (n, (v, o, g, _)) in cases.iter().enumerate() {
        set(&host, &format!("stg.{n}.dac-value"), Value::Float(*v));
        set(&host, &format!("stg.{n}.dac-offset"), Value::Float(*o));
        set(&host, &format!("stg.{n}.dac-gain"), Value::Float(*g));
    }
    run(&host, &["stg.write-dacs"]);
    wait("every word written", || {
        cases
            .iter()
            .enumerate()
            .all(|(n, c)| sim.with(|m| m.dac_word(n)) == c.3)
    });
    assert_eq!(sim.with(|m| m.dac_volts(0)), 10.0);
    assert!((sim.with(|m| m.dac_volts(1)) + 10.0).abs() < 0.003);
    assert_eq!(sim.with(|m| m.dac_volts(5)), 0.0);
}

/// A simulated board with an access log, loaded with `num_chan`.
fn logged(
    host: &hal_core::Host,
    model: Model,
    num_chan: usize,
    dio: &str,
) -> Arc<SimBoard<StgModel>> {
    let sim =
        Arc::new(SimBoard::new(StgModel::new(model, 0x220)).with_log(AccessLog::new(200_000)));
    let drv = Stg::new(
        sim.clone(),
        0x220,
        model,
        Dio::parse(dio).unwrap(),
        Arc::new(SimClock::new(0, 1_000)),
    );
    drv.init();
    hal_stg::hal::load_opened(
        host,
        Opened {
            drv,
            sim: Some(sim.clone()),
            warning: None,
        },
        num_chan,
    )
    .unwrap();
    sim
}

#[test]
fn adc_round_robin_covers_exactly_the_exported_channels() {
    for model in [Model::One, Model::Two] {
        let host = host(&format!("adc-{model:?}"));
        let sim = logged(&host, model, 3, "IIOO");
        let volts = [-7.5, 0.5, 9.0, 4.0];
        sim.with(|m| {
            for (n, v) in volts.iter().enumerate() {
                m.set_adc_volts(n, *v);
            }
        });
        set(&host, "stg.2.adc-gain", Value::Float(0.5));
        set(&host, "stg.2.adc-offset", Value::Float(-1.0));
        sim.clear_log();
        run(&host, &["stg.capture-position", "stg.read-adcs"]);
        let want = |n: usize| {
            let v = (volts[n] / regs::ADC_VOLTS_PER_COUNT).round() * regs::ADC_VOLTS_PER_COUNT;
            if n == 2 {
                v * 0.5 + 1.0
            } else {
                v
            }
        };
        wait("every channel", || {
            (0..3).all(|n| float(&host, &format!("stg.{n}.adc-value")) == want(n))
        });
        wait("two sweeps", || {
            sim.accesses()
                .iter()
                .filter(|a| a.width == Width::Word && a.dir == Dir::Write)
                .count()
                >= 7
        });
        host.stop();
        // Conversions start on 0, 1, 2, 0, 1, 2, ...: never on channel 3
        // (LinuxCNC's driver started one on channel num_chan each sweep).
        let log = sim.accesses();
        let adc = |a: &&hal_driver::sim::Access| {
            a.width == Width::Word && (0x630..0x640).contains(&a.addr)
        };
        assert!(
            log.iter().filter(adc).all(|a| a.addr < 0x630 + 6),
            "{model}"
        );
        let started: Vec<usize> = match model {
            Model::One => log
                .iter()
                .filter(|a| adc(a) && a.dir == Dir::Write)
                .map(|a| ((a.addr - 0x630) / 2) as usize)
                .collect(),
            Model::Two => log
                .iter()
                .filter(|a| a.dir == Dir::Write && a.addr == 0x621)
                .map(|a| ((a.value >> 4) & 7) as usize)
                .collect(),
        };
        assert!(started.len() >= 6, "{model}: {started:?}");
        for (i, ch) in started.iter().enumerate() {
            assert_eq!(*ch, i % 3, "{model}: {started:?}");
        }
    }
}

#[test]
fn digital_inputs_read_low_as_true_and_outputs_invert() {
    for model in ["model=1", "model=2"] {
        let host = host(&format!("dio-{}", model.replace('=', "")));
        host.loadrt(&MODULE, &["backend=sim", model, "dio=IOOI"])
            .unwrap();
        let sim = board(&host);
        // Ports A and D are inputs: in-00..07 and in-08..15.
        sim.with(|m| {
            m.set_port_lines(0, 0b1111_1110); // A0 low
            m.set_port_lines(3, 0b0111_1111); // D7 low
        });
        set(&host, "stg.out-01", Value::Bit(true)); // B1
        set(&host, "stg.out-09-invert", Value::Bit(true)); // C1
        set(&host, "stg.out-15", Value::Bit(true));
        set(&host, "stg.out-15-invert", Value::Bit(true)); // C7 stays low
        run(&host, &["stg.di-read", "stg.do-write"]);
        wait("inputs", || bit(&host, "stg.in-15"));
        for n in 0..16 {
            let low = n == 0 || n == 15;
            assert_eq!(
                bit(&host, &format!("stg.in-{n:02}")),
                low,
                "{model} in-{n:02}"
            );
            assert_eq!(bit(&host, &format!("stg.in-{n:02}-not")), !low);
        }
        wait("outputs", || sim.with(|m| m.port_output(1)) == Some(0b10));
        assert_eq!(sim.with(|m| m.port_output(2)), Some(0b10));
        host.stop();
        host.unloadrt("hal_stg").unwrap();
        // The safe state: every output at its `out` FALSE level.
        assert_eq!(sim.with(|m| m.port_output(1)), Some(0));
        assert_eq!(sim.with(|m| m.port_output(2)), Some(0b1000_0010));
        assert!((0..8).all(|n| sim.with(|m| m.dac_word(n)) == regs::DAC_ZERO));
    }
}

#[test]
fn no_access_outside_the_board_and_none_to_port_0x0a_or_0x80() {
    for model in [Model::One, Model::Two] {
        let host = host(&format!("stray-{model:?}"));
        let sim = logged(&host, model, 8, "IIOO");
        set(&host, "stg.1.index-enable", Value::Bit(true));
        set(&host, "stg.0.dac-value", Value::Float(3.0));
        run(
            &host,
            &[
                "stg.capture-position",
                "stg.read-adcs",
                "stg.di-read",
                "stg.write-dacs",
                "stg.do-write",
            ],
        );
        std::thread::sleep(std::time::Duration::from_millis(30));
        host.stop();
        host.unload("hal_stg").unwrap();
        let log = sim.accesses();
        assert!(log.len() > 100);
        let inside = |p: u64| (0x220..0x240).contains(&p) || (0x620..0x640).contains(&p);
        assert!(log.iter().all(|a| inside(a.addr)), "{model}");
        assert_eq!(sim.with(|m| m.stray_accesses()), 0);
        if model == Model::One {
            assert!(log
                .iter()
                .any(|a| a.dir == Dir::Write && a.addr == 0x629 && a.value == 0x0A));
        }
    }
}

#[test]
fn a_board_that_goes_away_is_reported_and_left_alone() {
    for model in ["model=1", "model=2"] {
        let host = host(&format!("gone-{}", model.replace('=', "")));
        host.loadrt(&MODULE, &["backend=sim", model, "base=0x280"])
            .unwrap();
        let sim = board(&host);
        set(&host, "stg.0.dac-value", Value::Float(2.0));
        run(&host, &["stg.capture-position", "stg.write-dacs"]);
        wait("driving", || sim.with(|m| m.dac_volts(0)) > 1.9);
        sim.with(|m| m.unplug());
        wait("the fault", || bit(&host, "stg.fault"));
        assert_eq!(get(&host, "stg.fault-code"), Value::U32(1));
        let m = if model == "model=1" {
            "Model I"
        } else {
            "Model II"
        };
        let said = log_lines(&host);
        let want = format!("stg ({m} at 0x280, simulated): board stopped answering");
        assert!(said.iter().any(|l| l.starts_with(&want)), "{said:?}");
        sim.with(|m| m.plug());
        std::thread::sleep(std::time::Duration::from_millis(20));
        assert!(bit(&host, "stg.fault"), "stays faulted");
        assert!(
            sim.with(|m| m.dac_volts(0)) > 1.9,
            "nothing written once gone"
        );
    }
}

#[test]
fn counters_that_cannot_be_read_back_trip_the_fault() {
    let host = host("readback");
    let sim = Arc::new(SimBoard::new(StgModel::new(Model::Two, 0x220)));
    // The counter data ports of the board at 0x220 fail once told to.
    let bus = Arc::new(Flaky::new(sim.clone(), |port| {
        (0x220..0x230).contains(&port)
    }));
    let drv = Stg::new(
        bus.clone(),
        0x220,
        Model::Two,
        Dio::parse("IIOO").unwrap(),
        Arc::new(SimClock::new(0, 1_000)),
    );
    drv.init();
    hal_stg::hal::load_opened(
        &host,
        Opened {
            drv,
            sim: Some(sim.clone()),
            warning: None,
        },
        8,
    )
    .unwrap();
    set(&host, "stg.3.dac-value", Value::Float(-4.0));
    set(&host, "stg.out-02", Value::Bit(true));
    run(
        &host,
        &["stg.capture-position", "stg.write-dacs", "stg.do-write"],
    );
    wait("driving", || {
        sim.with(|m| m.dac_volts(3)) < -3.9 && m_out(&sim) == Some(0b100)
    });
    bus.set_failing(true);
    wait("the fault", || bit(&host, "stg.fault"));
    assert_eq!(get(&host, "stg.fault-code"), Value::U32(2));
    assert_eq!(
        sim.with(|m| m.dac_word(3)),
        regs::DAC_ZERO,
        "safe in that same call"
    );
    assert_eq!(m_out(&sim), Some(0), "outputs off");
    let said = log_lines(&host);
    assert!(
        said.iter().any(|l| l
            == "stg (Model II at 0x220, simulated): encoder counters could not be read back (a \
                port access failed): DACs set to 0 V, outputs off"),
        "{said:?}"
    );
}

/// Port C's output levels.
fn m_out(sim: &SimBoard<StgModel>) -> Option<u8> {
    sim.with(|m| m.port_output(2))
}

#[test]
fn bad_parameters_load_nothing() {
    let host = host("badparams");
    for (args, want) in [
        (&["base=0x378"][..], "hal_stg: parameter 'base': 0x378 is not a Servo-To-Go base address (0x200, 0x220, ... 0x3e0; 0 searches them)"),
        (&["model=5"], "hal_stg: parameter 'model': 5 is out of range (0..=2)"),
        (&["num_chan=9"], "hal_stg: parameter 'num_chan': 9 is out of range (1..=8)"),
        (&["dio=IIOOX"], "hal_stg: parameter 'dio': \"IIOOX\" is not 4 letters, one per port A, B, C, D (e.g. \"IIOO\")"),
        (&["dio=IIOQ"], "hal_stg: parameter 'dio': port D: 'Q' is neither I (input) nor O (output)"),
        (&["backend=raw"], "hal_stg: parameter 'backend': 'raw' is not one of ioperm|devport|sim"),
        (&["backend=sim", "num_chan=x"], "hal_stg: parameter 'num_chan': 'x' is not a number"),
    ] {
        let e = host.loadrt(&MODULE, args).unwrap_err().to_string();
        assert_eq!(e, want, "{args:?}");
        assert!(host.loaded_components().is_empty(), "{args:?} left something");
    }
    let e = host
        .loadrt(&MODULE, &["backend=devport", "base=0x300"])
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("hal_stg: backend=devport cannot drive a Servo-To-Go"),
        "{e}"
    );
    assert!(host.loaded_components().is_empty());
}
