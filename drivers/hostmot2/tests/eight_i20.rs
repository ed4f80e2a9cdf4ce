//! The 8I20 drive on Smart Serial, as the Smithy machines have it: a
//! 5i20 with Smithy's `sssvst2_2_4_v31` firmware and an 8I20 on port 0
//! channel 0. The card names no tables; the driver knows its process
//! data and globals by name, as LinuxCNC does, and scales its current
//! to the card's own maximum current.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::{Named, Rig};
use hal_core::Value::{Bit, Float, U32};
use hal_core::{Host, HostConfig};
use hostmot2::hal::{HM2_PCI_MODULE, HOSTMOT2_MODULE};
use hostmot2::sim::plx_boards;
use hostmot2::sim::sserial::SimRemote;
use hostmot2::sim::Bench;

const CARD: &str = "8i20.0.0";

fn rig(tag: &str) -> Rig {
    let (board, _) = plx_boards::card("5i20").unwrap();
    let spec = plx_boards::firmware(&board.into(), "sssvst2_2_4_v31").unwrap();
    let bench = Box::new(Bench {
        pins: vec![None; 72],
        ..Bench::default()
    });
    Rig::new(
        tag,
        spec,
        bench,
        "num_encoders=1 num_pwmgens=0 num_stepgens=4 sserial_port_0=0xxxxxxx",
    )
}

fn drive<R>(r: &Rig, f: impl FnOnce(&mut SimRemote) -> R) -> R {
    r.sim
        .with(|m| f(m.sserial().remote(0, 0).expect("the 8I20")))
}

#[test]
fn the_8i20_has_linuxcncs_pins_and_parameters() {
    let r = rig("8i20-names");
    let inst = r.host.instance();
    for pin in [
        "angle",
        "current",
        "card-temp",
        "bus-voltage",
        "status.current-lim",
        "status.brake-on",
        "status.pid-on",
        "status.no-enable",
        "fault.watchdog",
        "fault.overtemp",
        "fault.U-current",
        "fault.W-current",
        "fault.bus-overv",
        "fault.framingr",
    ] {
        let name = r.full(&format!("{CARD}.{pin}"));
        assert!(inst.pin(&name).unwrap().is_some(), "{name}");
    }
    assert!(inst.pin(&r.full(&format!("{CARD}.pad"))).unwrap().is_none());
    for (param, v) in [
        ("swrevision", U32(42)),
        ("unitnumber", U32(0x0820)),
        ("nvmaxcurrent", U32(2000)),
        ("nvbusoverv", U32(39000)),
        ("nvbrakeonv", U32(37000)),
        ("current-scalemax", Float(20.0)),
        ("current-maxlim", Float(20.0)),
        ("current-minlim", Float(-20.0)),
    ] {
        assert_eq!(r.param(&format!("{CARD}.{param}")), v, "{param}");
    }
    // The port's objects and the GPIO the machines use.
    for pin in [
        "sserial.port-0.run",
        "sserial.port-0.port_state",
        "sserial.port-0.fault-count",
        "gpio.039.in_not",
        "gpio.045.out",
        "encoder.00.velocity",
        "stepgen.03.position-cmd",
    ] {
        assert!(inst.pin(&r.full(pin)).unwrap().is_some(), "{pin}");
    }
}

#[test]
fn current_in_voltage_temperature_and_status_out() {
    let mut r = rig("8i20-run");
    r.set_pin(&format!("{CARD}.angle"), Float(0.25));
    r.set_pin(&format!("{CARD}.current"), Float(5.0));
    r.cycles(20);
    let (angle, amps) = drive(&r, |c| {
        let d = c.drive.as_ref().unwrap();
        (d.angle, d.current)
    });
    assert!((angle - 0.25).abs() < 1e-3, "{angle}");
    assert!((amps - 5.0).abs() < 1e-3, "{amps}");
    let volts = r.float(&format!("{CARD}.bus-voltage"));
    assert!((volts - 159.75).abs() < 0.02, "{volts}");
    assert!(r.bit(&format!("{CARD}.status.pid-on")));
    assert!(!r.bit(&format!("{CARD}.status.current-lim")));
    let temp = r.float(&format!("{CARD}.card-temp"));
    assert!((25.0..=28.0).contains(&temp), "{temp}");

    // Past its maximum current the drive limits and says so.
    r.set_pin(&format!("{CARD}.current"), Float(-30.0));
    r.cycles(3);
    assert!(r.bit(&format!("{CARD}.status.current-lim")));
    let amps = drive(&r, |c| c.drive.as_ref().unwrap().current);
    assert!((amps + 20.0).abs() < 1e-3, "{amps}");

    // A hot card latches its fault and drops the output.
    drive(&r, |c| c.drive.as_mut().unwrap().temperature = 120.0);
    r.cycles(3);
    assert!(r.bit(&format!("{CARD}.fault.overtemp")));
    assert!(!r.bit(&format!("{CARD}.status.pid-on")));
    assert_eq!(drive(&r, |c| c.drive.as_ref().unwrap().current), 0.0);

    // The hardware enable input off.
    drive(&r, |c| {
        let d = c.drive.as_mut().unwrap();
        d.temperature = 30.0;
        d.enable_input = false;
    });
    r.set_pin("sserial.port-0.run", Bit(false));
    r.cycles(50);
    r.set_pin("sserial.port-0.run", Bit(true));
    r.cycles(20);
    assert!(
        !r.bit(&format!("{CARD}.fault.overtemp")),
        "cleared by the restart"
    );
    assert!(r.bit(&format!("{CARD}.status.no-enable")));
    assert!(!r.bit(&format!("{CARD}.status.pid-on")));
}

#[test]
fn a_smithy_load_line_runs_on_the_simulated_5i20() {
    let h = Host::create(HostConfig::for_tests("8i20-loadrt")).unwrap();
    h.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    h.loadrt(
        &HM2_PCI_MODULE,
        &[
            "config=firmware=hm2/5i20/sssvst2_2_4_v31.bit num_encoders=1 num_pwmgens=0 num_stepgens=4 sserial_port_0=0xxxxxxx enable_raw",
            "sim=5i20",
        ],
    )
    .unwrap();
    let inst = h.instance();
    for pin in [
        "hm2_5i20.0.8i20.0.0.angle",
        "hm2_5i20.0.8i20.0.0.bus-voltage",
        "hm2_5i20.0.raw.write_address",
    ] {
        assert!(inst.pin(pin).unwrap().is_some(), "{pin}");
    }
}
