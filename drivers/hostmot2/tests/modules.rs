//! Every module on the simulated board, through HAL pins and registers:
//! GPIO directions, open drain and inversion; the watchdog's bite and
//! reset; encoder counts, index, latches, velocity; step rates, timing
//! and tables; PWM values, modes and frequencies; LEDs; raw access; the
//! per-cycle transfers; io_error and the safe state.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::{Named, Rig, PERIOD};
use hal_core::Value::{Bit, Float, S32, U32};
use hal_driver::sim::Dir;
use hostmot2::image::{pd, FirmwareSpec};
use hostmot2::regs::gtag;
use hostmot2::sim::boards::preset;
use hostmot2::sim::machine::{self, Machine};
use hostmot2::sim::{Bench, EncoderIn};

const DATA: usize = 0x1000;
const DDR: usize = 0x1100;
const ALT: usize = 0x1200;
const OD: usize = 0x1300;
const INV: usize = 0x1400;

fn bench(pins: usize, encoders: usize) -> Box<Bench> {
    Box::new(Bench {
        pins: vec![None; pins],
        encoders: vec![EncoderIn::default(); encoders],
        ..Bench::default()
    })
}

fn spec(name: &str) -> FirmwareSpec {
    preset(name).unwrap()
}

#[test]
fn gpio_directions_open_drain_and_inversion() {
    let mut r = Rig::new("hm2-gpio", spec("5i25"), bench(34, 2), "");
    // Load wrote invert, open drain, alternate source, then direction.
    let writes: Vec<usize> = r
        .sim
        .accesses()
        .iter()
        .filter(|a| a.dir == Dir::Write)
        .map(|a| a.addr as usize)
        .collect();
    let first = |addr| writes.iter().position(|&a| a == addr).unwrap();
    assert!(first(INV) < first(OD) && first(OD) < first(ALT) && first(ALT) < first(DDR));
    assert_eq!(
        r.reg(ALT),
        0x1FFF,
        "stepgen and encoder pins to their modules"
    );
    assert_eq!(r.reg(DDR), 0, "module outputs wait for the first write");
    r.cycle();
    assert_eq!(
        r.reg(DDR),
        0x3FF,
        "step/dir pins driven after the first write"
    );

    // A GPIO output, then inverted.
    r.set_param("gpio.013.is_output", Bit(true));
    r.set_pin("gpio.013.out", Bit(true));
    r.cycles(2);
    assert_eq!(r.reg(DDR) & 1 << 13, 1 << 13);
    assert_eq!(r.sim.with(|m| m.pin_driven(13)), Some(true));
    assert!(r.bit("gpio.013.in"));
    r.set_param("gpio.013.invert_output", Bit(true));
    r.cycles(2);
    assert_eq!(r.sim.with(|m| m.pin_driven(13)), Some(false));
    assert!(!r.bit("gpio.013.in") && r.bit("gpio.013.in_not"));

    // Open drain: TRUE releases the line (pull-up or whoever drives it).
    r.set_param("gpio.013.invert_output", Bit(false));
    r.set_param("gpio.013.is_opendrain", Bit(true));
    r.cycles(2);
    assert_eq!(r.reg(OD) & 1 << 13, 1 << 13);
    assert_eq!(r.sim.with(|m| m.pin_driven(13)), None);
    assert!(r.bit("gpio.013.in"), "pulled up");
    r.world(|b: &mut Bench| b.pins[13] = Some(false));
    r.cycles(2);
    assert!(!r.bit("gpio.013.in"), "someone else pulls it low");
    r.set_pin("gpio.013.out", Bit(false));
    r.cycles(2);
    assert_eq!(r.sim.with(|m| m.pin_driven(13)), Some(false));

    // An input follows the outside; nothing connected reads high.
    assert!(r.bit("gpio.014.in") && !r.bit("gpio.014.in_not"));
    r.world(|b: &mut Bench| b.pins[14] = Some(false));
    r.cycles(2);
    assert!(!r.bit("gpio.014.in") && r.bit("gpio.014.in_not"));
    // Open drain on an input never pulls the line low.
    r.set_param("gpio.015.is_opendrain", Bit(true));
    r.cycles(2);
    assert_eq!(r.reg(OD) & 1 << 15, 0);

    // Module outputs: inversion in the register, through the alias.
    r.set_param("stepgen.00.step.invert_output", Bit(true));
    r.cycles(1);
    assert_eq!(r.reg(INV) & 1, 1);
    // Configuration is written only when it changes.
    r.sim.clear_log();
    r.cycles(10);
    assert!(r
        .sim
        .accesses()
        .iter()
        .all(|a| a.dir == Dir::Read || ![DDR, OD, ALT, INV].contains(&(a.addr as usize))));
    // read_gpio / write_gpio move GPIO outside TRAM.
    r.world(|b: &mut Bench| b.pins[16] = Some(false));
    r.sim.advance(1000);
    r.board.read_gpio();
    assert!(!r.bit("gpio.016.in"));
    r.set_param("gpio.016.is_output", Bit(true));
    r.set_pin("gpio.016.out", Bit(true));
    r.board.write_gpio(PERIOD);
    assert_eq!(r.reg(DDR) & 1 << 16, 1 << 16);
    assert_eq!(r.sim.with(|m| m.read32(DATA)) & 1 << 16, 1 << 16);
}

#[test]
fn watchdog_bites_when_writes_stop_and_recovers() {
    let mut r = Rig::new("hm2-wd", spec("5i25"), bench(34, 2), "");
    assert_eq!(r.reg(0x0C00), 0x8000_0000, "asleep until the first write");
    r.board.read();
    r.board.write(PERIOD);
    assert_eq!(r.reg(0x0C00), 499_999, "5 ms at 100 MHz");
    r.sim.advance(PERIOD as u64);
    r.cycles(3);
    assert!(!r.bit("watchdog.has_bit"));
    // The HAL thread stops writing: reads alone do not pet it.
    for _ in 0..6 {
        r.board.read();
        r.sim.advance(PERIOD as u64);
    }
    assert_eq!(r.reg(0x0D00) & 1, 1, "bitten");
    assert_eq!(r.reg(DDR), 0, "every pin released");
    assert_eq!(r.sim.with(|m| m.pin_driven(0)), None);
    r.board.read();
    assert!(r.bit("watchdog.has_bit"));
    let said = r.messages();
    assert!(
        said.contains(
            &"hm2/hm2_5i25.0: Watchdog has bit! (set the .has_bit pin to False to resume)"
                .to_string()
        ),
        "{said:?}"
    );
    // Writes go on, but nothing is driven until has_bit is reset.
    r.cycles(3);
    assert_eq!(r.reg(DDR), 0);
    r.set_pin("watchdog.has_bit", Bit(false));
    r.board.read();
    r.board.write(PERIOD);
    assert_eq!(r.reg(DDR), 0x3FF, "configuration rewritten");
    assert_eq!(r.reg(0x0D00), 0);
    assert_eq!(r.reg(0x0C00), 499_999, "re-armed");
    assert!(r
        .messages()
        .iter()
        .any(|m| m.ends_with("trying to recover from IO error or Watchdog bite")));
    r.sim.advance(PERIOD as u64);
    r.cycles(10);
    assert!(!r.bit("watchdog.has_bit"));
    // A new timeout is written at the next write.
    r.set_param("watchdog.timeout_ns", U32(10_000_000));
    r.board.read();
    r.board.write(PERIOD);
    assert_eq!(r.reg(0x0C00), 999_999);
    // pet_watchdog keeps it from biting while write does not run.
    for _ in 0..20 {
        r.board.read();
        r.board.pet_watchdog();
        r.sim.advance(PERIOD as u64);
    }
    assert_eq!(r.reg(0x0D00) & 1, 0, "petted: no bite");
    r.board.write(PERIOD);
    // Shorter than 1.5 periods: a warning.
    r.set_param("watchdog.timeout_ns", U32(1_000_000));
    r.board.write(PERIOD);
    assert!(r
        .messages()
        .iter()
        .any(|m| m.contains("less than 1.5 times")));
}

#[test]
fn encoder_counts_velocity_reset_and_wrap() {
    let mut r = Rig::new("hm2-enc", spec("6i25"), bench(34, 4), "");
    let set = |r: &Rig, count: i64| r.world(|b: &mut Bench| b.encoders[0].count = count);
    set(&r, 1000);
    r.cycles(2);
    assert_eq!(r.s32("encoder.00.count"), 1000);
    assert_eq!(r.s32("encoder.00.rawcounts"), 1000);
    r.set_param("encoder.00.scale", Float(4000.0));
    r.cycles(2);
    assert_eq!(r.float("encoder.00.position"), 0.25);
    // 40 counts per ms: 10 units/s.
    for k in 1..=20 {
        set(&r, 1000 + 40 * k);
        r.cycle();
    }
    let v = r.float("encoder.00.velocity");
    assert!((v - 10.0).abs() < 0.05, "velocity {v}");
    assert!((r.float("encoder.00.velocity-rpm") - 600.0).abs() < 3.0);
    // Stopped: velocity falls, then 0 after vel-timeout (0.5 s).
    r.cycles(600);
    assert_eq!(r.float("encoder.00.velocity"), 0.0);
    // Across the 16-bit counter's wrap, both ways.
    let mut c = 1800;
    for _ in 0..5 {
        c += 30_000;
        set(&r, c);
        r.cycle();
    }
    r.cycle();
    assert_eq!(r.s32("encoder.00.count"), 151_800);
    for _ in 0..7 {
        c -= 30_000;
        set(&r, c);
        r.cycle();
    }
    r.cycle();
    assert_eq!(r.s32("encoder.00.count"), -58_200);
    // reset zeroes count and position while TRUE; rawcounts stay.
    r.set_pin("encoder.00.reset", Bit(true));
    set(&r, c + 10);
    r.cycles(2);
    assert_eq!(r.s32("encoder.00.count"), 0);
    assert_eq!(r.float("encoder.00.position"), 0.0);
    assert_eq!(r.s32("encoder.00.rawcounts"), -58_190);
    r.set_pin("encoder.00.reset", Bit(false));
    set(&r, c + 30);
    r.cycles(2);
    assert_eq!(r.s32("encoder.00.count"), 20);
}

#[test]
fn encoder_index_latch_and_control() {
    let mut r = Rig::new("hm2-idx", spec("6i25"), bench(34, 4), "");
    let ctl = |r: &Rig| r.sim.with(|m| m.encoder(1).unwrap().control);
    r.world(|b: &mut Bench| b.encoders[1].count = 100);
    r.cycles(2);
    assert_eq!(ctl(&r) & 1 << 11, 1 << 11, "filter on by default");
    r.set_pin("encoder.01.index-enable", Bit(true));
    r.cycle();
    assert_eq!(ctl(&r) & 0x50, 0x50, "latch on index, once");
    r.cycle();
    assert!(r.bit("encoder.01.index-enable"), "no index yet");
    r.world(|b: &mut Bench| {
        b.encoders[1].count = 500;
        b.encoders[1].index_at = Some(300);
    });
    r.cycles(2);
    assert!(!r.bit("encoder.01.index-enable"));
    assert_eq!(r.s32("encoder.01.count"), 200, "zeroed at the index");
    assert_eq!(r.s32("encoder.01.rawcounts"), 500);
    assert_eq!(r.s32("encoder.01.rawlatch"), 300);
    assert_eq!(r.s32("encoder.01.count-latched"), 300, "from the old zero");
    // no_clear_on_index: latched, not zeroed.
    r.set_pin("encoder.01.no_clear_on_index", Bit(true));
    r.set_pin("encoder.01.index-enable", Bit(true));
    r.cycle();
    r.world(|b: &mut Bench| {
        b.encoders[1].count = 900;
        b.encoders[1].index_at = Some(700);
    });
    r.cycles(2);
    assert!(!r.bit("encoder.01.index-enable"));
    assert_eq!(r.s32("encoder.01.count"), 600);
    assert_eq!(r.s32("encoder.01.count-latched"), 400);
    assert_eq!(r.s32("encoder.01.rawlatch"), 700);
    // Params into the control word.
    r.set_param("encoder.01.counter-mode", Bit(true));
    r.set_param("encoder.01.filter", Bit(false));
    r.set_param("encoder.01.index-invert", Bit(true));
    r.set_param("encoder.01.index-mask", Bit(true));
    r.cycle();
    assert_eq!(ctl(&r) & 0xFF8, 1 << 10 | 1 << 9 | 1 << 3);
    // Quadrature errors are reported while enabled and cleared by a new
    // rising edge of quad-error-enable.
    r.set_pin("encoder.01.quad-error-enable", Bit(true));
    r.world(|b: &mut Bench| b.encoders[1].glitch = true);
    r.cycles(2);
    assert!(r.bit("encoder.01.quad-error"));
    r.set_pin("encoder.01.quad-error-enable", Bit(false));
    r.cycle();
    assert!(!r.bit("encoder.01.quad-error"));
    r.set_pin("encoder.01.quad-error-enable", Bit(true));
    r.cycles(2);
    assert!(
        !r.bit("encoder.01.quad-error"),
        "cleared by the rising edge"
    );
    // The live lines.
    r.world(|b: &mut Bench| {
        b.encoders[1].a = true;
        b.encoders[1].z = true;
    });
    r.cycles(2);
    assert!(r.bit("encoder.01.input-a") && !r.bit("encoder.01.input-b"));
    assert!(r.bit("encoder.01.input-index"));
    // The filter clock: 25 MHz asked, 33.3 MHz is what 66.67 MHz gives.
    assert_eq!(r.pin("encoder.sample-frequency"), U32(33_333_333));
    assert_eq!(r.reg(0x3400), 0);
    r.set_pin("encoder.hires-timestamp", Bit(true));
    r.cycle();
    assert_eq!(r.reg(0x3200), 4, "66.67 MHz / 10 MHz - 2");
}

#[test]
fn encoder_probe_latch() {
    let mut s = spec("6i25");
    s.pins[12] = pd(gtag::ENCODER, 2, 5); // a probe input for encoder 2
    let mut r = Rig::new("hm2-probe", s, bench(34, 4), "");
    r.world(|b: &mut Bench| b.encoders[2].count = 50);
    r.cycles(2);
    r.set_pin("encoder.02.probe-invert", Bit(true));
    r.set_pin("encoder.02.probe-enable", Bit(true));
    r.world(|b: &mut Bench| b.pins[12] = Some(false));
    r.cycles(2);
    assert!(r.bit("encoder.02.probe-enable"));
    r.world(|b: &mut Bench| b.pins[12] = Some(true));
    r.cycle();
    r.world(|b: &mut Bench| b.encoders[2].count = 80);
    r.cycles(2);
    assert!(!r.bit("encoder.02.probe-enable"));
    assert_eq!(r.s32("encoder.02.count-latched"), 50);
    assert_eq!(r.s32("encoder.02.count"), 80, "probe does not zero");
}

fn stepper_rig(tag: &str) -> Rig {
    let r = Rig::new(tag, spec("5i25"), Box::new(machine::preset("5i25")), "");
    for t in ["steplen", "stepspace", "dirsetup", "dirhold"] {
        r.set_param(&format!("stepgen.00.{t}"), U32(1000));
    }
    r.set_param("stepgen.00.position-scale", Float(100.0));
    r.set_param("stepgen.00.maxaccel", Float(0.0));
    r.set_pin("stepgen.00.enable", Bit(true));
    r
}

fn axis_steps(r: &Rig, k: usize) -> i64 {
    r.world(|m: &mut Machine| m.steppers[k].axis.steps())
}

#[test]
fn stepgen_position_and_velocity_modes() {
    let mut r = Rig::new(
        "hm2-sgdef",
        spec("5i25"),
        Box::new(machine::preset("5i25")),
        "",
    );
    assert_eq!(
        r.param("stepgen.00.steplen"),
        U32(163_830),
        "slowest by default"
    );
    r.cycle();
    assert_eq!(r.reg(0x2500), 16_382);
    drop(r);

    let mut r = stepper_rig("hm2-sg");
    r.set_pin("stepgen.00.position-cmd", Float(2.0));
    r.cycles(50);
    assert_eq!(r.reg(0x2500), 99, "1 us = 100 clocks, N + 1 clocks");
    assert_eq!(r.reg(0x2300), 99);
    assert!((r.float("stepgen.00.position-fb") - 2.0).abs() < 0.01);
    let counts = r.s32("stepgen.00.counts");
    assert!((199..=200).contains(&counts), "{counts}");
    assert_eq!(
        axis_steps(&r, 0),
        counts as i64,
        "the motor made every step"
    );
    assert_eq!(r.float("stepgen.00.velocity-fb"), 0.0);
    // Back to -1.5.
    r.set_pin("stepgen.00.position-cmd", Float(-1.5));
    r.cycles(50);
    let counts = r.s32("stepgen.00.counts");
    assert!((-151..=-150).contains(&counts), "{counts}");
    assert_eq!(axis_steps(&r, 0), counts as i64);
    // Velocity mode: 1 unit/s is 100 steps/s.
    r.set_pin("stepgen.00.control-type", Bit(true));
    r.set_pin("stepgen.00.velocity-cmd", Float(1.0));
    r.cycles(2);
    let rate = r.reg(0x2000) as i32;
    assert_eq!(rate, 4295, "100 steps/s × 2^32 / 100 MHz, rounded");
    assert_eq!(r.s32("stepgen.00.dbg_step_rate"), rate);
    r.cycles(1000);
    let moved = r.s32("stepgen.00.counts") - counts;
    assert!((99..=101).contains(&moved), "{moved} steps in a second");
    // Disabled: rate 0 at once.
    r.set_pin("stepgen.00.enable", Bit(false));
    r.cycle();
    assert_eq!(r.reg(0x2000), 0);
    assert_eq!(r.float("stepgen.00.velocity-fb"), 0.0);
    // position-reset zeroes the feedback.
    r.set_pin("stepgen.00.position-reset", Bit(true));
    r.cycle();
    assert_eq!(r.float("stepgen.00.position-fb"), 0.0);
    assert_eq!(r.s32("stepgen.00.counts"), 0);
}

#[test]
fn stepgen_timing_limits_rate_and_is_clamped() {
    let mut r = stepper_rig("hm2-sgt");
    // 50 us + 50 us: at most 10 kHz = 100 units/s.
    r.set_param("stepgen.00.steplen", U32(50_000));
    r.set_param("stepgen.00.stepspace", U32(50_000));
    r.set_pin("stepgen.00.control-type", Bit(true));
    r.set_pin("stepgen.00.velocity-cmd", Float(1000.0));
    r.cycles(5);
    assert!((r.float("stepgen.00.velocity-fb") - 100.0).abs() < 1e-9);
    r.cycles(100);
    let made = axis_steps(&r, 0);
    assert!(
        (1040..=1050).contains(&made),
        "{made} steps in 105 ms at 10 kHz"
    );
    // Longer than the 14-bit registers hold: clamped, param rewritten.
    r.set_param("stepgen.00.steplen", U32(1_000_000));
    r.cycle();
    assert_eq!(r.reg(0x2500), 0x3FFF);
    assert_eq!(r.param("stepgen.00.steplen"), U32(163_840));
    assert!(r.messages().iter().any(|m| m.contains("clamped to 0x3FFF")));
}

#[test]
fn stepgen_step_types_and_tables() {
    let mut r = stepper_rig("hm2-sgtab");
    r.cycle();
    assert_eq!(r.reg(0x2200) & 0xFF, 0);
    r.set_param("stepgen.00.step_type", U32(2));
    r.cycle();
    assert_eq!(r.reg(0x2200) & 3, 2, "quadrature");
    r.set_param("stepgen.00.step_type", U32(4));
    r.set_param("stepgen.00.table-data-0", U32(0x0804_0201));
    r.cycle();
    assert_eq!(r.reg(0x2200) & 3, 3, "table");
    assert_eq!(r.reg(0x2800), 3, "length − 1");
    let table = r.sim.with(|m| m.stepgen(0).unwrap().table.clone());
    assert_eq!(table, vec![8, 4, 2, 1], "last phase first");
    r.set_param("stepgen.00.step_type", U32(40));
    r.cycle();
    assert_eq!(r.param("stepgen.00.step_type"), U32(16));
}

#[test]
fn stepgen_index_latch_on_0xc2() {
    let mut s = spec("5i24");
    s.pins[71] = pd(gtag::STEPGEN, 0, 0x01); // index input of stepgen 0
    let world = Machine {
        pins: vec![None; 72],
        ..machine::preset("5i24")
    };
    let mut r = Rig::new("hm2-sgidx", s, Box::new(world), "");
    assert_eq!(r.pin("stepgen.00.index-enable"), Bit(false));
    r.set_param("stepgen.00.position-scale", Float(100.0));
    for t in ["steplen", "stepspace", "dirsetup", "dirhold"] {
        r.set_param(&format!("stepgen.00.{t}"), U32(1000));
    }
    r.set_pin("stepgen.00.enable", Bit(true));
    r.set_pin("stepgen.00.control-type", Bit(true));
    r.set_param("stepgen.00.maxaccel", Float(0.0));
    r.set_pin("stepgen.00.velocity-cmd", Float(10.0));
    r.set_pin("stepgen.00.index-invert", Bit(true));
    r.world(|m: &mut Machine| m.pins[71] = Some(false));
    r.cycles(100);
    r.set_pin("stepgen.00.index-enable", Bit(true));
    r.cycles(2);
    assert_eq!(r.reg(0x2200) & 0x30, 0x30, "latch on a rising index");
    let before = r.float("stepgen.00.position-fb");
    r.world(|m: &mut Machine| m.pins[71] = Some(true));
    r.cycles(3);
    assert!(!r.bit("stepgen.00.index-enable"));
    let latched = r.float("stepgen.00.position-latch");
    assert!(
        latched > before && latched < before + 0.03,
        "{before} {latched}"
    );
    assert!(
        r.float("stepgen.00.position-fb") < 0.05,
        "restarted at the index"
    );
    // 0xC2 has swap_step_dir.
    r.set_param("stepgen.00.swap_step_dir", Bit(true));
    r.cycle();
    assert_eq!(r.reg(0x2200) & 4, 4);
}

#[test]
fn pwm_values_modes_and_frequencies() {
    let mut r = Rig::new("hm2-pwm", spec("6i25"), bench(34, 4), "");
    let out = |r: &Rig| r.sim.with(|m| m.pwm_output(0));
    r.set_pin("pwmgen.00.enable", Bit(true));
    r.set_pin("pwmgen.00.value", Float(0.5));
    r.cycle();
    let o = out(&r);
    assert!(o.enabled);
    assert!((o.duty - 0.5).abs() < 2.0 / 4096.0, "{}", o.duty);
    assert!((o.frequency_hz - 20_000.0).abs() < 1.0);
    assert_eq!(r.reg(0x4000), (0.5 * 4095.0 * 65536.0) as u32);
    assert_eq!(
        r.reg(0x4100),
        3 | 1 << 5,
        "12 bits, PWM/dir, double buffered"
    );
    assert_eq!(r.reg(0x4400), 1);
    assert_eq!(r.sim.with(|m| m.pin_driven(19)), Some(false), "/enable low");
    r.set_pin("pwmgen.00.value", Float(-0.25));
    r.cycle();
    assert!((out(&r).duty + 0.25).abs() < 2.0 / 4096.0);
    assert_eq!(r.sim.with(|m| m.pin_driven(18)), Some(true), "direction");
    r.set_param("pwmgen.00.scale", Float(10.0));
    r.set_pin("pwmgen.00.value", Float(5.0));
    r.cycle();
    assert!((out(&r).duty - 0.5).abs() < 2.0 / 4096.0);
    r.set_pin("pwmgen.00.enable", Bit(false));
    r.cycle();
    assert_eq!(r.reg(0x4400), 0);
    assert_eq!(r.reg(0x4000), 0);
    assert!(!out(&r).enabled);
    assert_eq!(r.sim.with(|m| m.pin_driven(19)), Some(true), "/enable high");
    // Output types and their mode bits.
    for (ty, bits) in [(2, 2 << 3 | 1 << 5), (3, 3 << 3), (4, 1 << 3 | 1 << 5)] {
        r.set_param("pwmgen.00.output-type", S32(ty));
        r.cycle();
        assert_eq!(r.reg(0x4100), 3 | bits, "output-type {ty}");
    }
    r.set_param("pwmgen.00.output-type", S32(9));
    r.cycle();
    assert_eq!(r.param("pwmgen.00.output-type"), S32(1));
    // Frequencies: 100 kHz needs 10 bits; too high is clamped.
    r.set_param("pwmgen.pwm_frequency", U32(100_000));
    r.cycle();
    assert_eq!(r.reg(0x4200), 33_554);
    assert_eq!(r.reg(0x4100) & 3, 1);
    r.set_param("pwmgen.pwm_frequency", U32(5_000_000));
    r.cycle();
    assert_eq!(r.param("pwmgen.pwm_frequency"), U32(390_619));
    r.set_param("pwmgen.pdm_frequency", U32(1_000_000));
    r.cycle();
    assert_eq!(r.reg(0x4300), 327);
    // Offset mode: 0 is 50 %; dither sets its mode bit (firmware v1).
    r.set_param("pwmgen.pwm_frequency", U32(20_000));
    r.set_param("pwmgen.01.offset-mode", Bit(true));
    r.set_param("pwmgen.01.dither", Bit(true));
    r.set_pin("pwmgen.01.enable", Bit(true));
    r.cycle();
    assert_eq!(r.reg(0x4104) & 1 << 6, 1 << 6);
    let o = r.sim.with(|m| m.pwm_output(1));
    assert!(
        (o.duty - 0.5).abs() < 1e-3,
        "{o:?} {:x} {:x}",
        r.reg(0x4004),
        r.reg(0x4104)
    );
}

#[test]
fn leds_and_raw_access() {
    let mut r = Rig::new("hm2-raw", spec("5i25"), bench(34, 2), "enable_raw");
    r.set_pin("led.CR01", Bit(true));
    r.cycle();
    assert_eq!(r.reg(0x0200), 0x8000_0000);
    r.set_pin("led.CR02", Bit(true));
    r.cycle();
    assert_eq!(r.reg(0x0200), 0xC000_0000);
    r.set_pin("raw.read_address", U32(0x0100));
    r.cycles(2);
    assert_eq!(r.pin("raw.read_data"), U32(0x55AA_CAFE));
    r.set_pin("led.CR01", Bit(false));
    r.set_pin("led.CR02", Bit(false));
    r.cycle();
    r.set_pin("raw.write_address", U32(0x0200));
    r.set_pin("raw.write_data", U32(0x4000_0000));
    r.set_pin("raw.write_strobe", Bit(true));
    r.cycle();
    assert_eq!(r.reg(0x0200), 0x4000_0000);
    assert!(!r.bit("raw.write_strobe"), "cleared by write");
    r.set_pin("raw.dump_state", Bit(true));
    r.cycle();
    assert!(!r.bit("raw.dump_state"));
    assert!(r
        .messages()
        .iter()
        .any(|m| m.starts_with("hm2/hm2_5i25.0: dump_state:")));
}

#[test]
fn one_burst_per_region_and_the_timestamp_first() {
    let mut r = Rig::new(
        "hm2-tram",
        spec("5i24"),
        Box::new(machine::preset("5i24")),
        "",
    );
    r.cycles(3);
    r.sim.clear_log();
    r.board.read();
    let reads: Vec<usize> = r.sim.accesses().iter().map(|a| a.addr as usize).collect();
    // IOPort data, watchdog status, TSCount, 8 counters, 8 latches, 8
    // accumulators, 8 modes.
    assert_eq!(reads.len(), 3 + 1 + 1 + 8 * 4);
    let at = |addr| reads.iter().position(|&a| a == addr).unwrap();
    assert!(at(0x3300) < at(0x3000), "timestamp before counts");
    assert_eq!(&reads[..3], &[0x1000, 0x1004, 0x1008]);
    r.sim.clear_log();
    r.board.write(PERIOD);
    let writes: Vec<usize> = r.sim.accesses().iter().map(|a| a.addr as usize).collect();
    // Steady state: pet, IOPort data, 8 PWM values, 8 rates.
    assert_eq!(writes.len(), 1 + 3 + 8 + 8, "{writes:x?}");
}

#[test]
fn safe_state_releases_everything_at_once() {
    let mut r = Rig::new(
        "hm2-safe",
        spec("5i24"),
        Box::new(machine::preset("5i24")),
        "",
    );
    r.set_pin("pwmgen.00.enable", Bit(true));
    r.set_pin("pwmgen.00.value", Float(0.5));
    r.set_pin("stepgen.00.enable", Bit(true));
    r.set_param("stepgen.00.maxaccel", Float(0.0));
    r.set_param("stepgen.00.position-scale", Float(100.0));
    r.set_pin("stepgen.00.position-cmd", Float(100.0));
    r.cycles(3);
    assert_ne!(r.reg(0x2000), 0);
    assert_eq!(r.reg(0x4400) & 1, 1);
    r.board.go_safe();
    assert_eq!(r.reg(0x4400), 0);
    assert_eq!(r.reg(0x2000), 0);
    assert_eq!(r.reg(DDR) | r.reg(DDR + 4) | r.reg(DDR + 8), 0);
    r.sim.advance(1000);
    assert_eq!(r.reg(0x0D00) & 1, 1, "the watchdog bit");
}
