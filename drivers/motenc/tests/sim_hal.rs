//! `loadrt hal_motenc backend=sim`: every register path through the HAL
//! pins and functions, on simulated boards.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::Arc;

use common::*;
use hal_core::Value;
use hal_driver::sim::{AccessLog, Dir, SimBoard};
use hal_driver::testing::Flaky;
use hal_motenc::board::{identify, BoardKind, Motenc};
use hal_motenc::open::Opened;
use hal_motenc::regs;
use hal_motenc::sim::MotencModel;
use hal_motenc::MODULE;

#[test]
fn linuxcnc_names_functions_and_board_kinds() {
    let host = host("names");
    host.loadrt(&MODULE, &["backend=sim", "sim_boards=100,lite"])
        .unwrap();
    let inst = host.instance();
    let functs: Vec<(String, bool)> = inst
        .functs()
        .unwrap()
        .into_iter()
        .map(|f| (f.name, f.uses_fp))
        .collect();
    for (id, kind) in [(0, BoardKind::Motenc100), (1, BoardKind::MotencLite)] {
        let p = |s: String| format!("motenc.{id}.{s}");
        for k in 0..kind.encoders() {
            for item in ["count", "position", "index", "index-enable", "reset"] {
                inst.pin_value(&p(format!("enc-{k:02}-{item}"))).unwrap();
            }
            inst.param_value(&p(format!("enc-{k:02}-scale"))).unwrap();
        }
        assert!(inst
            .pin_value(&p(format!("enc-{:02}-count", kind.encoders())))
            .is_err());
        for n in 0..8 {
            inst.pin_value(&p(format!("dac-{n:02}-value"))).unwrap();
            inst.pin_value(&p(format!("adc-{n:02}-value"))).unwrap();
            for prm in [
                "dac-{}-offset",
                "dac-{}-gain",
                "adc-{}-offset",
                "adc-{}-gain",
            ] {
                inst.param_value(&p(prm.replace("{}", &format!("{n:02}"))))
                    .unwrap();
            }
        }
        for n in 0..kind.inputs() {
            assert_eq!(
                inst.pin_value(&p(format!("in-{n:02}-not"))).unwrap(),
                Value::Bit(true),
                "-not starts TRUE"
            );
            inst.pin_value(&p(format!("in-{n:02}"))).unwrap();
        }
        assert!(inst
            .pin_value(&p(format!("in-{:02}", kind.inputs())))
            .is_err());
        for n in 0..kind.outputs() {
            inst.pin_value(&p(format!("out-{n:02}"))).unwrap();
            inst.param_value(&p(format!("out-{n:02}-invert"))).unwrap();
        }
        for pin in [
            "estop-in",
            "estop-in-not",
            "watchdog-reset",
            "fault",
            "fault-code",
        ] {
            inst.pin_value(&p(pin.into())).unwrap();
        }
        assert_eq!(
            inst.param_value(&p("watchdog-control".into())).unwrap(),
            Value::U32(0)
        );
        for (f, fp) in [
            ("encoder-read", true),
            ("dac-write", true),
            ("adc-read", true),
            ("digital-in-read", false),
            ("digital-out-write", false),
            ("misc-update", false),
        ] {
            assert!(functs.contains(&(p(f.into()), fp)), "{f}");
        }
        assert_eq!(board(&host, id).with(|m| m.kind()), kind);
    }
}

#[test]
fn counters_count_and_index_enable_zeroes_them_at_the_index() {
    let host = host("index");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host, 0);
    set(&host, "motenc.0.enc-01-scale", Value::Float(4000.0));
    set(&host, "motenc.0.dac-01-value", Value::Float(-1.0));
    run(&host, &["motenc.0.encoder-read", "motenc.0.dac-write"]);
    wait("the motor turns backwards", || {
        s32(&host, "motenc.0.enc-01-count") < -6000
    });
    host.stop();
    let count = s32(&host, "motenc.0.enc-01-count");
    assert_eq!(
        count,
        sim.with(|m| m.counter(1)),
        "read as the board counts"
    );
    assert_eq!(
        float(&host, "motenc.0.enc-01-position"),
        count as f64 / 4000.0
    );
    assert_eq!(
        sim.with(|m| m.axis(0).encoder.count()),
        0,
        "only channel 1 moves"
    );

    set(&host, "motenc.0.enc-01-index-enable", Value::Bit(true));
    host.start().unwrap();
    wait("index-enable falls at the index", || {
        !bit(&host, "motenc.0.enc-01-index-enable")
    });
    wait("the channel is disarmed", || {
        !sim.with(|m| m.index_armed(1))
    });
    host.stop();
    // The board cleared its counter at the index (a multiple of 4000 in
    // shaft counts) and counts on from there; the pin agrees exactly.
    let shaft = sim.with(|m| m.axis(1).encoder.count());
    let since = s32(&host, "motenc.0.enc-01-count");
    assert_eq!(since, sim.with(|m| m.counter(1)));
    assert!(since <= 0 && since > -1000, "{since}");
    assert_eq!((shaft - since as i64).rem_euclid(4000), 0);
    assert!(
        !sim.with(|m| m.index_latched(1)),
        "disarming clears the latch"
    );
    let latched = float(&host, "motenc.0.enc-01-position-latched");
    assert!(
        latched < -1.5,
        "where the index was, from the old zero: {latched}"
    );

    // reset holds the count at 0 while rawcounts goes on.
    set(&host, "motenc.0.enc-01-reset", Value::Bit(true));
    host.start().unwrap();
    let raw0 = s32(&host, "motenc.0.enc-01-rawcounts");
    wait("rawcounts goes on", || {
        s32(&host, "motenc.0.enc-01-rawcounts") < raw0 - 100
    });
    assert_eq!(s32(&host, "motenc.0.enc-01-count"), 0);
    host.stop();
}

#[test]
fn live_index_input_shows_on_its_pin() {
    let host = host("live-index");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host, 0);
    sim.with(|m| {
        m.turn_to(5, 0.5);
        m.turn_to(6, 0.5);
    });
    run(&host, &["motenc.0.encoder-read"]);
    wait("off the index", || !bit(&host, "motenc.0.enc-06-index"));
    sim.with(|m| m.turn_to(6, 1.0));
    wait("on the index", || bit(&host, "motenc.0.enc-06-index"));
    assert!(!bit(&host, "motenc.0.enc-05-index"));
}

#[test]
fn dac_codes_for_volts_offset_and_gain_at_both_ends() {
    let host = host("dac");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host, 0);
    let cases: [(f64, f64, f64, u32); 8] = [
        // value, offset, gain, code
        (10.0, 0.0, 1.0, 0),
        (-10.0, 0.0, 1.0, 0x1FFF),
        (2.5, 0.0, 4.0, 0),
        (3.0, 1.0, -5.0, 0x1FFF),
        (1e6, 0.0, 1.0, 0),
        (0.0, 0.0, 1.0, 0x1000),
        (-2.5, 0.0, 1.0, 5119),
        (1.0, 0.5, 2.0, 3686),
    ];
    for (n, (v, o, g, _)) in cases.iter().enumerate() {
        set(
            &host,
            &format!("motenc.0.dac-{n:02}-value"),
            Value::Float(*v),
        );
        set(
            &host,
            &format!("motenc.0.dac-{n:02}-offset"),
            Value::Float(*o),
        );
        set(
            &host,
            &format!("motenc.0.dac-{n:02}-gain"),
            Value::Float(*g),
        );
    }
    run(&host, &["motenc.0.dac-write"]);
    wait("every code written", || {
        cases
            .iter()
            .enumerate()
            .all(|(n, c)| sim.with(|m| m.dac_code(n)) == c.3)
    });
    host.stop();
    assert!((sim.with(|m| m.dac_volts(6)) + 2.5).abs() < 0.003);
}

#[test]
fn adc_values_after_the_conversion_sequence() {
    let host = host("adc");
    host.loadrt(&MODULE, &["backend=sim", "sim_boards=lite"])
        .unwrap();
    let sim = board(&host, 0);
    let volts = [-4.0, -1.5, 0.0, 0.25, 1.0, 2.0, 3.5, 4.9];
    sim.with(|m| {
        for (n, v) in volts.iter().enumerate() {
            m.set_adc_volts(n, *v);
        }
    });
    set(&host, "motenc.0.adc-03-gain", Value::Float(2.0));
    set(&host, "motenc.0.adc-03-offset", Value::Float(1.0));
    run(&host, &["motenc.0.encoder-read", "motenc.0.adc-read"]);
    let want = |n: usize| {
        let counts = (volts[n] / regs::ADC_VOLTS_PER_COUNT).round();
        let v = counts * regs::ADC_VOLTS_PER_COUNT;
        if n == 3 {
            v * 2.0 - 1.0
        } else {
            v
        }
    };
    wait("every channel read", || {
        (0..8).all(|n| float(&host, &format!("motenc.0.adc-{n:02}-value")) == want(n))
    });
}

/// A simulated MOTENC-100 with an access log, loaded as board 0.
fn logged_board(host: &hal_core::Host) -> Arc<SimBoard<MotencModel>> {
    let sim = Arc::new(
        SimBoard::new(MotencModel::new(BoardKind::Motenc100, 0)).with_log(AccessLog::new(100_000)),
    );
    let id = identify(&*sim).unwrap();
    hal_motenc::hal::load_opened(
        host,
        vec![Opened {
            drv: Motenc::new(sim.clone(), id),
            location: "simulated".into(),
            guard: None,
            sim: Some(sim.clone()),
        }],
    )
    .unwrap();
    sim
}

#[test]
fn adc_commands_and_reads_come_in_the_order_the_board_needs() {
    let host = host("adc-order");
    let sim = logged_board(&host);
    sim.clear_log();
    run(&host, &["motenc.0.encoder-read", "motenc.0.adc-read"]);
    wait("several sweeps", || {
        sim.accesses()
            .iter()
            .filter(|a| a.addr == regs::ADC_START as u64)
            .count()
            >= 6
    });
    host.stop();
    // The ADC traffic only (encoder-read reads statusControl too).
    let adc: Vec<(Dir, u64, u32)> = sim
        .accesses()
        .iter()
        .filter(|a| a.addr == regs::ADC_DATA_COMMAND as u64 || a.addr == regs::ADC_START as u64)
        .map(|a| (a.dir, a.addr, a.value))
        .collect();
    let cmd = regs::ADC_DATA_COMMAND as u64;
    let start = regs::ADC_START as u64;
    assert_eq!(&adc[..2], &[(Dir::Write, cmd, 3), (Dir::Write, start, 1)]);
    let mut expect_cmd = regs::ADC_CMD_CH4_7;
    for chunk in adc[2..].chunks(6).take(4) {
        if chunk.len() < 6 {
            break;
        }
        assert!(
            chunk[..4].iter().all(|a| a.0 == Dir::Read && a.1 == cmd),
            "{chunk:?}"
        );
        assert_eq!(chunk[4], (Dir::Write, cmd, expect_cmd));
        assert_eq!(chunk[5], (Dir::Write, start, 1));
        expect_cmd ^= regs::ADC_CMD_CH0_3 ^ regs::ADC_CMD_CH4_7;
    }
    // Results are read only once the busy bit is clear.
    let log = sim.accesses();
    for (i, a) in log.iter().enumerate() {
        if a.dir == Dir::Read && a.addr == cmd {
            let status = log[..i]
                .iter()
                .rev()
                .find(|b| b.dir == Dir::Read && b.addr == regs::status_control(0) as u64)
                .unwrap();
            assert_eq!(status.value & regs::STATUS_ADC_BUSY, 0);
        }
    }
}

#[test]
fn digital_inputs_active_low_and_outputs_with_invert() {
    let host = host("dio");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host, 0);
    let on = [0usize, 15, 16, 31, 32, 47, 48, 63, 64, 67];
    sim.with(|m| {
        for &n in &on {
            m.set_input(n, true);
        }
        m.set_estop(true);
    });
    set(&host, "motenc.0.out-03", Value::Bit(true));
    set(&host, "motenc.0.out-05-invert", Value::Bit(true));
    set(&host, "motenc.0.out-06", Value::Bit(true));
    set(&host, "motenc.0.out-06-invert", Value::Bit(true));
    set(&host, "motenc.0.out-20", Value::Bit(true));
    run(
        &host,
        &[
            "motenc.0.digital-in-read",
            "motenc.0.digital-out-write",
            "motenc.0.misc-update",
        ],
    );
    wait("inputs read", || bit(&host, "motenc.0.in-67"));
    wait("estop read", || bit(&host, "motenc.0.estop-in"));
    assert!(!bit(&host, "motenc.0.estop-in-not"));
    for n in 0..68 {
        let want = on.contains(&n);
        assert_eq!(
            bit(&host, &format!("motenc.0.in-{n:02}")),
            want,
            "in-{n:02}"
        );
        assert_eq!(bit(&host, &format!("motenc.0.in-{n:02}-not")), !want);
    }
    wait("outputs written", || sim.with(|m| m.output(20)));
    let outs: Vec<usize> = (0..32).filter(|&n| sim.with(|m| m.output(n))).collect();
    assert_eq!(outs, vec![3, 5, 20], "out XOR invert");
    host.stop();
    // Unload: the safe state is `out` FALSE at every output: 5 stays on
    // (inverted), 3 and 20 go off; DACs at 0 V.
    set(&host, "motenc.0.dac-00-value", Value::Float(5.0));
    host.unloadrt("hal_motenc").unwrap();
    let outs: Vec<usize> = (0..32).filter(|&n| sim.with(|m| m.output(n))).collect();
    assert_eq!(outs, vec![5, 6]);
    assert!((0..8).all(|n| sim.with(|m| m.dac_code(n)) == regs::DAC_ZERO));
}

#[test]
fn watchdog_bite_goes_safe_in_the_same_period_and_reset_recovers() {
    let host = host("watchdog");
    let sim = logged_board(&host);
    set(&host, "motenc.0.watchdog-control", Value::U32(20));
    set(&host, "motenc.0.out-02", Value::Bit(true));
    set(&host, "motenc.0.dac-00-value", Value::Float(3.0));
    run(
        &host,
        &[
            "motenc.0.misc-update",
            "motenc.0.encoder-read",
            "motenc.0.dac-write",
            "motenc.0.digital-out-write",
        ],
    );
    wait("running", || {
        sim.with(|m| m.output(2) && m.watchdog_control() == 20)
    });
    std::thread::sleep(std::time::Duration::from_millis(30));
    assert!(!bit(&host, "motenc.0.fault"), "DAC writes keep it fed");
    host.delf("motenc.0.dac-write", None).unwrap();
    wait("the fault", || bit(&host, "motenc.0.fault"));
    host.stop();
    assert_eq!(get(&host, "motenc.0.fault-code"), Value::U32(3));
    let bit_at = sim.with(|m| m.watchdog_bitten_at()).expect("the board bit");
    // The driver found it in the same period and wrote its safe state
    // at that very board time: DAC 0 to 0 V, output 2 off.
    let log = sim.accesses();
    let dac0 = |a: &&hal_driver::sim::Access| a.dir == Dir::Write && a.addr == regs::dac(0) as u64;
    let last_drive = log
        .iter()
        .rposition(|a| dac0(&a) && a.value != regs::DAC_ZERO)
        .unwrap();
    let safe_dac = log[last_drive..]
        .iter()
        .find(|a| dac0(a) && a.value == regs::DAC_ZERO)
        .expect("DAC 0 written to 0 V");
    assert_eq!(safe_dac.time_ns, bit_at);
    let safe_out = log
        .iter()
        .rev()
        .find(|a| a.dir == Dir::Write && a.addr == regs::digital_io(0) as u64)
        .unwrap();
    assert_eq!((safe_out.time_ns, safe_out.value & 4), (bit_at, 4));
    let said = log_lines(&host);
    assert!(
        said.iter()
            .any(|l| l.starts_with("motenc.0 (MOTENC-100 simulated): watchdog bit")),
        "{said:?}"
    );
    // watchdog-reset restarts the board's watchdog and clears the fault.
    host.addf("motenc.0.dac-write", "servo", -1).unwrap();
    set(&host, "motenc.0.watchdog-reset", Value::Bit(true));
    host.start().unwrap();
    wait("recovered", || {
        !bit(&host, "motenc.0.fault") && sim.with(|m| !m.watchdog_bitten() && m.output(2))
    });
    assert!(!bit(&host, "motenc.0.watchdog-reset"), "self-clearing");
    wait("DAC back", || {
        (sim.with(|m| m.dac_volts(0)) - 3.0).abs() < 0.01
    });
}

#[test]
fn a_board_that_goes_away_is_reported_and_left_alone() {
    let host = host("gone");
    host.loadrt(&MODULE, &["backend=sim", "sim_ids=2"]).unwrap();
    let sim = board(&host, 2);
    run(
        &host,
        &[
            "motenc.2.encoder-read",
            "motenc.2.dac-write",
            "motenc.2.digital-out-write",
        ],
    );
    std::thread::sleep(std::time::Duration::from_millis(10));
    sim.with(|m| m.unplug());
    wait("the fault", || bit(&host, "motenc.2.fault"));
    assert_eq!(get(&host, "motenc.2.fault-code"), Value::U32(1));
    let said = log_lines(&host);
    assert!(
        said.iter()
            .any(|l| l.starts_with("motenc.2 (MOTENC-100 simulated): board stopped answering")),
        "{said:?}"
    );
    // It stays faulted when the board comes back: outputs stay as the
    // safe state left them.
    set(&host, "motenc.2.dac-03-value", Value::Float(4.0));
    sim.with(|m| m.plug());
    std::thread::sleep(std::time::Duration::from_millis(20));
    assert!(bit(&host, "motenc.2.fault"));
    assert_eq!(sim.with(|m| m.dac_code(3)), regs::DAC_ZERO);
}

#[test]
fn counters_that_cannot_be_read_back_trip_the_fault() {
    let host = host("readback");
    let sim = Arc::new(SimBoard::new(MotencModel::new(BoardKind::Motenc100, 1)));
    // The counters of FPGA 0 fail to read once told to.
    let bus = Arc::new(Flaky::new(sim.clone(), |off| off < 0x10));
    let id = identify(&*bus).unwrap();
    hal_motenc::hal::load_opened(
        &host,
        vec![Opened {
            drv: Motenc::new(bus.clone(), id),
            location: "on a flaky bus".into(),
            guard: None,
            sim: Some(sim.clone()),
        }],
    )
    .unwrap();
    set(&host, "motenc.1.dac-00-value", Value::Float(2.0));
    run(&host, &["motenc.1.encoder-read", "motenc.1.dac-write"]);
    wait("driving", || sim.with(|m| m.dac_volts(0)) > 1.9);
    bus.set_failing(true);
    wait("the fault", || bit(&host, "motenc.1.fault"));
    assert_eq!(get(&host, "motenc.1.fault-code"), Value::U32(2));
    assert_eq!(sim.with(|m| m.dac_code(0)), regs::DAC_ZERO);
    let said = log_lines(&host);
    assert!(
        said.iter().any(|l| l
            == "motenc.1 (MOTENC-100 on a flaky bus): encoder counters could not be read back \
                (a bus access failed): DACs set to 0 V, outputs off"),
        "{said:?}"
    );
}

#[test]
fn several_boards_with_clashing_jumpers() {
    let host = host("several");
    host.rt_log().set_level(hal_core::MsgLevel::Warn);
    host.loadrt(
        &MODULE,
        &["backend=sim", "sim_boards=100,lite,100", "sim_ids=1,1,0"],
    )
    .unwrap();
    assert_eq!(board(&host, 1).with(|m| m.kind()), BoardKind::Motenc100);
    assert_eq!(board(&host, 0).with(|m| m.kind()), BoardKind::MotencLite);
    assert_eq!(board(&host, 2).with(|m| m.kind()), BoardKind::Motenc100);
    let said = log_lines(&host);
    assert!(
        said.iter()
            .any(|l| l.contains("board 1 (simulated) has ID jumpers 1")
                && l.ends_with("it is motenc.0")),
        "{said:?}"
    );
    // Each board runs on its own.
    set(&host, "motenc.2.dac-07-value", Value::Float(-1.0));
    set(&host, "motenc.0.out-15", Value::Bit(true));
    run(&host, &["motenc.2.dac-write", "motenc.0.digital-out-write"]);
    wait("board 2's DAC", || {
        board(&host, 2).with(|m| m.dac_code(7)) == regs::dac_code(-1.0)
    });
    wait("board 0's output", || {
        board(&host, 0).with(|m| m.output(15))
    });
    assert_eq!(board(&host, 1).with(|m| m.dac_code(7)), regs::DAC_ZERO);
}

#[test]
fn bad_parameters_load_nothing() {
    let host = host("badparams");
    for (args, want) in [
        (
            &["backend=isa"][..],
            "hal_motenc: parameter 'backend': 'isa' is not one of pci|sim",
        ),
        (
            &["sim_boards=lite"],
            "hal_motenc: parameter 'sim_boards': only with backend=sim",
        ),
        (
            &["backend=sim", "sim_boards=lite,3000"],
            "hal_motenc: parameter 'sim_boards': item 1 \"3000\": not a board kind: 100 or lite",
        ),
        (
            &["backend=sim", "sim_ids=-1"],
            "hal_motenc: parameter 'sim_ids': item 0 \"-1\": out of range (0..=3)",
        ),
        (
            &["backend=sim", "sim_boards=100,100,100,100,100"],
            "hal_motenc: parameter 'sim_boards': can only take 4 arguments",
        ),
        (
            &["bogus=1"],
            "hal_motenc: parameter 'bogus': unknown parameter (hal_motenc takes backend, sim_boards, sim_ids)",
        ),
    ] {
        let e = host.loadrt(&MODULE, args).unwrap_err().to_string();
        assert_eq!(e, want, "{args:?}");
        assert!(
            host.loaded_components().is_empty(),
            "{args:?} left something"
        );
        assert!(host.loaded_modules().is_empty());
    }
    // This machine has no MOTENC: the PCI backend says so, loads nothing.
    let e = host
        .loadrt(&MODULE, &[] as &[&str])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no MOTENC (10b5:3001) found on the PCI bus"),
        "{e}"
    );
    assert!(host.loaded_components().is_empty());
}

#[test]
fn counts_made_between_load_and_the_first_read_are_kept() {
    let host = host("first-read");
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let sim = board(&host, 0);
    sim.with(|m| m.turn_to(3, -0.5));
    run(&host, &["motenc.0.encoder-read"]);
    wait("the count", || s32(&host, "motenc.0.enc-03-count") == -2000);
}
