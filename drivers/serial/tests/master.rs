//! The Modbus RTU master against the simulated drive on simulated time:
//! frames byte for byte (CRC, function codes, exception replies), the
//! silence between frames, timeouts, retries, and a line that goes away
//! and comes back.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::{Arc, Mutex};
use std::time::Duration;

use hal_serial::line::{LineSettings, Parity, SerialLine, SimLine};
use hal_serial::modbus::{Master, MasterConfig, ReplyLength};
use hal_serial::regs::gt;
use hal_serial::sim::{Protocol, VfdSim};
use hal_serial::{crc, SerialError};

fn frame(body: &[u8]) -> Vec<u8> {
    let mut f = body.to_vec();
    crc::append(&mut f);
    f
}

fn setup(protocol: Protocol, config: MasterConfig) -> (Arc<Mutex<VfdSim>>, Master<SimLine>) {
    let settings = LineSettings::new(38_400, Parity::None);
    let sim = Arc::new(Mutex::new(VfdSim::new(protocol, 1, settings)));
    let master = Master::new(SimLine::new(sim.clone()), config);
    (sim, master)
}

fn requests(sim: &Mutex<VfdSim>) -> Vec<Vec<u8>> {
    sim.lock().unwrap().requests().to_vec()
}

#[test]
fn write_single_register_frames_byte_for_byte() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    m.write_register(1, gt::CONTROL, gt::RUN_FORWARD).unwrap();
    m.write_register(1, gt::FREQUENCY, 5000).unwrap();
    // Slave 1, function 6, register 0x1000 = 1; CRC 0x0ACC low byte first.
    assert_eq!(
        requests(&sim),
        [
            vec![0x01, 0x06, 0x10, 0x00, 0x00, 0x01, 0x4C, 0xCA],
            vec![0x01, 0x06, 0x20, 0x00, 0x13, 0x88, 0x8F, 0x5C],
        ]
    );
    assert_eq!(requests(&sim)[1], frame(&[1, 6, 0x20, 0, 0x13, 0x88]));
    let s = sim.lock().unwrap();
    assert_eq!(s.gt_registers().control, gt::RUN_FORWARD);
    assert_eq!(s.model().set_frequency_hz(), 200.0);
}

#[test]
fn read_registers_decodes_big_endian_values() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    m.write_register(1, gt::FREQUENCY, 10_000).unwrap();
    let v = m.read_registers(1, 0x03, gt::OUTPUT_FREQUENCY, 2).unwrap();
    assert_eq!(v, [0, 40_000], "stopped, set point 400.00 Hz");
    assert_eq!(
        requests(&sim)[1],
        [0x01, 0x03, 0x30, 0x00, 0x00, 0x02, 0xCB, 0x0B]
    );
    let v = m.read_registers(1, 0x04, gt::DC_BUS_VOLTAGE, 1).unwrap();
    assert_eq!(v, [3110]);
}

#[test]
fn exception_replies_are_reported_with_their_code_and_not_retried() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    let e = m.read_registers(1, 0x03, 0x0042, 1).unwrap_err();
    match &e {
        SerialError::Exception {
            slave: 1,
            function: 3,
            code,
        } => assert_eq!(code.0, 0x02),
        other => panic!("{other}"),
    }
    assert_eq!(
        e.to_string(),
        "slave 1: function 0x03 refused: illegal data address (exception 0x02)"
    );
    let e = m.write_register(1, gt::CONTROL, 99).unwrap_err();
    assert_eq!(e.code(), -3, "illegal data value");
    let e = m
        .transact(1, 0x2B, &[0x0E, 0x01, 0x00], ReplyLength::CountAt2)
        .unwrap_err();
    assert!(
        matches!(e, SerialError::Exception { code, .. } if code.0 == 1),
        "{e}"
    );
    assert_eq!(requests(&sim).len(), 3, "no retries of refusals");
    assert_eq!(m.stats().exceptions, 3);
    assert_eq!(m.stats().retries, 0);
}

#[test]
fn a_busy_slave_is_asked_again() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    sim.lock().unwrap().faults.exception = Some((0x06, 2));
    m.write_register(1, gt::FREQUENCY, 100).unwrap();
    assert_eq!(requests(&sim).len(), 3);
    assert_eq!(m.stats().retries, 2);
}

#[test]
fn lost_and_garbled_replies_are_retried_then_reported() {
    let config = MasterConfig {
        retries: 3,
        ..Default::default()
    };
    let (sim, mut m) = setup(Protocol::ModbusGt, config);
    // Each misbehaviour costs one retry; the same request goes out again.
    sim.lock().unwrap().faults.silent = 1;
    m.write_register(1, gt::FREQUENCY, 1234).unwrap();
    sim.lock().unwrap().faults.bad_crc = 1;
    m.write_register(1, gt::FREQUENCY, 1234).unwrap();
    sim.lock().unwrap().faults.wrong_function = 1;
    m.write_register(1, gt::FREQUENCY, 1234).unwrap();
    let st = m.stats();
    assert_eq!(
        (st.timeouts, st.crc_errors, st.retries, st.failed),
        (1, 1, 3, 0)
    );
    assert_eq!(requests(&sim).len(), 6);
    assert!(
        requests(&sim).iter().all(|r| r == &requests(&sim)[0]),
        "same request each time"
    );

    sim.lock().unwrap().faults.truncate = 1;
    m.write_register(1, gt::FREQUENCY, 1).unwrap();
    assert_eq!(m.stats().retries, 4);

    // A drive that never answers: 1 + 3 attempts, each one response
    // timeout, all in simulated time.
    sim.lock().unwrap().faults.dead = true;
    let t0 = m.line().now();
    let e = m.write_register(1, gt::FREQUENCY, 2).unwrap_err();
    assert!(
        matches!(
            e,
            SerialError::Timeout {
                slave: 1,
                function: 6,
                waited_ms: 100
            }
        ),
        "{e}"
    );
    let took = m.line().now() - t0;
    assert!(
        took >= Duration::from_millis(400) && took < Duration::from_millis(420),
        "{took:?}"
    );
    assert_eq!(m.stats().failed, 1);
}

#[test]
fn a_late_reply_within_the_timeout_is_taken() {
    let config = MasterConfig {
        retries: 0,
        ..Default::default()
    };
    let (sim, mut m) = setup(Protocol::ModbusGt, config);
    sim.lock().unwrap().faults.reply_delay = Duration::from_millis(80);
    m.write_register(1, gt::FREQUENCY, 7).unwrap();
    sim.lock().unwrap().faults.reply_delay = Duration::from_millis(120);
    let e = m.write_register(1, gt::FREQUENCY, 8).unwrap_err();
    assert!(matches!(e, SerialError::Timeout { .. }), "{e}");
}

#[test]
fn frames_are_separated_by_three_and_a_half_characters() {
    // 9600 baud 8N1: a character is 1.0417 ms; the silence 3.646 ms.
    let settings = LineSettings::new(9600, Parity::None);
    let sim = Arc::new(Mutex::new(VfdSim::new(Protocol::ModbusGt, 1, settings)));
    let mut m = Master::new(SimLine::new(sim.clone()), MasterConfig::default());
    m.write_register(1, gt::FREQUENCY, 1).unwrap();
    let t1 = m.line().now();
    m.write_register(1, gt::FREQUENCY, 2).unwrap();
    let t2 = m.line().now();
    // One transaction: silence, 8 characters out, the drive's own 3.5
    // characters of turnaround, 8 characters back.
    let c = settings.char_time();
    let expected = settings.silence(3.5) * 2 + c * 16;
    let diff = (t2 - t1).abs_diff(expected);
    assert!(
        diff < Duration::from_micros(5),
        "{:?} vs {expected:?}",
        t2 - t1
    );
}

#[test]
fn broadcasts_get_no_reply_and_are_not_waited_for() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    let t0 = m.line().now();
    m.write_register(0, gt::FREQUENCY, 2500).unwrap();
    assert!(m.line().now() - t0 < Duration::from_millis(10));
    assert_eq!(sim.lock().unwrap().gt_registers().frequency, 2500);
    assert!(matches!(
        m.read_registers(0, 3, 0x3000, 1),
        Err(SerialError::BadRequest(_))
    ));
    assert!(matches!(
        m.read_registers(1, 3, 0x3000, 126),
        Err(SerialError::BadRequest(_))
    ));
}

#[test]
fn write_multiple_registers() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    m.write_registers(1, gt::CONTROL, &[gt::STOP]).unwrap();
    assert_eq!(
        requests(&sim)[0],
        frame(&[1, 0x10, 0x10, 0x00, 0x00, 0x01, 0x02, 0x00, 0x05])
    );
}

#[test]
fn an_unplugged_line_fails_fast_and_comes_back() {
    let (sim, mut m) = setup(Protocol::ModbusGt, MasterConfig::default());
    m.write_register(1, gt::FREQUENCY, 1).unwrap();
    sim.lock().unwrap().set_unplugged(true);
    let e = m.write_register(1, gt::FREQUENCY, 2).unwrap_err();
    assert!(e.is_line_failure(), "{e}");
    assert!(m.line_is_down());
    // While down, requests fail at once without touching the line.
    let t0 = m.line().now();
    let e = m.write_register(1, gt::FREQUENCY, 3).unwrap_err();
    assert!(matches!(e, SerialError::LineDown { .. }), "{e}");
    assert_eq!(m.line().now(), t0);
    // Reopening is tried every reopen_interval; it fails while unplugged.
    m.line_mut().idle(Duration::from_millis(600));
    assert!(m.write_register(1, gt::FREQUENCY, 4).is_err());
    sim.lock().unwrap().set_unplugged(false);
    assert!(
        m.write_register(1, gt::FREQUENCY, 5).is_err(),
        "not yet time to retry"
    );
    m.line_mut().idle(Duration::from_millis(600));
    m.write_register(1, gt::FREQUENCY, 6).unwrap();
    assert!(!m.line_is_down());
    assert_eq!(m.stats().reopens, 1);
    assert_eq!(sim.lock().unwrap().gt_registers().frequency, 6);
}

#[test]
fn hy_transactions_frame_byte_for_byte() {
    let (sim, mut m) = setup(Protocol::Hy, MasterConfig::default());
    assert_eq!(m.hy_read_parameter(1, 5).unwrap(), 40_000);
    assert_eq!(m.hy_write_parameter(1, 144, 3000).unwrap(), 3000);
    assert_eq!(m.hy_write_frequency(1, 20_000).unwrap(), 20_000);
    let cnst = m.hy_write_control(1, 0x01).unwrap();
    assert_eq!(cnst & 0x01, 0x01, "run bit");
    assert_eq!(m.hy_read_status(1, 0).unwrap(), 20_000, "SetF");
    assert_eq!(
        requests(&sim),
        [
            frame(&[0x01, 0x01, 0x03, 0x05, 0x00, 0x00]),
            frame(&[0x01, 0x02, 0x03, 0x90, 0x0B, 0xB8]),
            frame(&[0x01, 0x05, 0x02, 0x4E, 0x20]),
            frame(&[0x01, 0x03, 0x01, 0x01]),
            frame(&[0x01, 0x04, 0x01, 0x00]),
        ]
    );
    assert_eq!(
        requests(&sim)[0],
        [0x01, 0x01, 0x03, 0x05, 0x00, 0x00, 0x2C, 0x4F]
    );
    let e = m.hy_read_status(1, 9).unwrap_err();
    assert!(
        matches!(e, SerialError::Exception { code, .. } if code.0 == 2),
        "{e}"
    );
}
