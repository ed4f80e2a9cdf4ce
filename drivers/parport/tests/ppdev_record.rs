//! The ppdev backend issues the expected ioctl sequence: a recording fake
//! stands in for /dev/parportN.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;

use hal_parport::cfg::{Backend, Mode, PortAddr, PortSpec};
use hal_parport::clock::SimClock;
use hal_parport::driver::{Outputs, PortDriver};
use hal_parport::port::ppdev::{Ioctl, PpdevPort, RecordingIoctl, MODE_PCSPP, MODE_TRISTATE};
use hal_parport::port::PortIo;
use hal_parport::select::{check_ppdev_mode, choose, SysPaths};

fn driver(mode: Mode, modes: u32) -> (PortDriver, Arc<RecordingIoctl>) {
    let rec = Arc::new(RecordingIoctl::new(modes));
    let port = PpdevPort::with_ioctl(rec.clone(), "/dev/parport0", Some(0x378));
    port.claim().unwrap();
    check_ppdev_mode(&port, mode).unwrap();
    let drv = PortDriver::new(mode, Arc::new(port), Arc::new(SimClock::new(0, 10)));
    drv.init().unwrap();
    (drv, rec)
}

#[test]
fn out_mode_sequence() {
    use Ioctl::*;
    let (drv, rec) = driver(Mode::Out, MODE_PCSPP);
    let o = Outputs::default();
    drv.write(&o);
    drv.write(&o);
    rec.set_status(0x78 ^ 0x08);
    let i = drv.read();
    assert_eq!(i.status & 0xF8, 0xF0, "pin 15 low, busy corrected");
    let step = Outputs {
        data: 0x05,
        data_reset_mask: 0x01,
        control: 0x02,
        control_reset_mask: 0x02,
        control_reset_val: 0x02,
        ..o
    };
    drv.write(&step);
    drv.reset(1_000, 1_000_000);
    drv.reset(1_000, 1_000_000);
    drop(drv);
    assert_eq!(
        rec.calls(),
        vec![
            Claim,
            GetModes,
            // First write: both registers, whatever their value.
            WriteData(0x00),
            WriteControl(0x0B),
            // Second write: nothing changed, no ioctl.
            ReadStatus,
            WriteData(0x05),
            WriteControl(0x02 ^ 0x0B),
            // Reset: data bit 0 back to 0; control pin 14 was
            // reset to its invert (already its level): nothing.
            WriteData(0x04),
            Release,
        ]
    );
}

#[test]
fn in_mode_sequence_uses_ppdatadir() {
    use Ioctl::*;
    let (drv, rec) = driver(Mode::In, MODE_PCSPP | MODE_TRISTATE);
    let i = drv.read();
    assert_eq!(i.data, Some(0));
    drv.write(&Outputs {
        data: 0xFF,
        control: 0x05,
        ..Outputs::default()
    });
    assert_eq!(drv.io().read_control() & 0x20, 0x20, "direction bit kept");
    drop(drv);
    assert_eq!(
        rec.calls(),
        vec![
            Claim,
            GetModes,
            // init: read control (raw 0), write it back with bit 5:
            // PPDATADIR, then the unchanged lines.
            ReadControl,
            DataDir(true),
            WriteControl(0x00),
            ReadStatus,
            ReadData,
            // write: no data in `in` mode; control keeps bit 5 (no
            // PPDATADIR again), low nibble 0x05 ^ 0x0B.
            WriteControl(0x0E),
            ReadControl,
            Release,
        ]
    );
}

#[test]
fn modes_that_ppdev_cannot_serve_are_refused() {
    // x and epp: refused when the backend is chosen, before any open.
    let nowhere = SysPaths {
        dev: "/nonexistent-dev".into(),
        proc_parport: "/nonexistent-proc".into(),
    };
    let on_ppdev = |mode| PortSpec {
        addr: PortAddr::Number(3),
        mode,
        backend: Some(Backend::Ppdev),
    };
    let e = choose(&on_ppdev(Mode::X), &nowhere)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("PPRCONTROL returns the kernel's cached copy"),
        "{e}"
    );
    let e = choose(&on_ppdev(Mode::Epp), &nowhere)
        .unwrap_err()
        .to_string();
    assert!(e.contains("ECR"), "{e}");
    // in: refused after the claim, which reports the port's modes.
    let rec = Arc::new(RecordingIoctl::new(MODE_PCSPP));
    let port = PpdevPort::with_ioctl(rec.clone(), "/dev/parport3", None);
    port.claim().unwrap();
    let e = check_ppdev_mode(&port, Mode::In).unwrap_err().to_string();
    assert!(
        e.contains("/dev/parport3 reports no PARPORT_MODE_TRISTATE"),
        "{e}"
    );
    assert!(check_ppdev_mode(&port, Mode::Out).is_ok());
    drop(port);
    assert_eq!(
        rec.calls(),
        vec![Ioctl::Claim, Ioctl::GetModes, Ioctl::Release]
    );
}
