//! `loadrt pca9685 / mcp23017 / ads1115` on simulated buses: every pin,
//! parameter and function, the chips' register sequences, inversion,
//! analog scaling, a chip unplugged mid-run (fault pin, counter, held
//! values, safe outputs, fault reset), shared buses, and load errors.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;

mod common;

use common::*;
use hal_core::{HalType, Host, ModuleDef, ParamDir, PinDir, Value};
use hal_i2c::hal::{ads1115, mcp23017, pca9685, sim_bus};
use hal_i2c::regs::pca9685 as pca;
use hal_i2c::sim::{Ads1115, Kind, Mcp23017, Pca9685, SimBus};

fn load(h: &Host, m: &'static ModuleDef, args: &[&str]) -> hal_core::Result<()> {
    h.loadrt(m, args)
}

fn setp(h: &Host, param: &str, v: Value) {
    h.instance()
        .set_param(param, v)
        .unwrap_or_else(|e| panic!("{param}: {e}"));
}

fn bus(h: &Host, n: u32) -> Arc<SimBus> {
    sim_bus(h.instance().name(), n).expect("simulated bus published")
}

/// (name, type, dir) of every pin of `owner`, sorted, without function
/// timing pins.
fn pins_of(h: &Host, owner: &str) -> Vec<(String, HalType, PinDir)> {
    h.instance()
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == owner && !p.name.ends_with(".time"))
        .map(|p| (p.name, p.hal_type, p.dir))
        .collect()
}

fn params_of(h: &Host, owner: &str) -> Vec<(String, HalType, ParamDir, Value)> {
    h.instance()
        .params()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == owner && !p.name.contains(".tmax"))
        .map(|p| (p.name, p.hal_type, p.dir, p.value))
        .collect()
}

fn functs_of(h: &Host, owner: &str) -> Vec<(String, bool)> {
    h.instance()
        .functs()
        .unwrap()
        .into_iter()
        .filter(|f| f.owner == owner)
        .map(|f| (f.name, f.uses_fp))
        .collect()
}

#[test]
fn pca9685_pins_params_functions() {
    let h = host("pca-names");
    load(&h, &pca9685::MODULE, &["backend=sim", "address=0x40,0x41"]).unwrap();
    let pins = pins_of(&h, "pca9685");
    assert_eq!(pins.len(), 2 * (16 * 2 + 3));
    for chip in 0..2 {
        for ch in 0..16 {
            let p = format!("pca9685.{chip}.pwmgen.{ch:02}");
            assert!(
                pins.contains(&(format!("{p}.value"), HalType::Float, PinDir::In)),
                "{p}"
            );
            assert!(
                pins.contains(&(format!("{p}.enable"), HalType::Bit, PinDir::In)),
                "{p}"
            );
        }
        let p = format!("pca9685.{chip}");
        assert!(pins.contains(&(format!("{p}.fault"), HalType::Bit, PinDir::Out)));
        assert!(pins.contains(&(format!("{p}.errors"), HalType::U32, PinDir::Out)));
        assert!(pins.contains(&(format!("{p}.fault-reset"), HalType::Bit, PinDir::In)));
    }
    let params = params_of(&h, "pca9685");
    assert_eq!(params.len(), 32);
    assert!(params.contains(&(
        "pca9685.1.pwmgen.15.scale".into(),
        HalType::Float,
        ParamDir::Rw,
        Value::Float(1.0)
    )));
    assert_eq!(
        functs_of(&h, "pca9685"),
        vec![
            ("pca9685.0.read".into(), false),
            ("pca9685.0.write".into(), true),
            ("pca9685.1.read".into(), false),
            ("pca9685.1.write".into(), true),
        ]
    );
}

#[test]
fn pca9685_set_up_frequency_mode2_and_duty() {
    let h = host("pca-run");
    load(
        &h,
        &pca9685::MODULE,
        &[
            "backend=sim",
            "bus=3",
            "address=0x55",
            "freq=50",
            "invert=1",
            "opendrain=1",
        ],
    )
    .unwrap();
    let b = bus(&h, 3);
    // The set-up runs inside loadrt; the bus helper thread may already
    // have sent its first duty blocks after it, so only the start counts.
    let mut setup: Vec<_> = b
        .transfers_to(0x55)
        .iter()
        .map(|t| (t.kind, t.reg, t.bytes().to_vec()))
        .collect();
    setup.truncate(5);
    assert_eq!(
        setup,
        vec![
            (Kind::WriteByte, pca::MODE1, vec![0x30]),
            (Kind::WriteByte, pca::PRE_SCALE, vec![121]),
            (Kind::WriteByte, pca::MODE2, vec![pca::MODE2_INVRT]),
            (Kind::WriteByte, pca::ALL_LED_OFF_H, vec![0x10]),
            (Kind::WriteByte, pca::MODE1, vec![0x20]),
        ]
    );
    let chip = |f: &dyn Fn(&Pca9685) -> f64| b.with_chip::<Pca9685, _>(0x55, |c| f(c)).unwrap();
    assert!((chip(&|c| c.frequency()) - 50.0).abs() < 0.2);
    assert_eq!(chip(&|c| c.inverted() as u8 as f64), 1.0);
    assert_eq!(chip(&|c| c.totem_pole() as u8 as f64), 0.0);
    run(&h, &["pca9685.0.read", "pca9685.0.write"]);
    let p = "pca9685.0.pwmgen";
    set(&h, &format!("{p}.00.value"), Value::Float(0.25));
    set(&h, &format!("{p}.00.enable"), Value::Bit(true));
    set(&h, &format!("{p}.07.value"), Value::Float(3.0));
    setp(&h, &format!("{p}.07.scale"), Value::Float(4.0));
    set(&h, &format!("{p}.07.enable"), Value::Bit(true));
    set(&h, &format!("{p}.15.value"), Value::Float(-0.5));
    set(&h, &format!("{p}.15.enable"), Value::Bit(true));
    set(&h, &format!("{p}.03.value"), Value::Float(0.9));
    wait_for("duty cycles", || {
        chip(&|c| c.duty(0)) == 0.25 && chip(&|c| c.duty(7)) == 0.75
    });
    assert_eq!(chip(&|c| c.duty(15)), 0.0, "negative: off");
    assert_eq!(chip(&|c| c.duty(3)), 0.0, "disabled: off");
    assert_eq!(chip(&|c| c.pin_high(0)), 0.75, "inverted pin");
    set(&h, &format!("{p}.00.value"), Value::Float(2.0));
    wait_for("full on", || chip(&|c| c.duty(0)) == 1.0);
    assert_eq!(value(&h, "pca9685.0.fault"), Value::Bit(false));
    assert_eq!(value(&h, "pca9685.0.errors"), Value::U32(0));
    // Unload: every channel full off.
    h.stop();
    h.unloadrt("pca9685").unwrap();
    assert!((0..16).all(|ch| chip(&|c| c.duty(ch)) == 0.0));
    assert_eq!(
        b.with_chip::<Pca9685, _>(0x55, |c| c.prescale_writes_ignored + c.testmode_writes),
        Some(0)
    );
}

#[test]
fn mcp23017_pins_inversion_and_pullups() {
    let h = host("mcp");
    load(
        &h,
        &mcp23017::MODULE,
        &["backend=sim", "address=0x27", "dir=0x7f00", "pullup=0x0300"],
    )
    .unwrap();
    let pins = pins_of(&h, "mcp23017");
    let m = "mcp23017.0";
    for pin in 0..16 {
        let input = (0x7f00 >> pin) & 1 == 1;
        let (digin, digout) = (
            format!("{m}.digin.{pin:02}"),
            format!("{m}.digout.{pin:02}"),
        );
        assert_eq!(
            pins.contains(&(format!("{digin}.in"), HalType::Bit, PinDir::Out)),
            input
        );
        assert_eq!(
            pins.contains(&(format!("{digin}.in-not"), HalType::Bit, PinDir::Out)),
            input
        );
        assert_eq!(
            pins.contains(&(format!("{digout}.out"), HalType::Bit, PinDir::In)),
            !input
        );
    }
    assert_eq!(pins.len(), 7 * 2 + 9 + 3);
    let params = params_of(&h, "mcp23017");
    assert_eq!(params.len(), 9, "an invert per output");
    assert!(params.contains(&(
        format!("{m}.digout.15.invert"),
        HalType::Bit,
        ParamDir::Rw,
        Value::Bit(false)
    )));
    assert_eq!(
        functs_of(&h, "mcp23017"),
        vec![(format!("{m}.read"), false), (format!("{m}.write"), false)]
    );
    let b = bus(&h, 1);
    let chip = |f: &dyn Fn(&Mcp23017) -> u16| b.with_chip::<Mcp23017, _>(0x27, |c| f(c)).unwrap();
    assert_eq!(chip(&|c| c.iodir()), 0x7f00);
    assert_eq!(chip(&|c| c.gppu()), 0x0300);
    // Before any write the outputs sit at their safe level.
    assert_eq!(chip(&|c| c.pins()) & 0x80FF, 0);
    setp(&h, &format!("{m}.digout.01.invert"), Value::Bit(true));
    set(&h, &format!("{m}.digout.00.out"), Value::Bit(true));
    set(&h, &format!("{m}.digout.15.out"), Value::Bit(true));
    b.with_chip::<Mcp23017, _>(0x27, |c| {
        c.set_input(10, true);
        c.set_input(8, false);
    });
    run(&h, &[&format!("{m}.read"), &format!("{m}.write")]);
    wait_for("outputs", || chip(&|c| c.pins()) & 0x80FF == 0x8003);
    wait_for("inputs", || {
        value(&h, &format!("{m}.digin.10.in")) == Value::Bit(true)
    });
    let bit = |p: &str| value(&h, &format!("{m}.digin.{p}"));
    assert_eq!(bit("08.in"), Value::Bit(false), "driven low");
    assert_eq!(bit("08.in-not"), Value::Bit(true));
    assert_eq!(bit("09.in"), Value::Bit(true), "floating with its pull-up");
    assert_eq!(bit("11.in"), Value::Bit(false), "floating, no pull-up");
    b.with_chip::<Mcp23017, _>(0x27, |c| c.set_input(10, false));
    wait_for("input change", || bit("10.in") == Value::Bit(false));
    h.stop();
    h.unloadrt("mcp23017").unwrap();
    assert_eq!(
        chip(&|c| c.pins()) & 0x80FF,
        0x0002,
        "safe: each output at its invert level"
    );
}

#[test]
fn mcp23017_reads_gp7_only_on_request_and_refuses_useless_pullups() {
    let h = host("mcp-gp7");
    load(&h, &mcp23017::MODULE, &["backend=sim"]).unwrap();
    let pins = pins_of(&h, "mcp23017");
    assert!(!pins
        .iter()
        .any(|p| p.0.contains(".digin.07.") || p.0.contains(".digin.15.")));
    assert_eq!(pins.len(), 14 * 2 + 3, "the default: 14 readable inputs");
    assert_eq!(
        bus(&h, 1).with_chip::<Mcp23017, _>(0x20, |c| c.iodir()),
        Some(0xFFFF),
        "GP7 stay high-impedance"
    );
    h.unloadrt("mcp23017").unwrap();
    load(
        &h,
        &mcp23017::MODULE,
        &["backend=sim", "dir=0x8080", "gp7_input=1"],
    )
    .unwrap();
    let pins = pins_of(&h, "mcp23017");
    assert!(pins.iter().any(|p| p.0 == "mcp23017.0.digin.07.in"));
    assert!(pins.iter().any(|p| p.0 == "mcp23017.0.digin.15.in"));
    h.unloadrt("mcp23017").unwrap();
    let e = load(
        &h,
        &mcp23017::MODULE,
        &["backend=sim", "dir=0x000f", "pullup=0x0030"],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(
            "parameter 'pullup': item 0 \"0x0030\": pull-ups on output pins (0x0030) do nothing"
        ),
        "{e}"
    );
    assert!(h.loaded_components().is_empty());
}

#[test]
fn ads1115_scaling_and_channels() {
    let h = host("ads");
    load(
        &h,
        &ads1115::MODULE,
        &[
            "backend=sim",
            "address=0x48,0x4b",
            "range=4096,512",
            "channels=3",
            "diff=0,1",
        ],
    )
    .unwrap();
    let pins = pins_of(&h, "ads1115");
    let adc = |chip: usize, ch: usize| format!("ads1115.{chip}.adcin.{ch}");
    for ch in 0..3 {
        assert!(pins.contains(&(format!("{}.value", adc(0, ch)), HalType::Float, PinDir::Out)));
    }
    assert!(!pins.iter().any(|p| p.0.starts_with(&adc(0, 3))));
    assert!(
        pins.iter().any(|p| p.0 == format!("{}.value", adc(1, 1))),
        "diff: 2 channels"
    );
    assert!(!pins.iter().any(|p| p.0.starts_with(&adc(1, 2))));
    let params = params_of(&h, "ads1115");
    assert!(params.contains(&(
        format!("{}.bit_weight", adc(0, 0)),
        HalType::Float,
        ParamDir::Rw,
        Value::Float(4.096 / 32768.0)
    )));
    assert!(params.contains(&(
        format!("{}.bit_weight", adc(1, 1)),
        HalType::Float,
        ParamDir::Rw,
        Value::Float(0.512 / 32768.0)
    )));
    assert!(params.contains(&(
        format!("{}.scale", adc(0, 2)),
        HalType::Float,
        ParamDir::Rw,
        Value::Float(1.0)
    )));
    assert!(params.contains(&(
        format!("{}.hw_offset", adc(0, 2)),
        HalType::Float,
        ParamDir::Rw,
        Value::Float(0.0)
    )));
    assert_eq!(
        functs_of(&h, "ads1115"),
        vec![
            ("ads1115.0.read".into(), true),
            ("ads1115.1.read".into(), true)
        ]
    );
    let b = bus(&h, 1);
    b.with_chip::<Ads1115, _>(0x48, |c| {
        c.set_input(0, 1.0);
        c.set_input(1, -0.5);
        c.set_input(2, 9.0);
    });
    b.with_chip::<Ads1115, _>(0x4b, |c| {
        c.set_input(0, 0.3);
        c.set_input(1, 0.1);
        c.set_input(2, 0.0);
        c.set_input(3, 0.25);
    });
    setp(&h, &format!("{}.scale", adc(0, 1)), Value::Float(10.0));
    setp(&h, &format!("{}.offset", adc(0, 1)), Value::Float(1.0));
    run(&h, &["ads1115.0.read", "ads1115.1.read"]);
    let float = |p: String| match value(&h, &p) {
        Value::Float(f) => f,
        v => panic!("{p}: {v:?}"),
    };
    let lsb = 4.096 / 32768.0;
    wait_for("conversions", || {
        (float(format!("{}.value", adc(0, 0))) - 1.0).abs() < lsb
            && float(format!("{}.value", adc(0, 2))) > 4.0
            && (float(format!("{}.value", adc(1, 1))) + 0.25).abs() < 0.512 / 32768.0
    });
    let v1 = float(format!("{}.value", adc(0, 1)));
    assert!(
        (v1 - (-0.5 * 10.0 - 1.0)).abs() < 10.0 * lsb,
        "value = volts * scale - offset: {v1}"
    );
    let v2 = float(format!("{}.value", adc(0, 2)));
    assert!(
        (v2 - 32767.0 * lsb).abs() < 1e-12,
        "9 V clips at full scale: {v2}"
    );
    let d0 = float(format!("{}.value", adc(1, 0)));
    assert!((d0 - 0.2).abs() < 0.512 / 32768.0, "AIN0 - AIN1: {d0}");
    // Only single-shot conversions with the comparator off were started.
    for t in b
        .transfers_to(0x48)
        .iter()
        .filter(|t| t.kind == Kind::WriteWord)
    {
        let cfg = u16::from_be_bytes([t.bytes()[0], t.bytes()[1]]);
        assert_eq!(
            cfg & 0x0103,
            0x0103,
            "single shot, comparator off: {cfg:#06x}"
        );
    }
}

#[test]
fn ads1115_refuses_what_the_chip_cannot_do() {
    let h = host("ads-bad");
    for (args, want) in [
        (
            &["backend=sim", "range=5000"][..],
            "parameter 'range': item 0 \"5000\": not one of 6144",
        ),
        (
            &["backend=sim", "rate=100"][..],
            "parameter 'rate': item 0 \"100\": not one of 8",
        ),
        (
            &["backend=sim", "diff=1", "channels=3"][..],
            "parameter 'channels': item 0 \"3\": differential inputs make at most 2",
        ),
        (
            &["backend=sim", "channels=5"][..],
            "parameter 'channels': item 0 \"5\": out of range",
        ),
        (
            &["backend=sim", "address=0x40"][..],
            "parameter 'address': item 0 \"0x40\": not an address this chip can have (0x48..=0x4b)",
        ),
        (
            &["backend=sim", "address=0x48,0x48"][..],
            "item 1 \"0x48\": chip 0 is at this address of bus 1 already",
        ),
        (
            &["backend=sim", "bus=1,2"][..],
            "parameter 'bus': 2 items given, but there are only 1",
        ),
        (
            &["backend=i2c"][..],
            "parameter 'backend': 'i2c' is not one of dev|sim",
        ),
    ] {
        let e = load(&h, &ads1115::MODULE, args).unwrap_err().to_string();
        assert!(
            e.starts_with("ads1115: ") && e.contains(want),
            "{args:?}: {e}"
        );
        assert!(h.loaded_components().is_empty());
    }
}

#[test]
fn a_chip_unplugged_mid_run_faults_holds_and_recovers_on_reset() {
    let h = host("unplug");
    load(&h, &mcp23017::MODULE, &["backend=sim", "dir=0xff00"]).unwrap();
    load(&h, &pca9685::MODULE, &["backend=sim"]).unwrap();
    let b = bus(&h, 1);
    let m = "mcp23017.0";
    b.with_chip::<Mcp23017, _>(0x20, |c| c.set_input(12, true));
    set(&h, &format!("{m}.digout.03.out"), Value::Bit(true));
    set(&h, "pca9685.0.pwmgen.02.value", Value::Float(0.5));
    set(&h, "pca9685.0.pwmgen.02.enable", Value::Bit(true));
    run(
        &h,
        &[
            &format!("{m}.read"),
            "pca9685.0.read",
            &format!("{m}.write"),
            "pca9685.0.write",
        ],
    );
    let mcp_pins = || b.with_chip::<Mcp23017, _>(0x20, |c| c.pins()).unwrap();
    let duty = || b.with_chip::<Pca9685, _>(0x40, |c| c.duty(2)).unwrap();
    wait_for("running", || {
        value(&h, &format!("{m}.digin.12.in")) == Value::Bit(true)
            && mcp_pins() & 0x08 != 0
            && duty() == 0.5
    });
    b.unplug(0x20);
    wait_for("fault pin", || {
        value(&h, &format!("{m}.fault")) == Value::Bit(true)
    });
    assert!(matches!(value(&h, &format!("{m}.errors")), Value::U32(n) if n >= 1));
    assert_eq!(
        value(&h, &format!("{m}.digin.12.in")),
        Value::Bit(true),
        "last value held"
    );
    assert_eq!(
        value(&h, "pca9685.0.fault"),
        Value::Bit(false),
        "the other chip runs on"
    );
    assert!(h.fault().is_none(), "the HAL thread runs on");
    // Retries count, every 100 ms.
    wait_for(
        "retries",
        || matches!(value(&h, &format!("{m}.errors")), Value::U32(n) if n >= 3),
    );
    // Back after a power cycle, with input 12 now low.
    b.with_chip::<Mcp23017, _>(0x20, |c| {
        c.power_cycle();
        c.set_input(12, false);
    });
    b.plug(0x20);
    wait_for("fresh inputs", || {
        value(&h, &format!("{m}.digin.12.in")) == Value::Bit(false)
    });
    assert_eq!(
        value(&h, &format!("{m}.fault")),
        Value::Bit(true),
        "latched"
    );
    assert_eq!(mcp_pins() & 0xff, 0, "set up again, outputs safe");
    set(&h, &format!("{m}.fault-reset"), Value::Bit(true));
    wait_for("reset", || {
        value(&h, &format!("{m}.fault")) == Value::Bit(false)
    });
    wait_for("outputs back", || mcp_pins() & 0x08 != 0);
    h.flush_rt_log();
    let log: Vec<String> = h.rt_log().history().into_iter().map(|(_, m)| m).collect();
    let said = |what: &str| log.iter().filter(|l| l.contains(what)).count();
    assert_eq!(
        said("mcp23017.0: simulated i2c-1 address 0x20: "),
        1,
        "said once: {log:?}"
    );
    assert_eq!(said("no answer"), 1, "{log:?}");
    assert_eq!(said("address 0x20 answers again"), 1, "{log:?}");
}

#[test]
fn chips_of_several_modules_share_a_bus_and_its_addresses() {
    let h = host("shared");
    load(&h, &pca9685::MODULE, &["backend=sim", "address=0x48"]).unwrap();
    let e = load(&h, &ads1115::MODULE, &["backend=sim", "address=0x48"])
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "ads1115: ads1115.0: simulated i2c-1 address 0x48 is already used by pca9685.0"
    );
    load(
        &h,
        &ads1115::MODULE,
        &["backend=sim", "address=0x49,0x48", "bus=1,2"],
    )
    .unwrap();
    let one = bus(&h, 1);
    assert!(one.with_chip::<Pca9685, _>(0x48, |_| ()).is_some());
    assert!(one.with_chip::<Ads1115, _>(0x49, |_| ()).is_some());
    assert!(bus(&h, 2).with_chip::<Ads1115, _>(0x48, |_| ()).is_some());
    // An address a kernel driver owns.
    one.set_busy(0x20);
    let e = load(&h, &mcp23017::MODULE, &["backend=sim"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("mcp23017.0: simulated i2c-1 address 0x20: ")
            && e.contains("kernel driver owns this address"),
        "{e}"
    );
    // The bus goes when its last chip does.
    drop(one);
    h.unloadrt("all").unwrap();
    assert!(sim_bus(h.instance().name(), 1).is_none());
    assert!(sim_bus(h.instance().name(), 2).is_none());
}

#[test]
fn a_missing_bus_device_says_what_to_do() {
    let h = host("nobus");
    let e = load(&h, &pca9685::MODULE, &["bus=250"])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("pca9685: opening /dev/i2c-250: "), "{e}");
    assert!(e.contains("modprobe i2c-dev"), "{e}");
    assert!(h.loaded_components().is_empty());
}
