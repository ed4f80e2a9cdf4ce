//! `hy_gt_vfd` against the simulated GT drive, on simulated time: every
//! pin, the frames of a cycle byte for byte, run, reverse, stop,
//! at-speed, the drive's own faults, refusals, a dead drive, an
//! unplugged line.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use common::*;
use hal_core::{PinDir, Value};
use hal_serial::line::{LineSettings, Parity, SimLine};
use hal_serial::regs::gt;
use hal_serial::sim::RunCommand;
use hal_serial::vfd::gt::{parse_options, sim_drive, GtOptions, GtVfd};
use hal_serial::vfd::Cycle;

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

const CLI: &[&str] = &["-S", "24000", "-F", "400", "-f", "120"];

type GtRig = Rig<GtVfd<SimLine>>;

fn rig(tag: &str) -> GtRig {
    let opts: GtOptions = parse_options(&args(CLI)).unwrap().unwrap();
    let sim = Arc::new(Mutex::new(sim_drive(&opts)));
    let name = opts.name.clone();
    Rig::new(tag, &name, sim, |comp, line| {
        GtVfd::new(comp, opts, line).unwrap()
    })
}

impl GtRig {
    fn run(&self, rpm: f64) {
        self.set("spindle-on", Value::Bit(true));
        self.set("speed-cmd", Value::Float(rpm));
    }
}

/// A read of one holding register.
fn read(address: u16) -> Vec<u8> {
    let [hi, lo] = address.to_be_bytes();
    frame(&[1, 0x03, hi, lo, 0, 1])
}

/// A write of one register.
fn write(address: u16, value: u16) -> Vec<u8> {
    let [hi, lo] = address.to_be_bytes();
    let [vh, vl] = value.to_be_bytes();
    frame(&[1, 0x06, hi, lo, vh, vl])
}

const STATUS: [u16; 13] = [
    0x3000, 0x3002, 0x3003, 0x3004, 0x3005, 0x3006, 0x300A, 0x300B, 0x300C, 0x300D, 0x3010, 0x3014,
    0x5000,
];

#[test]
fn every_pin_has_linuxcnc_name_type_and_direction() {
    let r = rig("gt-pins");
    let mut want: Vec<(String, String, PinDir)> = Vec::new();
    let mut add = |n: &str, t: &str, d: PinDir| want.push((n.into(), t.into(), d));
    add("period-seconds", "float", PinDir::In);
    add("speed-cmd", "float", PinDir::In);
    add("spindle-on", "bit", PinDir::In);
    add("freq-cmd", "float", PinDir::Out);
    add("at-speed", "bit", PinDir::Out);
    add("modbus-errors", "u32", PinDir::Out);
    // LinuxCNC 2.10 added it beside the float fault-info.
    add("fault-info-code", "u32", PinDir::Out);
    for n in [
        "freq-fb",
        "dc-bus-voltage",
        "output-voltage",
        "output-current",
        "speed-fb",
        "output-power",
        "input-terminal",
        "output-terminal",
        "AI1",
        "AI2",
        "HDI-frequency",
        "external-counter",
        "fault-info",
    ] {
        add(n, "float", PinDir::Out);
    }
    add("modbus-ok", "bit", PinDir::Out);
    add("fault", "bit", PinDir::Out);
    add("last-error", "s32", PinDir::Out);
    want.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(pins_of(&r.inst, "hy_gt_vfd"), want);
    assert_eq!(r.float("period-seconds"), 0.1);
}

#[test]
fn a_cycle_writes_command_and_frequency_then_reads_every_status_register() {
    let mut r = rig("gt-cycle");
    r.run(12_000.0);
    r.cycle();
    let mut want = vec![write(gt::CONTROL, 1), write(gt::FREQUENCY, 5000)];
    want.extend(STATUS.iter().map(|&a| read(a)));
    assert_eq!(take_requests(&r.sim), want);
    // The first of them, byte for byte as on the wire.
    assert_eq!(want[0], [0x01, 0x06, 0x10, 0x00, 0x00, 0x01, 0x4C, 0xCA]);
    assert_eq!(r.float("freq-cmd"), 200.0);
    r.set("spindle-on", Value::Bit(false));
    r.cycle();
    let req = take_requests(&r.sim);
    assert_eq!(req[0], write(gt::CONTROL, 5), "stop");
    assert_eq!(req[1], read(0x3000), "no frequency while stopped");
    assert_eq!(r.float("freq-cmd"), 0.0);
}

#[test]
fn runs_to_speed_and_reports_every_reading() {
    let mut r = rig("gt-run");
    r.run(12_000.0);
    r.cycles(10);
    assert!(near(r.float("freq-fb"), 200.0, 1e-9));
    assert!(near(r.float("speed-fb"), 12_000.0, 1.0));
    assert!(r.bit("at-speed"));
    assert_eq!(r.float("dc-bus-voltage"), 311.0);
    assert_eq!(r.float("output-voltage"), 110.0);
    assert!(r.float("output-current") > 0.0 && r.float("output-power") > 0.0);
    assert_eq!(r.float("fault-info"), 0.0);
    assert_eq!(r.get("fault-info-code"), Value::U32(0));
    assert!(r.bit("modbus-ok") && !r.bit("fault"));
    assert_eq!(r.get("modbus-errors"), Value::U32(0));
    assert_eq!(lock(&r.sim).model().command(), RunCommand::Forward);
    // The command moved on faster than the spindle: not at speed.
    r.set("speed-cmd", Value::Float(16_000.0));
    r.vfd.cycle();
    assert!(!r.bit("at-speed"));
}

#[test]
fn a_negative_speed_runs_in_reverse() {
    let mut r = rig("gt-reverse");
    r.run(-6_000.0);
    r.cycle();
    let req = take_requests(&r.sim);
    assert_eq!(req[0], write(gt::CONTROL, 2));
    assert_eq!(req[1], write(gt::FREQUENCY, 3000), "120 Hz floor: 30.00 %");
    assert_eq!(r.float("freq-cmd"), -120.0);
    r.cycles(5);
    assert!(lock(&r.sim).model().rpm() < -7_000.0);
    assert!(near(r.float("speed-fb"), 7_200.0, 1.0), "magnitude");
    r.set("speed-cmd", Value::Float(-7_200.0));
    r.vfd.cycle();
    assert!(r.bit("at-speed"));
}

#[test]
fn frequency_is_clamped_to_the_command_line_limits() {
    let mut r = rig("gt-clamp");
    r.run(48_000.0);
    r.cycle();
    assert_eq!(take_requests(&r.sim)[1], write(gt::FREQUENCY, 10_000));
    assert_eq!(r.float("freq-cmd"), 400.0);
}

#[test]
fn the_period_pin_sets_the_cycle_time() {
    let mut r = rig("gt-period");
    assert_eq!(r.vfd.period(), Duration::from_millis(100));
    r.set("period-seconds", Value::Float(0.5));
    assert_eq!(r.vfd.period(), Duration::from_millis(500));
    r.set("period-seconds", Value::Float(0.0));
    assert_eq!(r.vfd.period(), Duration::from_millis(1), "at least 1 ms");
    r.set("period-seconds", Value::Float(9.0));
    assert_eq!(r.vfd.period(), Duration::from_secs(2), "at most 2 s");
    r.cycle();
}

#[test]
fn a_drive_fault_raises_the_fault_pin_until_it_clears() {
    let mut r = rig("gt-drive-fault");
    r.run(12_000.0);
    r.cycles(10);
    lock(&r.sim).model_mut().trip(17);
    r.cycle();
    assert_eq!(r.float("fault-info"), 17.0);
    assert_eq!(r.get("fault-info-code"), Value::U32(17));
    assert!(r.bit("fault") && r.bit("modbus-ok"));
    assert!(!r.bit("at-speed"), "the spindle coasts");
    r.cycles(2);
    assert!(r.bit("fault"));
    lock(&r.sim).model_mut().reset_fault();
    r.cycle();
    assert!(!r.bit("fault"));
    r.cycles(10);
    assert!(
        r.bit("at-speed"),
        "runs again: the run command is sent every cycle"
    );
}

#[test]
fn a_refused_register_is_reported_and_the_rest_still_read() {
    let mut r = rig("gt-refusal");
    r.run(12_000.0);
    // The third request of the cycle (the read of 0x3000) is refused.
    lock(&r.sim).faults.silent = 0;
    r.cycle();
    lock(&r.sim).faults.exception = Some((0x02, 1));
    take_requests(&r.sim);
    r.cycle();
    assert_eq!(take_requests(&r.sim).len(), 15, "the cycle went on");
    assert!(
        r.bit("modbus-ok") && !r.bit("fault"),
        "a refusal is an answer"
    );
    assert_eq!(r.get("last-error"), Value::S32(-2));
    assert_eq!(r.get("modbus-errors"), Value::U32(1));
}

#[test]
fn a_dead_drive_ends_the_cycle_and_raises_fault_then_recovers() {
    let mut r = rig("gt-dead");
    r.run(12_000.0);
    r.cycles(10);
    lock(&r.sim).faults.dead = true;
    take_requests(&r.sim);
    let t0 = r.now();
    r.vfd.cycle();
    let took = r.now() - t0;
    assert_eq!(
        take_requests(&r.sim).len(),
        6,
        "one request, five retries, no more"
    );
    assert!(took < Duration::from_millis(700), "{took:?}");
    assert!(r.bit("fault") && !r.bit("modbus-ok") && !r.bit("at-speed"));
    assert_eq!(r.get("modbus-errors"), Value::U32(6));
    assert_eq!(r.get("last-error"), Value::S32(-0x0C));
    lock(&r.sim).faults.dead = false;
    r.cycle();
    assert!(!r.bit("fault") && r.bit("modbus-ok") && r.bit("at-speed"));
}

#[test]
fn an_unplugged_line_raises_fault_and_comes_back() {
    let mut r = rig("gt-unplug");
    r.run(12_000.0);
    r.cycles(5);
    lock(&r.sim).set_unplugged(true);
    r.cycles(3);
    assert!(r.bit("fault") && !r.bit("modbus-ok"));
    lock(&r.sim).set_unplugged(false);
    r.cycles(6);
    assert!(!r.bit("fault") && r.bit("modbus-ok"));
}

#[test]
fn the_program_stops_the_spindle_when_it_ends() {
    let mut r = rig("gt-exit");
    r.run(12_000.0);
    r.cycles(2);
    r.vfd.shutdown();
    assert_eq!(lock(&r.sim).model().command(), RunCommand::Stop);
}

#[test]
fn command_line_matches_linuxcnc() {
    let o = parse_options(&args(CLI)).unwrap().unwrap();
    assert_eq!(o.serial.device, "/dev/ttyS0");
    assert_eq!(o.serial.settings, LineSettings::new(38_400, Parity::None));
    assert_eq!((o.serial.slave, o.name.as_str()), (1, "hy_gt_vfd"));
    assert_eq!(o.serial.master.retries, 5);
    assert_eq!(
        (o.motor_max_speed, o.max_freq, o.min_freq),
        (24_000.0, 400.0, 120.0)
    );
    let o = parse_options(&args(&[
        "--motor-max-speed=18000",
        "--max-frequency",
        "300",
        "--min-frequency",
        "50",
        "-d",
        "/dev/ttyUSB1",
        "-r",
        "96",
        "-p",
        "even",
        "-t",
        "7",
        "-v",
        "-n",
        "spindle",
        "--response-timeout",
        "40",
        "--retries",
        "1",
    ]))
    .unwrap()
    .unwrap();
    assert_eq!(o.serial.settings.baud, 9600);
    assert_eq!(o.serial.settings.parity, Parity::Even);
    assert_eq!((o.serial.slave, o.name.as_str()), (7, "spindle"));
    assert!(o.serial.master.debug);
    assert_eq!(o.serial.master.response_timeout, Duration::from_millis(40));
    assert_eq!(o.serial.master.retries, 1);
    let err = |a: &[&str]| parse_options(&args(a)).unwrap_err().to_string();
    assert_eq!(
        err(&["-F", "400", "-f", "120"]),
        "must specify --motor-max-speed"
    );
    assert_eq!(
        err(&["-S", "1", "-f", "120"]),
        "must specify --max-frequency"
    );
    assert_eq!(
        err(&["-S", "1", "-F", "400"]),
        "must specify --min-frequency"
    );
    assert_eq!(
        err(&["-S", "1", "-F", "100", "-f", "200"]),
        "min frequency (200) must be less than max frequency (100)"
    );
    assert_eq!(err(&["-S", "0"]), "invalid -S: 0 (must not be zero)");
    assert_eq!(
        err(&["-r", "57600"]),
        "invalid -r: 57600 (one of 1200, 2400, 4800, 9600, 19200, 38400)"
    );
    assert_eq!(
        err(&["-t", "248"]),
        "invalid -t: 248 (must be between 1 and 247)"
    );
    assert_eq!(parse_options(&args(&["--help"])).unwrap(), None);
}
