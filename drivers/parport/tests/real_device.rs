//! Against a real parallel port: `/dev/parport0` (or `$VMRIG_PARPORT`).
//! The tests are ignored, with the reason, unless run on purpose
//! (`--include-ignored`, as `scripts/test-all` does in the VM rig); then
//! a missing device fails them. The VM rig provides one (QEMU's
//! isa-parallel at 0x378, running as root):
//!
//! ```text
//! vmrig run -- target/debug/deps/real_device-<hash> --include-ignored --test-threads=1 --nocapture
//! ```
//!
//! QEMU's port reads back the data and control latches and returns a
//! fixed status, so these tests check register round trips, not inputs.

mod common;

use std::sync::Arc;

use common::*;
use hal_core::Value;
use hal_parport::cfg::Mode;
use hal_parport::clock::MonotonicClock;
use hal_parport::driver::{Outputs, PortDriver};
use hal_parport::port::ppdev::PpdevPort;
use hal_parport::port::raw::RawPort;
use hal_parport::port::PortIo;
use hal_parport::select::{linux_ports, SysPaths};

/// The port's device; the test fails, saying why, when it is absent.
fn device() -> String {
    let path = std::env::var("VMRIG_PARPORT").unwrap_or_else(|_| "/dev/parport0".into());
    assert!(
        std::path::Path::new(&path).exists(),
        "{path} is not present (no parport_pc/ppdev here); \
         run this binary through the VM rig to test a real port"
    );
    path
}

#[test]
#[ignore = "needs a real parallel port: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn ppdev_register_round_trip() {
    let path = device();
    let p = PpdevPort::open(&path, None).expect("open");
    p.claim().expect("PPCLAIM");
    eprintln!("{}: modes {:#x}", p.describe(), p.modes());
    for v in [0x00u8, 0xFF, 0xA5, 0x5A, 0x01, 0x80] {
        p.write_data(v);
        assert_eq!(p.read_data(), v, "data latch reads back");
    }
    for v in [0x00u8, 0x05, 0x0A, 0x0F] {
        p.write_control(v);
        assert_eq!(p.read_control() & 0x0F, v, "control reads back");
    }
    eprintln!("status register: {:#04x}", p.read_status());
    assert_eq!(p.errors(), 0);

    // The driver algorithm over ppdev.
    let drv = PortDriver::new(Mode::Out, Arc::new(p), Arc::new(MonotonicClock));
    drv.write(&Outputs {
        data: 0x3C,
        control: 0x05,
        ..Outputs::default()
    });
    assert_eq!(drv.io().read_data(), 0x3C);
    assert_eq!(drv.io().read_control() & 0x0F, 0x05 ^ 0x0B);
    let i = drv.read();
    eprintln!("status after 0x80 correction: {:#04x}", i.status);
    assert_eq!(drv.io().errors(), 0);
}

#[test]
#[ignore = "needs a real parallel port: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn hal_parport_loads_on_the_real_port_and_safe_state_sticks() {
    let path = device();
    let host = host("real");
    loadrt(&host, "0").unwrap_or_else(|e| panic!("loadrt cfg=0 on {path}: {e}"));
    setp(&host, "parport.0.pin-02-out-invert", Value::Bit(true));
    setp(&host, "parport.0.pin-09-out-invert", Value::Bit(true));
    set(&host, "parport.0.pin-05-out", true);
    run(&host, 1_000_000, &["parport.0.read", "parport.0.write"]);
    std::thread::sleep(std::time::Duration::from_millis(50));
    host.stop();
    host.unloadrt("hal_parport").unwrap();
    // After unload, the outputs rest at their inactive (inverted) levels.
    let p = PpdevPort::open(&path, None).unwrap();
    p.claim().unwrap();
    assert_eq!(p.read_data(), 0x81);
}

#[test]
#[ignore = "needs a real parallel port: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn in_mode_on_ppdev_sets_the_direction() {
    device();
    let host = host("realin");
    match loadrt(&host, "0 in") {
        Ok(()) => {
            run(&host, 1_000_000, &["parport.0.read"]);
            std::thread::sleep(std::time::Duration::from_millis(20));
            host.stop();
            eprintln!(
                "pin-02-in = {:?}",
                host.instance().pin_value("parport.0.pin-02-in").unwrap()
            );
        }
        // A port without PARPORT_MODE_TRISTATE is refused with a reason.
        Err(e) => assert!(e.to_string().contains("TRISTATE"), "{e}"),
    }
}

#[test]
#[ignore = "needs a real parallel port: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn raw_port_io_when_permitted() {
    device();
    let Some(lp) = linux_ports(&SysPaths::system()).into_iter().next() else {
        eprintln!("SKIPPED: /proc/sys/dev/parport lists no port");
        return;
    };
    let raw = match RawPort::open(lp.base, lp.base_hi, None) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("SKIPPED raw I/O: {e}");
            return;
        }
    };
    for v in [0x12u8, 0xED] {
        raw.write_data(v);
        assert_eq!(raw.read_data(), v);
    }
    // From another thread: the permission is taken there on first use.
    let r = Arc::new(raw);
    let r2 = r.clone();
    std::thread::spawn(move || {
        r2.write_data(0x42);
        assert_eq!(r2.read_data(), 0x42);
    })
    .join()
    .unwrap();
    assert_eq!(r.errors(), 0);
    // x mode needs raw I/O; with permission it loads (claimed via ppdev).
    let host = host("realx");
    loadrt(&host, "0 x").unwrap();
    run(&host, 1_000_000, &["parport.0.read", "parport.0.write"]);
    std::thread::sleep(std::time::Duration::from_millis(20));
    host.stop();
    // QEMU's control lines are push-pull and read back the released 0x0F.
    assert!(bit(&host, "parport.0.pin-01-in"));
}
