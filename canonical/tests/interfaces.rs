//! The canonical interfaces behave as their definitions say.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use canonical::Converter;
use canonical::*;
use hal_core::{ComponentKind, Host, HostConfig, Value};

fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(&format!("canon-{tag}"))).unwrap()
}

#[test]
fn digital_inputs_and_outputs() {
    let host = host("dig");
    let inst = host.instance();
    let comp = inst.new_component("dev", ComponentKind::User).unwrap();
    let names = ChannelNames::canonical::<DigIn>("dev", 0, 16);
    let din = DigIn::export(&comp, &names, 3).unwrap();
    assert_eq!(
        inst.pin_value("dev.0.digin.03.in-not").unwrap(),
        Value::Bit(true)
    );
    din.update(true);
    assert_eq!(
        inst.pin_value("dev.0.digin.03.in").unwrap(),
        Value::Bit(true)
    );
    assert_eq!(
        inst.pin_value("dev.0.digin.03.in-not").unwrap(),
        Value::Bit(false)
    );

    let dout = DigOut::export(&comp, &ChannelNames::canonical::<DigOut>("dev", 0, 4), 1).unwrap();
    assert!(!dout.level());
    inst.set_pin("dev.0.digout.1.out", Value::Bit(true))
        .unwrap();
    assert!(dout.level());
    inst.set_param("dev.0.digout.1.invert", Value::Bit(true))
        .unwrap();
    assert!(!dout.level());
    assert!(dout.safe_level(), "off, inverted, is a high level");
}

#[test]
fn analog_inputs_scale_and_offset() {
    let host = host("adcin");
    let inst = host.instance();
    let comp = inst.new_component("dev", ComponentKind::User).unwrap();
    let ain = AdcIn::export(
        &comp,
        &ChannelNames::canonical::<AdcIn>("dev", 0, 8),
        0,
        10.0 / 2048.0,
        10.0,
    )
    .unwrap();
    ain.update_counts(3072);
    assert_eq!(
        inst.pin_value("dev.0.adcin.0.value").unwrap(),
        Value::Float(5.0)
    );
    inst.set_param("dev.0.adcin.0.scale", Value::Float(2.0))
        .unwrap();
    inst.set_param("dev.0.adcin.0.offset", Value::Float(1.0))
        .unwrap();
    ain.update_volts(5.0);
    assert_eq!(
        inst.pin_value("dev.0.adcin.0.value").unwrap(),
        Value::Float(9.0)
    );
}

#[test]
fn analog_outputs_enable_limits_and_counts() {
    let host = host("adcout");
    let inst = host.instance();
    let comp = inst.new_component("dev", ComponentKind::User).unwrap();
    let opts = AdcOutOptions {
        limits: Some((10.0, -10.0)),
        converter: Some(Converter {
            bit_weight: 10.0 / 2048.0,
            hw_offset: -10.0,
            min_count: 0,
            max_count: 4095,
        }),
    };
    let aout = AdcOut::export(
        &comp,
        &ChannelNames::canonical::<AdcOut>("dev", 0, 4),
        2,
        opts,
    )
    .unwrap();
    assert_eq!(aout.volts(), None, "disabled by default");
    assert_eq!(
        aout.counts(),
        Some(2048),
        "disabled outputs the count for 0 V"
    );
    inst.set_pin("dev.0.adcout.2.enable", Value::Bit(true))
        .unwrap();
    inst.set_pin("dev.0.adcout.2.value", Value::Float(2.5))
        .unwrap();
    inst.set_param("dev.0.adcout.2.scale", Value::Float(2.0))
        .unwrap();
    inst.set_param("dev.0.adcout.2.offset", Value::Float(0.5))
        .unwrap();
    assert_eq!(aout.volts(), Some(5.5));
    inst.set_pin("dev.0.adcout.2.value", Value::Float(100.0))
        .unwrap();
    assert_eq!(aout.volts(), Some(10.0), "clamped to high_limit");
    assert_eq!(
        aout.counts(),
        Some(4095),
        "clamped to the converter's range"
    );
    inst.set_pin("dev.0.adcout.2.value", Value::Float(f64::NAN))
        .unwrap();
    assert_eq!(aout.volts(), Some(0.0), "a NaN value outputs 0 V");
    assert_eq!(aout.counts(), Some(2048));
    // Limits set the wrong way round never panic.
    inst.set_param("dev.0.adcout.2.low_limit", Value::Float(20.0))
        .unwrap();
    inst.set_pin("dev.0.adcout.2.value", Value::Float(0.0))
        .unwrap();
    assert_eq!(aout.volts(), Some(20.0));
}

#[test]
fn encoder_pins_follow_the_index_handshake() {
    let host = host("enc");
    let inst = host.instance();
    let comp = inst.new_component("hm", ComponentKind::User).unwrap();
    let names = ChannelNames::canonical::<Encoder>("hm", 0, 12);
    let mut enc = Encoder::export(&comp, &names, 1, 16).unwrap();
    inst.set_param("hm.0.encoder.01.scale", Value::Float(4.0))
        .unwrap();
    enc.update(0, None, 0);
    enc.update(40, None, 1_000_000);
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.position").unwrap(),
        Value::Float(10.0)
    );
    // Not armed: an index seen by the hardware changes nothing.
    enc.update(44, Some(42), 2_000_000);
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.count").unwrap(),
        Value::S32(44)
    );
    // Armed: count restarts at the index; index-enable is cleared.
    inst.set_pin("hm.0.encoder.01.index-enable", Value::Bit(true))
        .unwrap();
    assert!(enc.index_armed());
    enc.update(50, Some(46), 3_000_000);
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.count").unwrap(),
        Value::S32(4)
    );
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.rawcounts").unwrap(),
        Value::S32(50)
    );
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.position-latched").unwrap(),
        Value::Float(11.5)
    );
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.index-enable").unwrap(),
        Value::Bit(false)
    );
    // A zero scale is replaced rather than dividing by zero.
    inst.set_param("hm.0.encoder.01.scale", Value::Float(0.0))
        .unwrap();
    enc.update(52, None, 4_000_000);
    assert_eq!(
        inst.param_value("hm.0.encoder.01.scale").unwrap(),
        Value::Float(1.0)
    );
    assert_eq!(
        inst.pin_value("hm.0.encoder.01.position").unwrap(),
        Value::Float(6.0)
    );
}

#[test]
fn pwm_duty_follows_enable_value_and_scale() {
    let host = host("pwm");
    let inst = host.instance();
    let comp = inst.new_component("hm", ComponentKind::User).unwrap();
    let pwm = Pwm::export(&comp, &ChannelNames::canonical::<Pwm>("hm", 0, 4), 0).unwrap();
    assert_eq!(pwm.duty(), None);
    inst.set_pin("hm.0.pwmgen.0.enable", Value::Bit(true))
        .unwrap();
    inst.set_pin("hm.0.pwmgen.0.value", Value::Float(-5.0))
        .unwrap();
    inst.set_param("hm.0.pwmgen.0.scale", Value::Float(10.0))
        .unwrap();
    assert_eq!(pwm.duty(), Some(-0.5));
    // A zero scale is replaced by 1.0, as the encoder's and stepgen's.
    inst.set_param("hm.0.pwmgen.0.scale", Value::Float(0.0))
        .unwrap();
    assert_eq!(pwm.duty(), Some(-1.0));
    assert_eq!(
        inst.param_value("hm.0.pwmgen.0.scale").unwrap(),
        Value::Float(1.0)
    );
}

#[test]
fn each_interface_names_its_own_io_type() {
    // The io-type fields hal_canonical-devices defines, and hostmot2's.
    assert_eq!(DigIn::IO_TYPE, "digin");
    assert_eq!(DigOut::IO_TYPE, "digout");
    assert_eq!(AdcIn::IO_TYPE, "adcin");
    assert_eq!(AdcOut::IO_TYPE, "adcout");
    assert_eq!(Encoder::IO_TYPE, "encoder");
    assert_eq!(Stepgen::IO_TYPE, "stepgen");
    assert_eq!(Pwm::IO_TYPE, "pwmgen");
}

#[test]
fn stepgen_rate_follows_enable_mode_and_scale() {
    let host = host("stepgen");
    let inst = host.instance();
    let comp = inst.new_component("hm", ComponentKind::User).unwrap();
    let mut sg =
        Stepgen::export(&comp, &ChannelNames::canonical::<Stepgen>("hm", 0, 10), 0).unwrap();
    let set = |n: &str, v: Value| {
        if inst.set_pin(n, v).is_err() {
            inst.set_param(n, v).unwrap();
        }
    };
    set("hm.0.stepgen.0.position-scale", Value::Float(100.0));
    set("hm.0.stepgen.0.maxaccel", Value::Float(0.0));
    set("hm.0.stepgen.0.maxvel", Value::Float(5.0));
    set("hm.0.stepgen.0.position-cmd", Value::Float(1.0));
    assert_eq!(sg.update(0, 0.0, 1_000_000), 0.0, "disabled");
    set("hm.0.stepgen.0.enable", Value::Bit(true));
    assert_eq!(
        sg.update(0, 0.0, 1_000_000),
        500.0,
        "5 units/s at 100 steps per unit"
    );
    assert_eq!(
        inst.pin_value("hm.0.stepgen.0.velocity-fb").unwrap(),
        Value::Float(5.0)
    );
    set("hm.0.stepgen.0.control-type", Value::Bit(true));
    set("hm.0.stepgen.0.velocity-cmd", Value::Float(-2.0));
    assert_eq!(sg.update(250, 250.5, 1_000_000), -200.0);
    assert_eq!(
        inst.pin_value("hm.0.stepgen.0.counts").unwrap(),
        Value::S32(250)
    );
    assert_eq!(
        inst.pin_value("hm.0.stepgen.0.position-fb").unwrap(),
        Value::Float(2.505)
    );
    set("hm.0.stepgen.0.steplen", Value::U32(5000));
    assert_eq!(sg.timing(100_000_000).steplen, 500);
}
