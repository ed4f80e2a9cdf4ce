//! `loadrt hal_ppmc sim=...`: LinuxCNC's names, the options, and every
//! board's register path through the HAL pins and functions, on
//! simulated buses.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;

use hal_core::{Host, Value};
use hal_driver::sim::SimBoard;
use hal_driver::testing::{bit, float, host, s32, set, value, wait};
use hal_ppmc::regs::{dac, stepgen, uxc};
use hal_ppmc::sim::PpmcPort;
use hal_ppmc::MODULE;

/// The simulated port of bus `n`.
fn port(host: &Host, n: usize) -> Arc<SimBoard<PpmcPort>> {
    hal_driver::sim::find(host.instance().name(), &format!("ppmc.{n}")).expect("no simulated bus")
}

/// Runs the bus's functions in a 1 ms thread.
fn run(host: &Host, functs: &[&str]) {
    hal_driver::testing::run(host, "servo", 1_000_000, functs);
}

fn has_pin(host: &Host, name: &str) -> bool {
    host.instance().pin_value(name).is_ok()
}

fn has_param(host: &Host, name: &str) -> bool {
    host.instance().param_value(name).is_ok()
}

#[test]
fn a_ppmc_set_has_linuxcncs_names() {
    let host = host("ppmc-names");
    host.loadrt(&MODULE, &["sim=ppmc"]).unwrap();
    for n in 0..4 {
        for pin in [
            "position",
            "count",
            "delta",
            "velocity",
            "index",
            "index-enable",
        ] {
            assert!(
                has_pin(&host, &format!("ppmc.0.encoder.{n:02}.{pin}")),
                "{pin}"
            );
        }
        assert!(has_param(&host, &format!("ppmc.0.encoder.{n:02}.scale")));
        assert!(!has_param(
            &host,
            &format!("ppmc.0.encoder.{n:02}.min-speed-estimate")
        ));
        assert!(has_pin(&host, &format!("ppmc.0.DAC.{n:02}.value")));
        assert!(has_param(&host, &format!("ppmc.0.DAC.{n:02}.scale")));
    }
    assert!(!has_pin(&host, "ppmc.0.encoder.04.count"));
    for n in 0..16 {
        assert!(has_pin(&host, &format!("ppmc.0.din.{n:02}.in")));
        assert_eq!(
            value(&host, &format!("ppmc.0.din.{n:02}.in-not")),
            Value::Bit(true)
        );
    }
    for n in 0..8 {
        assert!(has_pin(&host, &format!("ppmc.0.dout.{n:02}.out")));
        assert!(has_param(&host, &format!("ppmc.0.dout.{n:02}.invert")));
    }
    for name in [
        "din.estop.in",
        "din.estop.in-not",
        "din.fault.in",
        "din.fault.in-not",
        "dout.Estop.out",
        "fault",
    ] {
        assert!(has_pin(&host, &format!("ppmc.0.{name}")), "{name}");
    }
    assert!(has_param(&host, "ppmc.0.dout.Estop.invert"));
    let functs: Vec<(String, bool)> = host
        .instance()
        .functs()
        .unwrap()
        .into_iter()
        .map(|f| (f.name, f.uses_fp))
        .collect();
    assert!(functs.contains(&("ppmc.0.read".into(), true)));
    assert!(functs.contains(&("ppmc.0.write".into(), true)));
}

#[test]
fn usc_and_upc_names_and_numbering_across_boards() {
    let host = host("uxc-names");
    host.loadrt(
        &MODULE,
        &[
            "sim=usc+upc",
            "extradout=0x00",
            "extradac=0x02",
            "timestamp=0x02",
        ],
    )
    .unwrap();
    for name in ["setup-time-ns", "pulse-width-ns", "pulse-space-min-ns"] {
        assert!(
            has_param(&host, &format!("ppmc.0.stepgen.00-03.{name}")),
            "{name}"
        );
    }
    assert_eq!(
        value(&host, "ppmc.0.stepgen.00-03.setup-time-ns"),
        Value::U32(10_000)
    );
    for n in 0..4 {
        for pin in ["enable", "velocity"] {
            assert!(has_pin(&host, &format!("ppmc.0.stepgen.{n:02}.{pin}")));
            assert!(has_pin(
                &host,
                &format!(
                    "ppmc.0.pwm.{n:02}.{pin_pwm}",
                    pin_pwm = if pin == "velocity" { "value" } else { pin }
                )
            ));
        }
        for prm in ["scale", "max-vel", "freq"] {
            assert!(
                has_param(&host, &format!("ppmc.0.stepgen.{n:02}.{prm}")),
                "{prm}"
            );
        }
        for prm in ["scale", "max-dc", "min-dc", "duty-cycle", "bootstrap"] {
            assert!(
                has_param(&host, &format!("ppmc.0.pwm.{n:02}.{prm}")),
                "{prm}"
            );
        }
    }
    assert!(has_param(&host, "ppmc.0.pwm.00-03.freq"));
    // USC: encoders 00..03, inputs 00..15, outputs 00..07 and its extra
    // port's 08..15; then the UPC's encoders 04..07 (timestamped),
    // inputs 16..31, outputs 16..23, and its spindle DAC.
    assert!(has_param(&host, "ppmc.0.dout.07-invert"));
    assert!(
        has_param(&host, "ppmc.0.dout.08.invert"),
        "extra port outputs"
    );
    assert!(has_param(&host, "ppmc.0.dout.15.invert"));
    assert!(has_param(&host, "ppmc.0.dout.16-invert"));
    assert!(has_pin(&host, "ppmc.0.din.31.in"));
    assert!(has_pin(&host, "ppmc.0.DAC8.00.value"));
    assert!(has_param(&host, "ppmc.0.DAC8.00.scale"));
    assert!(has_param(&host, "ppmc.0.encoder.07.min-speed-estimate"));
    assert!(!has_param(&host, "ppmc.0.encoder.03.min-speed-estimate"));
}

#[test]
fn options_that_name_no_suitable_board_fail_the_load() {
    let host = host("options");
    for (args, want) in [
        (&["sim=upc:1", "extradac=0x00"][..], "hal_ppmc: extradac=0x00: the board at slot 0 of bus 0 is a Universal PWM Controller revision 1, which has no extra port (every USC has one; a UPC from revision 2)"),
        (&["sim=upc", "extradac=0x00", "extradout=0x00"], "hal_ppmc: extradac=0x00: extradout names the same board: its extra port is one or the other"),
        (&["sim=upc:3", "timestamp=0x00"], "hal_ppmc: timestamp=0x00: the board at slot 0 of bus 0 is a Universal PWM Controller revision 3, whose firmware has no encoder timestamps (an encoder board or UPC of revision 4 or later has them)"),
        (&["sim=usc", "extradac=0x01"], "hal_ppmc: extradac=0x01: no board starts at slot 1 of bus 0 (it should be a USC or UPC)"),
        (&["sim=ppmc", "enc_clock=0x502"], "hal_ppmc: enc_clock=0x502: the board at slot 2 of bus 0 is a PPMC DAC board revision 1, whose filter clock cannot be set (an encoder board of revision 4 or later)"),
        (&["sim=dac+dac", "timestamp=0x00"], "hal_ppmc: timestamp=0x00: the board at slot 0 of bus 0 is a PPMC DAC board revision 1, whose firmware has no encoder timestamps (an encoder board or UPC of revision 4 or later has them)"),
    ] {
        let e = host.loadrt(&MODULE, args).unwrap_err().to_string();
        assert_eq!(e, want, "{args:?}");
        assert!(host.loaded_modules().is_empty(), "{args:?} left something loaded");
    }
    host.loadrt(&MODULE, &["sim=ppmc", "enc_clock=0xa00"])
        .unwrap();
    assert_eq!(
        port(&host, 0).with(|p| p.boards[0].counters.as_ref().unwrap().clock),
        3
    );
}

#[test]
fn a_dac_drives_its_motor_and_the_encoder_counts_it() {
    let host = host("ppmc-loop");
    host.loadrt(&MODULE, &["sim=ppmc"]).unwrap();
    set(&host, "ppmc.0.DAC.02.scale", Value::Float(-0.5));
    set(&host, "ppmc.0.DAC.02.value", Value::Float(-0.5));
    set(&host, "ppmc.0.encoder.02.scale", Value::Float(1000.0));
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    // +1 V: 128 counts per 1 ms period.
    wait("the encoder counts", || {
        s32(&host, "ppmc.0.encoder.02.count") > 128 * 200
    });
    let v = float(&host, "ppmc.0.encoder.02.velocity");
    assert!((v - 128.0).abs() < 2.0, "velocity {v}");
    assert!((s32(&host, "ppmc.0.encoder.02.delta") - 128).abs() <= 1);
    let c = s32(&host, "ppmc.0.encoder.02.count");
    let p = float(&host, "ppmc.0.encoder.02.position");
    assert!((p * 1000.0 - c as f64).abs() < 200.0, "{p} {c}");
    assert_eq!(s32(&host, "ppmc.0.encoder.00.count"), 0, "other axes still");
}

#[test]
fn the_estop_chain_of_a_dio_board() {
    let host = host("dio-estop");
    host.loadrt(&MODULE, &["sim=ppmc"]).unwrap();
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    wait("in estop", || bit(&host, "ppmc.0.din.estop.in"));
    set(&host, "ppmc.0.dout.Estop.out", Value::Bit(true));
    wait("out of estop", || !bit(&host, "ppmc.0.din.estop.in"));
    port(&host, 0).with(|p| p.chain_closed = false);
    wait("estop again", || bit(&host, "ppmc.0.din.estop.in"));
    port(&host, 0).with(|p| p.board_mut(3).unwrap().inputs = 0x0201);
    wait("inputs", || {
        bit(&host, "ppmc.0.din.00.in") && bit(&host, "ppmc.0.din.09.in")
    });
    assert!(!bit(&host, "ppmc.0.din.01.in"));
    set(&host, "ppmc.0.dout.03.out", Value::Bit(true));
    set(&host, "ppmc.0.dout.05.invert", Value::Bit(true));
    wait("outputs", || {
        port(&host, 0).with(|p| p.board(3).unwrap().outputs(true)) == 0x28
    });
}

#[test]
fn usc_steps_at_the_commanded_rate_out_of_estop() {
    let host = host("usc");
    host.loadrt(&MODULE, &["sim=usc"]).unwrap();
    set(&host, "ppmc.0.stepgen.01.scale", Value::Float(200.0));
    set(&host, "ppmc.0.stepgen.01.velocity", Value::Float(-10.0));
    set(&host, "ppmc.0.stepgen.01.enable", Value::Bit(true));
    set(
        &host,
        "ppmc.0.stepgen.00-03.pulse-width-ns",
        Value::U32(3550),
    );
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    wait("frequency", || {
        float(&host, "ppmc.0.stepgen.01.freq") == -2000.0
    });
    assert_eq!(
        value(&host, "ppmc.0.stepgen.00-03.pulse-width-ns"),
        Value::U32(3500)
    );
    let sim = port(&host, 0);
    let (ctrl, width, div) = sim.with(|p| {
        let w = &p.boards[0].written;
        let at = stepgen::RATE0 as usize + 3;
        (
            w[stepgen::CTRL as usize],
            w[stepgen::WIDTH as usize],
            u32::from_le_bytes([w[at], w[at + 1], w[at + 2], 0]),
        )
    });
    assert_eq!(ctrl & 0x0C, 0x08, "generator 1 running, reverse");
    assert_eq!(width as u32, 256 - 35);
    assert_eq!(div, 5000 - 4);
    assert!(
        !bit(&host, "ppmc.0.din.15.in"),
        "estop input off while the output is"
    );
    assert_eq!(
        s32(&host, "ppmc.0.encoder.01.count"),
        0,
        "no steps in estop"
    );
    set(&host, "ppmc.0.dout.07.out", Value::Bit(true));
    wait("out of estop", || bit(&host, "ppmc.0.din.15.in"));
    wait("steps", || s32(&host, "ppmc.0.encoder.01.count") < -100);
    let v = float(&host, "ppmc.0.encoder.01.velocity");
    assert!((v + 2000.0).abs() < 10.0, "{v}");
}

#[test]
fn upc_pwm_with_bootstrap_and_timestamps() {
    let host = host("upc");
    host.loadrt(&MODULE, &["sim=upc", "timestamp=0x00"])
        .unwrap();
    set(&host, "ppmc.0.pwm.00-03.freq", Value::Float(50_000.0));
    set(&host, "ppmc.0.pwm.00.bootstrap", Value::Bit(true));
    set(&host, "ppmc.0.pwm.00.max-dc", Value::Float(0.9));
    set(&host, "ppmc.0.pwm.00.scale", Value::Float(10.0));
    set(&host, "ppmc.0.pwm.00.value", Value::Float(5.0));
    set(&host, "ppmc.0.encoder.00.scale", Value::Float(10.0));
    set(&host, "ppmc.0.dout.07.out", Value::Bit(true));
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    let sim = port(&host, 0);
    let start =
        || sim.with(|p| u16::from_le_bytes([p.boards[0].written[0x1D], p.boards[0].written[0x1E]]));
    // 40 MHz / 50 kHz: 800 clocks.
    wait("carrier", || start() == (65536 - 800) as u16);
    assert_eq!(float(&host, "ppmc.0.pwm.00-03.freq"), 50_000.0);
    set(&host, "ppmc.0.pwm.00.enable", Value::Bit(true));
    wait("half duty", || {
        float(&host, "ppmc.0.pwm.00.duty-cycle") == 0.5
    });
    // 50 % of 20000 counts/s: 1000 units/s at 10 counts/unit.
    wait("moving", || s32(&host, "ppmc.0.encoder.00.count") > 2_000);
    let v = float(&host, "ppmc.0.encoder.00.velocity");
    assert!((v - 1000.0).abs() < 5.0, "timestamped velocity {v}");
    set(&host, "ppmc.0.pwm.00.value", Value::Float(50.0));
    wait("max-dc", || float(&host, "ppmc.0.pwm.00.duty-cycle") == 0.9);
    assert_eq!(sim.with(|p| p.boards[0].written[uxc::DOUT as usize]), 0x80);
}

#[test]
fn index_enable_clears_the_count_at_the_index() {
    let host = host("index");
    host.loadrt(&MODULE, &["sim=ppmc"]).unwrap();
    set(&host, "ppmc.0.DAC.00.value", Value::Float(0.1));
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    // 12.8 counts per period: the index at 4000 comes after ~310 periods.
    wait("moving", || s32(&host, "ppmc.0.encoder.00.count") > 100);
    set(&host, "ppmc.0.encoder.00.index-enable", Value::Bit(true));
    wait("index taken", || {
        !bit(&host, "ppmc.0.encoder.00.index-enable")
    });
    let c = s32(&host, "ppmc.0.encoder.00.count");
    assert!((0..200).contains(&c), "count restarted at the index: {c}");
    let pos = port(&host, 0).with(|p| p.motors[0]);
    assert!(pos > 4000.0, "{pos}");
}

#[test]
fn a_bus_that_stops_answering_trips_the_fault_and_goes_safe() {
    let host = host("lost");
    host.loadrt(&MODULE, &["sim=ppmc"]).unwrap();
    set(&host, "ppmc.0.DAC.01.value", Value::Float(5.0));
    set(&host, "ppmc.0.dout.Estop.out", Value::Bit(true));
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    let sim = port(&host, 0);
    wait("estop out", || {
        sim.with(|p| p.board(3).unwrap().estop_out())
    });
    sim.with(|p| p.connected = false);
    wait("fault", || bit(&host, "ppmc.0.fault"));
    sim.with(|p| p.connected = true);
    host.stop();
    // The latch's safe state ran while the cable was out: the writes were
    // lost. At unload it runs again, on a bus that answers.
    host.unloadrt("all").unwrap();
    sim.with(|p| {
        assert!(!p.board(3).unwrap().estop_out());
        for ch in 0..4 {
            assert!(p.board(2).unwrap().dac_volts(ch).abs() < 1e-3);
        }
        let w = &p.board(2).unwrap().written;
        assert_eq!(u16::from_le_bytes([w[dac::DAC0 as usize], w[1]]), dac::ZERO);
    });
}

#[test]
fn two_buses_and_port_numbers() {
    let host = host("two-buses");
    host.loadrt(
        &MODULE,
        &["port_addr=0x378,1", "sim=upc,usc", "extradac=0x10"],
    )
    .unwrap();
    assert!(has_pin(&host, "ppmc.0.pwm.00.value"));
    assert!(has_pin(&host, "ppmc.1.stepgen.00.velocity"));
    assert!(has_pin(&host, "ppmc.1.DAC8.00.value"));
    assert!(has_pin(&host, "ppmc.1.encoder.00.count"));
    assert!(!has_pin(&host, "ppmc.0.DAC8.00.value"));
    let host = hal_driver::testing::host("second-item");
    host.loadrt(&MODULE, &["sim=ppmc", "port_addr=-1,0x278"])
        .unwrap();
    assert!(
        has_pin(&host, "ppmc.1.DAC.00.value"),
        "bus numbers follow port_addr's items"
    );
    assert!(!has_pin(&host, "ppmc.0.DAC.00.value"));
}

#[test]
fn later_estop_boards_are_slaves_of_the_first() {
    let host = host("slaves");
    host.loadrt(&MODULE, &["sim=dio+dio+usc"]).unwrap();
    // The second DIO board numbers on; only the first has the estop pins.
    assert!(has_pin(&host, "ppmc.0.din.31.in"));
    assert!(has_pin(&host, "ppmc.0.dout.15.out"));
    assert!(has_pin(&host, "ppmc.0.din.estop.in"));
    assert!(has_pin(&host, "ppmc.0.dout.Estop.out"));
    // The USC after them: inputs 32..47, outputs 16..23.
    assert!(has_pin(&host, "ppmc.0.din.47.in"));
    assert!(has_param(&host, "ppmc.0.dout.23-invert"));
    let sim = port(&host, 0);
    sim.with(|p| {
        assert_eq!(
            p.board(1).unwrap().written[2],
            2,
            "second DIO told it is a slave"
        );
        assert!(p.board(2).unwrap().slave, "the USC too");
    });
    run(&host, &["ppmc.0.read", "ppmc.0.write"]);
    set(&host, "ppmc.0.dout.09.out", Value::Bit(true));
    wait("the second board's output", || {
        sim.with(|p| p.board(1).unwrap().outputs(true)) == 0x02
    });
    // Its estop register is not rewritten by the realtime functions.
    assert_eq!(sim.with(|p| p.board(1).unwrap().written[2]), 2);
    // The slave USC steps once the first DIO board is out of estop.
    set(&host, "ppmc.0.stepgen.00.velocity", Value::Float(1000.0));
    set(&host, "ppmc.0.stepgen.00.enable", Value::Bit(true));
    std::thread::sleep(std::time::Duration::from_millis(50));
    assert_eq!(s32(&host, "ppmc.0.encoder.00.count"), 0, "in estop");
    set(&host, "ppmc.0.dout.Estop.out", Value::Bit(true));
    wait("steps", || s32(&host, "ppmc.0.encoder.00.count") > 10);
}
