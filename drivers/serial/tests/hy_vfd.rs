//! `hy_vfd` against the simulated HY drive, on simulated time: every pin,
//! the set-up, the frames of a cycle byte for byte, run, reverse, stop,
//! at-speed, a dead drive and an unplugged line.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::time::Duration;

use common::*;
use hal_core::{PinDir, Value};
use hal_serial::line::{LineSettings, Parity, SimLine};
use hal_serial::sim::Protocol;
use hal_serial::vfd::hy::{parse_options, HyOptions, HyVfd};
use hal_serial::vfd::{Cycle, Parsed};

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

type HyRig = Rig<HyVfd<SimLine>>;

fn rig_with(tag: &str, cli: &[&str]) -> HyRig {
    let opts: HyOptions = parse_options(&args(cli)).unwrap().into_run().unwrap();
    let sim = drive(Protocol::Hy, opts.serial.settings);
    let name = opts.name.clone();
    Rig::new(tag, &name, sim, |comp, line| {
        HyVfd::new(comp, opts, line).unwrap()
    })
}

fn rig(tag: &str) -> HyRig {
    rig_with(tag, &[])
}

impl HyRig {
    fn run_forward(&self, rpm: f64) {
        self.set("enable", Value::Bit(true));
        self.set("spindle-on", Value::Bit(true));
        self.set("spindle-forward", Value::Bit(true));
        self.set("speed-command", Value::Float(rpm));
    }
}

#[test]
fn every_pin_has_linuxcnc_name_type_and_direction() {
    let r = rig("hy-pins");
    let mut want: Vec<(String, String, PinDir)> = Vec::new();
    let mut add = |n: &str, t: &str, d: PinDir| want.push((n.into(), t.into(), d));
    for n in ["enable", "spindle-forward", "spindle-reverse", "spindle-on"] {
        add(n, "bit", PinDir::In);
    }
    add("speed-command", "float", PinDir::In);
    add("spindle-at-speed-tolerance", "float", PinDir::In);
    for n in [
        "SetF",
        "OutF",
        "OutA",
        "Rott",
        "DCV",
        "ACV",
        "Cont",
        "Tmp",
        "CNTR",
        "CNST",
        "frequency-command",
        "spindle-speed-fb",
        "spindle-speed-fb-rps",
        "max-freq",
        "base-freq",
        "freq-lower-limit",
        "rated-motor-voltage",
        "rated-motor-current",
        "rated-motor-rev",
    ] {
        add(n, "float", PinDir::Out);
    }
    for n in [
        "CNST-run",
        "CNST-jog",
        "CNST-command-rf",
        "CNST-running",
        "CNST-jogging",
        "CNST-running-rf",
        "CNST-bracking",
        "CNST-track-start",
        "spindle-at-speed",
        "hycomm-ok",
    ] {
        add(n, "bit", PinDir::Out);
    }
    add("motor-poles", "u32", PinDir::Out);
    add("error-count", "s32", PinDir::Io);
    add("retval", "u32", PinDir::Io);
    // This suite's additions.
    add("modbus-ok", "bit", PinDir::Out);
    add("fault", "bit", PinDir::Out);
    add("last-error", "s32", PinDir::Out);
    want.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(pins_of(&r.inst, "hy_vfd"), want);
    assert_eq!(r.float("spindle-at-speed-tolerance"), 0.02);
    let params: Vec<_> = r
        .inst
        .params()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == "hy_vfd")
        .collect();
    assert!(params.is_empty(), "hy_vfd has no parameters: {params:?}");
}

#[test]
fn nothing_goes_over_the_line_until_enabled() {
    let mut r = rig("hy-enable");
    r.set("spindle-on", Value::Bit(true));
    r.cycles(5);
    assert!(take_requests(&r.sim).is_empty());
    assert!(!r.bit("modbus-ok") && !r.bit("fault"));
}

#[test]
fn setup_reads_the_drive_and_writes_what_the_command_line_gives() {
    let mut r = rig_with(
        "hy-setup",
        &["-F", "300", "-S", "18000", "-P", "4", "-x", "PD014=30"],
    );
    r.set("enable", Value::Bit(true));
    assert_eq!(
        r.float("max-freq"),
        300.0,
        "the command line's value before set-up"
    );
    r.cycle();
    let req = take_requests(&r.sim);
    assert_eq!(
        req[..12],
        [
            frame(&[1, 0x02, 3, 5, 0x75, 0x30]), // PD005 = 300.00 Hz
            frame(&[1, 0x01, 3, 5, 0, 0]),
            frame(&[1, 0x01, 3, 4, 0, 0]),  // PD004
            frame(&[1, 0x01, 3, 11, 0, 0]), // PD011
            frame(&[1, 0x01, 3, 141, 0, 0]),
            frame(&[1, 0x01, 3, 142, 0, 0]),
            frame(&[1, 0x02, 3, 143, 0, 4]), // PD143 = 4 poles
            frame(&[1, 0x01, 3, 143, 0, 0]),
            frame(&[1, 0x02, 3, 144, 0x0B, 0xB8]), // 18000 rpm at 300 Hz = 3000 at 50 Hz
            frame(&[1, 0x01, 3, 144, 0, 0]),
            frame(&[1, 0x02, 3, 14, 0, 30]), // -x PD014=30
            frame(&[1, 0x01, 3, 14, 0, 0]),
        ]
    );
    assert_eq!(
        req.len(),
        12 + 8 + 2,
        "then a cycle: 8 status reads, frequency, control"
    );
    assert_eq!(r.float("max-freq"), 300.0);
    assert_eq!(r.float("base-freq"), 400.0);
    assert_eq!(r.float("freq-lower-limit"), 120.0);
    assert_eq!(r.float("rated-motor-voltage"), 220.0);
    assert_eq!(r.float("rated-motor-current"), 10.0);
    assert_eq!(r.get("motor-poles"), Value::U32(4));
    assert_eq!(r.float("rated-motor-rev"), 18_000.0);
    assert_eq!(lock(&r.sim).hy_parameters().pd[14], 30);
    assert!(r.vfd.setup_done());
}

#[test]
fn a_cycle_reads_status_then_writes_frequency_and_control() {
    let mut r = rig("hy-cycle");
    r.run_forward(12_000.0);
    r.cycle();
    take_requests(&r.sim);
    r.cycle();
    let mut want: Vec<Vec<u8>> = (0..8).map(|i| frame(&[1, 0x04, 1, i])).collect();
    // Frequency unchanged: only the control word.
    want.push(frame(&[1, 0x03, 1, 0x01]));
    assert_eq!(take_requests(&r.sim), want);
    r.set("speed-command", Value::Float(9_000.0));
    r.cycle();
    let req = take_requests(&r.sim);
    // 9000 rpm of 24000 at 400 Hz: 150.00 Hz (15000 = 0x3A98).
    assert_eq!(req[8], frame(&[1, 0x05, 2, 0x3A, 0x98]));
    assert_eq!(req[9], frame(&[1, 0x03, 1, 0x01]));
    assert_eq!(r.float("frequency-command"), 15_000.0);
    r.set("speed-command", Value::Float(6_000.0));
    r.cycle();
    assert_eq!(
        r.float("frequency-command"),
        12_000.0,
        "100 Hz clamped to PD011 = 120 Hz"
    );
    r.set("speed-command", Value::Float(30_000.0));
    r.cycle();
    assert_eq!(
        r.float("frequency-command"),
        40_000.0,
        "clamped to PD005 = 400 Hz"
    );
}

#[test]
fn runs_forward_to_speed_and_says_so() {
    let mut r = rig("hy-forward");
    r.run_forward(12_000.0);
    r.cycle();
    // The control word goes out in the cycle that sees the pins (LinuxCNC
    // sends it one cycle late).
    assert_eq!(
        lock(&r.sim).model().command(),
        hal_serial::sim::RunCommand::Forward
    );
    assert_eq!(r.float("CNTR"), 1.0);
    assert!(r.bit("CNST-run"));
    assert_eq!(
        r.float("frequency-command"),
        20_000.0,
        "200.00 Hz in 0.01 Hz"
    );
    r.cycles(8); // 0.8 s: the 400 Hz/s ramp is done
    assert!(near(r.float("SetF"), 200.0, 1e-9));
    assert!(near(r.float("OutF"), 200.0, 1e-9));
    assert!(near(r.float("spindle-speed-fb"), 12_000.0, 1e-6));
    assert!(near(r.float("spindle-speed-fb-rps"), 200.0, 1e-6));
    assert!(r.bit("spindle-at-speed"));
    assert!(near(r.float("Rott"), 12_000.0, 2.0), "{}", r.float("Rott"));
    assert_eq!(r.float("DCV"), 311.0);
    assert_eq!(r.float("ACV"), 110.0);
    assert!(r.float("OutA") > 0.0);
    assert_eq!(r.float("Tmp"), 35.0);
    assert_eq!(r.float("Cont"), 0.0);
    assert!(r.bit("CNST-running") && !r.bit("CNST-running-rf") && !r.bit("CNST-command-rf"));
    assert!(r.bit("hycomm-ok") && r.bit("modbus-ok") && !r.bit("fault"));
    assert_eq!(r.get("error-count"), Value::S32(0));
    assert_eq!(r.get("retval"), Value::U32(0));
}

#[test]
fn at_speed_follows_the_tolerance() {
    let mut r = rig("hy-tolerance");
    r.run_forward(12_000.0);
    r.cycles(9);
    assert!(r.bit("spindle-at-speed"));
    // 12 300 rpm asked, 12 000 running for a cycle: 2.4 % off.
    r.set("speed-command", Value::Float(12_300.0));
    r.vfd.cycle();
    assert!(!r.bit("spindle-at-speed"));
    r.set("spindle-at-speed-tolerance", Value::Float(0.05));
    r.vfd.cycle();
    assert!(r.bit("spindle-at-speed"));
    r.set("spindle-on", Value::Bit(false));
    r.vfd.cycle();
    assert!(!r.bit("spindle-at-speed"));
    assert_eq!(
        r.float("spindle-speed-fb"),
        0.0,
        "no feedback without a command, as LinuxCNC"
    );
}

#[test]
fn reverse_stop_and_both_directions() {
    let mut r = rig("hy-reverse");
    r.run_forward(6_000.0);
    r.set("spindle-forward", Value::Bit(false));
    r.set("spindle-reverse", Value::Bit(true));
    r.cycles(6);
    assert_eq!(r.float("CNTR"), 17.0, "0x11 run reverse");
    assert!(r.bit("CNST-command-rf") && r.bit("CNST-running-rf"));
    assert!(lock(&r.sim).model().rpm() < -5_000.0);
    r.set("spindle-forward", Value::Bit(true));
    r.cycle();
    assert_eq!(r.float("CNTR"), 8.0, "both directions: stop");
    r.set("spindle-forward", Value::Bit(false));
    r.set("spindle-on", Value::Bit(false));
    r.cycle();
    assert_eq!(r.float("CNTR"), 8.0);
    assert!(!r.bit("CNST-run"));
    assert!(r.bit("CNST-bracking"), "ramping down");
    r.cycles(20);
    assert!(!r.bit("CNST-running") && !r.bit("CNST-bracking"));
}

#[test]
fn enable_falling_stops_the_spindle() {
    let mut r = rig("hy-disable");
    r.run_forward(12_000.0);
    r.cycles(3);
    take_requests(&r.sim);
    r.set("enable", Value::Bit(false));
    r.cycles(3);
    assert_eq!(
        take_requests(&r.sim),
        [frame(&[1, 0x03, 1, 0x08])],
        "one stop, then silence"
    );
    assert_eq!(
        lock(&r.sim).model().command(),
        hal_serial::sim::RunCommand::Stop
    );
}

#[test]
fn the_program_stops_the_spindle_when_it_ends() {
    let mut r = rig("hy-exit");
    r.run_forward(12_000.0);
    r.cycles(2);
    r.vfd.shutdown();
    assert_eq!(
        lock(&r.sim).model().command(),
        hal_serial::sim::RunCommand::Stop
    );
}

#[test]
fn hycomm_ok_after_more_than_ten_good_reads_and_writes() {
    let mut r = rig("hy-hycomm");
    r.run_forward(12_000.0);
    for _ in 0..5 {
        r.cycle();
        assert!(!r.bit("hycomm-ok"));
        assert!(
            r.bit("modbus-ok"),
            "modbus-ok says the last cycle was answered"
        );
    }
    r.cycle();
    assert!(r.bit("hycomm-ok"), "12 good phases");
}

#[test]
fn a_dead_drive_raises_fault_and_recovers() {
    let mut r = rig("hy-dead");
    r.run_forward(12_000.0);
    r.cycles(10);
    assert!(r.bit("spindle-at-speed") && r.bit("hycomm-ok"));
    lock(&r.sim).faults.dead = true;
    let t0 = r.now();
    r.vfd.cycle();
    let took = r.now() - t0;
    // One status read, three attempts of 100 ms, and the cycle ends.
    assert!(took < Duration::from_millis(350), "{took:?}");
    assert!(!r.bit("modbus-ok") && r.bit("fault") && !r.bit("hycomm-ok"));
    assert!(!r.bit("spindle-at-speed"));
    assert_eq!(r.get("error-count"), Value::S32(1));
    assert_eq!(r.get("retval"), Value::U32((-0x0Ci32) as u32));
    assert_eq!(r.get("last-error"), Value::S32(-0x0C));
    r.cycles(3);
    assert_eq!(r.get("error-count"), Value::S32(4));
    lock(&r.sim).faults.dead = false;
    take_requests(&r.sim);
    r.cycle();
    assert!(r.bit("modbus-ok") && !r.bit("fault"));
    assert_eq!(r.get("retval"), Value::U32(0));
    assert_eq!(r.get("last-error"), Value::S32(0));
    let req = take_requests(&r.sim);
    assert_eq!(
        req[8],
        frame(&[1, 0x05, 2, 0x4E, 0x20]),
        "frequency sent again"
    );
    r.cycles(6);
    assert!(r.bit("hycomm-ok"));
}

#[test]
fn setup_is_retried_until_the_drive_answers() {
    let mut r = rig("hy-setup-retry");
    lock(&r.sim).faults.dead = true;
    r.set("enable", Value::Bit(true));
    r.cycles(2);
    assert!(!r.vfd.setup_done() && r.bit("fault"));
    lock(&r.sim).faults.dead = false;
    r.cycle();
    assert!(r.vfd.setup_done() && !r.bit("fault"));
    assert_eq!(r.float("max-freq"), 400.0);
}

#[test]
fn an_unplugged_line_raises_fault_and_comes_back() {
    let mut r = rig("hy-unplug");
    r.run_forward(12_000.0);
    r.cycles(3);
    lock(&r.sim).set_unplugged(true);
    r.cycle();
    assert!(r.bit("fault") && !r.bit("modbus-ok"));
    assert_eq!(r.get("last-error"), Value::S32(-0x0B), "the write failed");
    r.cycles(10);
    assert!(r.bit("fault"));
    lock(&r.sim).set_unplugged(false);
    r.cycles(6); // the reopen is tried every 500 ms
    assert!(!r.bit("fault") && r.bit("modbus-ok"));
    assert!(r.vfd.master_mut().stats().reopens >= 1);
    assert!(r.bit("spindle-at-speed"));
}

#[test]
fn a_refusal_is_reported_but_the_drive_counts_as_heard() {
    let mut r = rig("hy-refusal");
    r.run_forward(12_000.0);
    r.cycles(2);
    lock(&r.sim).faults.exception = Some((0x04, 1));
    r.cycle();
    assert!(r.bit("modbus-ok") && !r.bit("fault"));
    assert_eq!(r.get("retval"), Value::U32((-4i32) as u32));
    assert_eq!(r.get("error-count"), Value::S32(1));
}

#[test]
fn command_line_matches_linuxcnc() {
    let o = parse_options(&[]).unwrap().into_run().unwrap();
    assert_eq!(o.serial.device, "/dev/ttyS0");
    assert_eq!(o.serial.settings, LineSettings::new(19_200, Parity::Even));
    assert_eq!((o.serial.slave, o.name.as_str()), (1, "hy_vfd"));
    let o = parse_options(&args(&[
        "-d",
        "/dev/ttyUSB0",
        "-n",
        "spindle-vfd",
        "-r",
        "5",
        "-p",
        "n",
        "-b",
        "7",
        "-s",
        "2",
        "-t",
        "3",
        "-g",
        "-y",
        "--register",
        "PD001=2",
        "--period=0.05",
    ]))
    .unwrap()
    .into_run()
    .unwrap();
    assert_eq!(o.serial.device, "/dev/ttyUSB0");
    assert_eq!(o.name, "spindle-vfd");
    assert_eq!(o.serial.settings.baud, 57_600);
    assert_eq!(o.serial.settings.parity, Parity::None);
    assert_eq!(
        (o.serial.settings.data_bits, o.serial.settings.stop_bits),
        (7, 2)
    );
    assert_eq!(o.serial.slave, 3);
    assert!(o.serial.master.debug && o.regdump);
    assert_eq!(o.registers, [(1, 2)]);
    assert_eq!(o.period, Duration::from_millis(50));
    assert_eq!(parse_options(&args(&["-h"])).unwrap(), Parsed::Help);
    assert_eq!(
        parse_options(&args(&["--version"])).unwrap(),
        Parsed::Version
    );
    let err = |a: &[&str]| parse_options(&args(a)).unwrap_err().to_string();
    assert_eq!(
        err(&["-r", "1"]),
        "invalid -r: 1 (one of 110, 300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200)"
    );
    assert_eq!(
        err(&["-t", "0"]),
        "invalid -t: 0 (must be between 1 and 254)"
    );
    assert_eq!(
        err(&["-x", "PD1"]),
        "invalid -x: PD1 (expected PDnnn=value, nnn 0..255, value 0..65535)"
    );
    assert_eq!(
        err(&["-F", "-3"]),
        "invalid -F: -3 (must be between 0 and 655.35)"
    );
    assert_eq!(
        err(&["-F", "100", "-f", "200"]),
        "min frequency (200) must be less than max frequency (100)"
    );
    assert!(err(&["-n", "bad name"]).starts_with("invalid -n: bad name"));
    let many: Vec<String> = (0..11)
        .flat_map(|i| ["-x".to_string(), format!("PD{i}=1")])
        .collect();
    assert_eq!(
        parse_options(&many).unwrap_err().to_string(),
        "invalid -x: PD10=1 (too many direct register writes, max is 10)"
    );
}
