//! The tty backend on a real pseudo-terminal, with the simulated drive at
//! the far end: transactions through the kernel's tty layer, and the
//! device disappearing and coming back under the same name.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;
use std::time::{Duration, Instant};

use hal_serial::line::{LineSettings, Parity, SerialLine, TtyLine};
use hal_serial::modbus::{Master, MasterConfig};
use hal_serial::regs::gt;
use hal_serial::sim::{Protocol, PtyVfd, VfdSim};
use hal_serial::SerialError;

fn private_dir(tag: &str) -> PathBuf {
    use std::os::unix::fs::DirBuilderExt;
    let p = std::env::temp_dir().join(format!("hal-serial-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    std::fs::DirBuilder::new().mode(0o700).create(&p).unwrap();
    p
}

fn config() -> MasterConfig {
    MasterConfig {
        response_timeout: Duration::from_millis(200),
        reopen_interval: Duration::from_millis(20),
        ..Default::default()
    }
}

#[test]
fn transactions_through_a_pty() {
    let settings = LineSettings::new(38_400, Parity::None);
    let pty = PtyVfd::start(VfdSim::new(Protocol::ModbusGt, 1, settings)).unwrap();
    let line = TtyLine::open(&pty.device(), settings).unwrap();
    let mut m = Master::new(line, config());
    for i in 0..20u16 {
        m.write_register(1, gt::FREQUENCY, i * 100).unwrap();
        let v = m.read_registers(1, 0x03, gt::FREQUENCY, 1).unwrap();
        assert_eq!(v, [i * 100]);
    }
    assert_eq!(m.stats().failed, 0);
    assert_eq!(m.line().errors(), 0);
    assert_eq!(pty.with(|s| s.crc_errors()), 0);
}

#[test]
fn a_device_that_goes_away_fails_the_line_until_it_is_back() {
    let dir = private_dir("pty-line");
    let link = dir.join("ttyUSB-vfd");
    let settings = LineSettings::new(19_200, Parity::Even);
    let pty = PtyVfd::start_linked(VfdSim::new(Protocol::Hy, 1, settings), &link).unwrap();
    let line = TtyLine::open(&link.to_string_lossy(), settings).unwrap();
    let mut m = Master::new(line, config());
    assert_eq!(m.hy_read_parameter(1, 5).unwrap(), 40_000);

    pty.unplug();
    let e = m.hy_read_parameter(1, 5).unwrap_err();
    assert!(e.is_line_failure(), "the closed pty fails the line: {e}");
    assert!(!m.line().is_open());
    // While it is gone, reopening fails and says so.
    std::thread::sleep(Duration::from_millis(30));
    match m.hy_read_parameter(1, 5) {
        Err(SerialError::LineDown { reason, .. }) => {
            assert!(reason.contains("no such device"), "{reason}")
        }
        other => panic!("{other:?}"),
    }

    pty.replug().unwrap();
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        match m.hy_read_parameter(1, 5) {
            Ok(v) => {
                assert_eq!(v, 40_000);
                break;
            }
            Err(e) => assert!(Instant::now() < end, "never came back: {e}"),
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(m.stats().reopens >= 1);
    drop(pty);
    let _ = std::fs::remove_dir_all(&dir);
}
