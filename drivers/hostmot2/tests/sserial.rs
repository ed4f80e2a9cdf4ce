//! Smart Serial: discovery of the simulated 7I76 and 7I77 over UDP and
//! on the PCI simulator, their process data both ways with LinuxCNC's
//! names, scaling, inversion and modes, the `sserial_port_N` syntax,
//! globals written back to a card, and a card that stops answering
//! (fault pins, the port stopped, the card's outputs off, the restart).

mod common;

use common::eth::EthRig;
use common::Named;
use hal_core::Value::{self, Bit, Float, S32, U32};
use hal_core::{Host, HostConfig};
use hostmot2::hal::{HM2_PCI_MODULE, HOSTMOT2_MODULE};
use hostmot2::sim::boards::{self, seven_i77_on};
use hostmot2::sim::SimHm2;

fn f(v: Value) -> f64 {
    match v {
        Float(x) => x,
        v => panic!("{v:?}"),
    }
}

#[test]
fn the_7i76_is_found_and_named_as_linuxcnc_names_it() {
    let r = EthRig::new("ss-names", "7i76e", "");
    let inst = r.host.instance();
    let card = "hm2_7i76e.0.7i76.0.0";
    for k in 0..32 {
        assert!(
            inst.pin(&format!("{card}.input-{k:02}")).unwrap().is_some(),
            "input {k}"
        );
        assert!(inst
            .pin(&format!("{card}.input-{k:02}-not"))
            .unwrap()
            .is_some());
    }
    for k in 0..16 {
        assert!(inst
            .pin(&format!("{card}.output-{k:02}"))
            .unwrap()
            .is_some());
        assert!(inst
            .param(&format!("{card}.output-{k:02}-invert"))
            .unwrap()
            .is_some());
    }
    assert!(inst.pin(&format!("{card}.input-32")).unwrap().is_none());
    for pin in ["spinout", "spinena", "spindir"] {
        assert!(
            inst.pin(&format!("{card}.{pin}")).unwrap().is_some(),
            "{pin}"
        );
    }
    for (param, v) in [
        ("spinout-scalemax", Float(10.0)),
        ("spinout-minlim", Float(0.0)),
        ("spinout-maxlim", Float(10.0)),
        ("spinena-invert", Bit(false)),
        ("swrevision", U32(22)),
        ("nvunitnumber", U32(0x1000_1234)),
        ("nvbaudrate", U32(9)),
        ("nvwatchdogtimeout", U32(50)),
    ] {
        assert_eq!(
            inst.param_value(&format!("{card}.{param}")).unwrap(),
            v,
            "{param}"
        );
    }
    let port = "hm2_7i76e.0.sserial.port-0";
    assert_eq!(inst.pin_value(&format!("{port}.run")).unwrap(), Bit(true));
    for pin in [
        "port_state",
        "port_state2",
        "port_state3",
        "fault-count",
        "fault",
    ] {
        assert!(
            inst.pin(&format!("{port}.{pin}")).unwrap().is_some(),
            "{pin}"
        );
    }
    for (param, v) in [("fault-inc", 10), ("fault-dec", 1), ("fault-lim", 200)] {
        assert_eq!(
            inst.param_value(&format!("{port}.{param}")).unwrap(),
            U32(v)
        );
    }
    assert!(inst.pin("hm2_7i76e.0.0.debug").unwrap().is_some());
    // The channel's pins belong to the module: no GPIO output on them.
    assert!(inst.pin("hm2_7i76e.0.gpio.010.in").unwrap().is_some());
    assert!(inst.pin("hm2_7i76e.0.gpio.010.out").unwrap().is_none());
    assert!(inst.pin("hm2_7i76e.0.gpio.011.out").unwrap().is_none());
    // Mode 0 has no analog inputs.
    assert!(inst.pin(&format!("{card}.analogin0")).unwrap().is_none());
}

#[test]
fn the_7i76_moves_its_process_data_both_ways() {
    let mut r = EthRig::new("ss-7i76", "7i76e", "");
    let card = "7i76.0.0";
    let set = |r: &EthRig, n: &str, v| r.set(&format!("{card}.{n}"), v);
    set(&r, "output-03", Bit(true));
    set(&r, "output-15", Bit(true));
    set(&r, "spinout", Float(2.5));
    set(&r, "spinena", Bit(true));
    r.remote(0, 0, |c| c.set_value("Input", (1u32 << 5 | 1 << 31) as f64));
    r.cycles(4);
    assert_eq!(r.pin("sserial.port-0.port_state"), U32(3), "running");
    assert_eq!(
        r.remote(0, 0, |c| c.value("Output")),
        Some((1 << 3 | 1 << 15) as f64)
    );
    assert!((r.remote(0, 0, |c| c.value("SpinOut")).unwrap() - 2.5).abs() < 1e-3);
    assert_eq!(r.remote(0, 0, |c| c.value("SpinEna")), Some(1.0));
    assert_eq!(r.remote(0, 0, |c| c.value("SpinDir")), Some(0.0));
    assert_eq!(r.pin(&format!("{card}.input-05")), Bit(true));
    assert_eq!(r.pin(&format!("{card}.input-05-not")), Bit(false));
    assert_eq!(r.pin(&format!("{card}.input-31")), Bit(true));
    assert_eq!(r.pin(&format!("{card}.input-04")), Bit(false));
    assert_eq!(r.pin(&format!("{card}.input-04-not")), Bit(true));
    // Inversion, clamping and scaling.
    set(&r, "output-03-invert", Bit(true));
    set(&r, "spindir-invert", Bit(true));
    set(&r, "spinout", Float(50.0));
    r.cycles(2);
    assert_eq!(
        r.remote(0, 0, |c| c.value("Output")),
        Some((1 << 15) as f64)
    );
    assert_eq!(r.remote(0, 0, |c| c.value("SpinDir")), Some(1.0));
    assert!((r.remote(0, 0, |c| c.value("SpinOut")).unwrap() - 10.0).abs() < 1e-3);
    set(&r, "spinout-maxlim", Float(4.0));
    r.cycles(2);
    assert!((r.remote(0, 0, |c| c.value("SpinOut")).unwrap() - 4.0).abs() < 1e-3);
    set(&r, "spinout-scalemax", Float(20.0));
    set(&r, "spinout", Float(4.0));
    r.cycles(2);
    // 4 of a 20 V full scale is 2 V at a card whose full scale is 10 V.
    assert!((r.remote(0, 0, |c| c.value("SpinOut")).unwrap() - 2.0).abs() < 1e-3);
    // The inputs of a cycle arrive with the next read. The change is
    // made after this cycle's round trip: by then the board has handled
    // the last write (writes get no reply) and its transfer has sampled
    // the old inputs.
    r.board.read_request();
    r.board.read();
    r.remote(0, 0, |c| c.set_value("Input", 0.0));
    r.board.write(common::PERIOD);
    assert_eq!(
        r.pin(&format!("{card}.input-05")),
        Bit(true),
        "one period old"
    );
    r.cycle();
    assert_eq!(r.pin(&format!("{card}.input-05")), Bit(false));
}

#[test]
fn modes_bring_analog_inputs_field_voltage_and_counters() {
    let mut r = EthRig::new("ss-mode2", "7i76e", "sserial_port_0=2xxxxxxx");
    let card = "7i76.0.0";
    r.remote(0, 0, |c| {
        c.set_value("AnalogIn2", 12.0);
        c.set_value("FieldVoltage", 24.0);
        c.set_value("MPG0", 250.0);
    });
    r.cycles(3);
    assert!((f(r.pin(&format!("{card}.analogin2"))) - 12.0).abs() < 0.2);
    assert!((f(r.pin(&format!("{card}.fieldvoltage"))) - 24.0).abs() < 0.2);
    assert_eq!(
        r.pin(&format!("{card}.mpg0.count")),
        S32(-6),
        "8-bit counter"
    );
    // The counter unwraps past its 8 bits.
    for n in [260.0, 380.0, 500.0, 620.0, 700.0] {
        r.remote(0, 0, |c| c.set_value("MPG0", n));
        r.cycles(2);
    }
    assert_eq!(r.pin(&format!("{card}.mpg0.count")), S32(700 - 256));
    r.set_param(&format!("{card}.mpg0.scale"), Float(4.0));
    r.set_pin(&format!("{card}.mpg0.reset"), Bit(true));
    r.cycles(1);
    r.set_pin(&format!("{card}.mpg0.reset"), Bit(false));
    r.remote(0, 0, |c| c.set_value("MPG0", 708.0));
    r.cycles(2);
    assert_eq!(r.pin(&format!("{card}.mpg0.count")), S32(8));
    assert_eq!(r.pin(&format!("{card}.mpg0.position")), Float(2.0));
    assert_eq!(r.pin(&format!("{card}.mpg0.rawcounts")), S32(708 - 256));
}

#[test]
fn the_7i77_io_and_analog_channels() {
    let mut spec = boards::preset("7i96s").unwrap();
    spec.remotes = seven_i77_on(0, 0).to_vec();
    let mut r = EthRig::with_spec("ss-7i77", "7i96s", spec, "sserial_port_0=10");
    let io = "7i77.0.0";
    let an = "7i77.0.1";
    let inst = r.host.instance();
    for k in 0..6 {
        let base = format!("hm2_7i96s.0.{an}.analogout{k}");
        assert!(inst.pin(&base).unwrap().is_some());
        assert_eq!(
            inst.param_value(&format!("{base}-minlim")).unwrap(),
            Float(-10.0)
        );
        assert_eq!(
            inst.param_value(&format!("{base}-maxlim")).unwrap(),
            Float(10.0)
        );
        assert_eq!(
            inst.param_value(&format!("{base}-scalemax")).unwrap(),
            Float(10.0)
        );
    }
    assert!(
        inst.pin(&format!("hm2_7i96s.0.{io}.analogin3"))
            .unwrap()
            .is_some(),
        "mode 1"
    );
    assert!(inst
        .pin(&format!("hm2_7i96s.0.{io}.fieldvoltage"))
        .unwrap()
        .is_none());
    r.set_pin(&format!("{an}.analogout0"), Float(-4.5));
    r.set_pin(&format!("{an}.analogout5"), Float(12.0));
    r.set_pin(&format!("{an}.analogena"), Bit(true));
    r.set_pin(&format!("{io}.output-07"), Bit(true));
    r.remote(0, 0, |c| c.set_value("Input", 3.0));
    r.cycles(3);
    assert!((r.remote(0, 1, |c| c.value("AnalogOut0")).unwrap() + 4.5).abs() < 0.01);
    assert!((r.remote(0, 1, |c| c.value("AnalogOut5")).unwrap() - 10.0).abs() < 0.01);
    assert_eq!(r.remote(0, 1, |c| c.value("AnalogEna")), Some(1.0));
    assert_eq!(r.remote(0, 1, |c| c.value("SpinEna")), Some(0.0));
    assert_eq!(r.remote(0, 0, |c| c.value("Output")), Some(128.0));
    assert_eq!(r.pin(&format!("{io}.input-00")), Bit(true));
    assert_eq!(r.pin(&format!("{io}.input-01")), Bit(true));
    assert_eq!(r.pin(&format!("{io}.input-02")), Bit(false));
}

#[test]
fn sserial_port_syntax_disables_channels_and_refuses_unknown_modes() {
    // x: channel 0 is not probed, its pins stay GPIO, no card objects.
    let r = EthRig::new("ss-x", "7i96s", "sserial_port_0=x");
    let inst = r.host.instance();
    assert!(inst.pin("hm2_7i96s.0.7i76.0.0.input-00").unwrap().is_none());
    assert!(
        inst.pin("hm2_7i96s.0.gpio.001.out").unwrap().is_some(),
        "TX is GPIO"
    );
    assert!(inst
        .pin("hm2_7i96s.0.sserial.port-0.run")
        .unwrap()
        .is_none());
    drop(r);
    // Channel 1 has no card: its pins stay GPIO.
    let r = EthRig::new("ss-empty", "7i96s", "");
    let inst = r.host.instance();
    assert!(inst.pin("hm2_7i96s.0.7i76.0.0.input-00").unwrap().is_some());
    assert!(
        inst.pin("hm2_7i96s.0.gpio.004.out").unwrap().is_some(),
        "TX1 is GPIO"
    );
    assert!(inst.pin("hm2_7i96s.0.gpio.001.out").unwrap().is_none());
    drop(r);
    // A mode the card does not have: the load fails naming it.
    let server = common::eth::serve("7i96s", Default::default());
    let h = Host::create(HostConfig::for_tests("ss-mode9")).unwrap();
    h.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    let ip = format!("board_ip={}", server.addr());
    let e = h
        .loadrt(
            &hostmot2::eth::hal::HM2_ETH_MODULE,
            &[ip.as_str(), "config=sserial_port_0=7"],
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("Smart Serial port 0 channel 0: the card has no mode 7"),
        "{e}"
    );
    assert_eq!(h.loaded_components(), ["hostmot2"]);
}

#[test]
fn a_card_that_stops_answering_trips_the_port_and_its_outputs_go_off() {
    let mut r = EthRig::new("ss-cut", "7i76e", "");
    r.set_pin("7i76.0.0.output-00", Bit(true));
    r.set_pin("7i76.0.0.spinena", Bit(true));
    r.cycles(5);
    assert_eq!(r.remote(0, 0, |c| c.value("Output")), Some(1.0));
    let _ = r.messages();
    // The cable is pulled.
    r.remote(0, 0, |c| c.connected = false);
    // Each read of a failed transfer: +10 -1. (The first read after the
    // cut has the last transfer before it, good or failed depending on
    // whether its datagram reached the simulator before the cable went.)
    r.cycle();
    let first = match r.pin("sserial.port-0.fault-count") {
        U32(v) => v,
        v => panic!("{v:?}"),
    };
    assert!(first == 0 || first == 9, "{first}");
    let mut tripped_after = None;
    for k in 2..=40 {
        r.cycle();
        if r.pin("sserial.port-0.fault") == Bit(true) {
            tripped_after = Some(k);
            break;
        }
        assert_eq!(
            r.pin("sserial.port-0.fault-count"),
            U32(first + 9 * (k - 1))
        );
    }
    let expected = if first == 0 { 24 } else { 23 };
    assert_eq!(tripped_after, Some(expected), "past fault-lim 200");
    assert_eq!(r.pin("sserial.port-0.port_state"), U32(10));
    let msgs = r.messages();
    assert!(
        msgs.iter()
            .any(|m| m.contains("***Smart Serial Port 0 will be stopped***")),
        "{msgs:?}"
    );
    assert!(msgs.iter().any(|m| m.contains("timeout")), "{msgs:?}");
    // The card heard nothing for its watchdog time: its outputs are off.
    r.cycles(30);
    assert!(r.remote(0, 0, |c| c.watchdog_tripped()));
    assert_eq!(r.remote(0, 0, |c| c.value("Output")), Some(0.0));
    assert_eq!(r.remote(0, 0, |c| c.value("SpinEna")), Some(0.0));
    // The cable is back; run is toggled: the port restarts.
    r.remote(0, 0, |c| c.connected = true);
    r.set_pin("sserial.port-0.run", Bit(false));
    r.cycles(4);
    assert_eq!(r.pin("sserial.port-0.port_state"), U32(0));
    r.set_pin("sserial.port-0.run", Bit(true));
    r.cycles(4);
    assert_eq!(r.pin("sserial.port-0.port_state"), U32(3));
    assert_eq!(r.pin("sserial.port-0.fault"), Bit(false));
    assert_eq!(r.remote(0, 0, |c| c.value("Output")), Some(1.0));
    assert_eq!(r.pin("sserial.port-0.fault-count"), U32(0));
}

#[test]
fn a_changed_global_is_written_to_the_cards_eeprom_while_idle() {
    let mut r = EthRig::new("ss-param", "7i76e", "");
    r.cycles(3);
    r.set_param("7i76.0.0.nvwatchdogtimeout", U32(20));
    r.cycles(3);
    assert_eq!(
        r.remote(0, 0, |c| c.global("NVWatchDogTimeout")),
        Some(50),
        "not while running"
    );
    r.set_pin("sserial.port-0.run", Bit(false));
    r.cycles(20);
    assert_eq!(r.remote(0, 0, |c| c.global("NVWatchDogTimeout")), Some(20));
    assert!(r.remote(0, 0, |c| c.eeprom_writes) > 0, "in the EEPROM");
    r.set_pin("sserial.port-0.run", Bit(true));
    r.cycles(4);
    assert_eq!(r.pin("sserial.port-0.port_state"), U32(3));
    // The card now turns its outputs off after 20 ms without data.
    r.remote(0, 0, |c| c.connected = false);
    r.cycles(19);
    assert!(!r.remote(0, 0, |c| c.watchdog_tripped()));
    r.cycles(3);
    assert!(r.remote(0, 0, |c| c.watchdog_tripped()));
}

#[test]
fn the_pci_simulator_has_smart_serial_too() {
    let h = Host::create(HostConfig::for_tests("ss-pci")).unwrap();
    h.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    h.loadrt(
        &HM2_PCI_MODULE,
        &["sim=5i25-7i77", "config=sserial_port_0=30"],
    )
    .unwrap();
    let inst = h.instance();
    assert!(
        inst.pin("hm2_5i25.0.7i77.0.0.mpg1.count")
            .unwrap()
            .is_some(),
        "mode 3"
    );
    assert!(inst
        .pin("hm2_5i25.0.7i77.0.1.analogout5")
        .unwrap()
        .is_some());
    assert!(inst
        .pin("hm2_5i25.0.stepgen.04.position-fb")
        .unwrap()
        .is_some());
    let board = hal_driver::sim::find::<SimHm2>(inst.name(), "hm2_5i25.0").unwrap();
    inst.set_pin("hm2_5i25.0.7i77.0.1.analogout2", Float(3.0))
        .unwrap();
    h.create_thread("servo", 1_000_000, false, None).unwrap();
    h.addf("hm2_5i25.0.read", "servo", -1).unwrap();
    h.addf("hm2_5i25.0.write", "servo", -1).unwrap();
    h.start().unwrap();
    let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
    let out = || {
        board.with(|m| {
            m.sserial()
                .remote(0, 1)
                .and_then(|c| c.value("AnalogOut2"))
                .unwrap_or(0.0)
        })
    };
    while (out() - 3.0).abs() > 0.01 {
        assert!(std::time::Instant::now() < end, "the value never arrived");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    h.stop();
}
