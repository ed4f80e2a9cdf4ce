//! Malformed and hostile frames: the fuzz target's body
//! ([`hal_canservo::fuzzing::frames`]) over more than 100 000 random frames
//! (proptest, on stable), and the hostile cases by hand: wrong lengths,
//! unknown COB-IDs, SDO toggle errors, segmented transfers that never
//! end, EMCY floods.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

use hal_canservo::bus::{CanBus, Filter, Filters, SimBus};
use hal_canservo::codes::AbortCode;
use hal_canservo::engine::faults;
use hal_canservo::frame::Frame;
use hal_canservo::rig::Rig;
use hal_canservo::sdo::{SdoClient, TRANSFER_TIMEOUT_NS};
use hal_canservo::startup::Mode;

#[test]
fn fuzz_over_a_hundred_thousand_random_frames() {
    let mut runner = TestRunner::new(Config {
        cases: 6000,
        failure_persistence: None,
        ..Config::default()
    });
    let total = std::cell::Cell::new(0usize);
    runner
        .run(&vec(any::<u8>(), 0..11 * 40), |data| {
            total.set(total.get() + hal_canservo::fuzzing::frames(&data));
            Ok(())
        })
        .unwrap();
    assert!(total.get() >= 100_000, "only {} frames", total.get());
}

fn enabled_rig() -> Rig {
    let mut r = Rig::new(&[1], Mode::Csp).unwrap();
    r.inputs[0].enable = true;
    r.run_until(20, |r| r.status(0).enabled).unwrap();
    r
}

#[test]
fn wrong_lengths_and_unknown_identifiers_are_ignored_and_counted() {
    let mut r = enabled_rig();
    for f in [
        Frame::new(0x181, &[1, 2, 3]), // TPDO1 too short
        Frame::new(0x281, &[1; 8]),    // TPDO2 too long
        Frame::new(0x081, &[]),        // EMCY without a code
        Frame::new(0x701, &[]),        // heartbeat without a state
        Frame::new(0x1A5, &[0; 8]),    // someone else's TPDO
        Frame::remote(0x181, 7),
        Frame::from_raw(hal_canservo::frame::CAN_EFF_FLAG | 0x181, 7, [0xFF; 8]),
    ] {
        r.bus.inject(f);
    }
    r.cycle();
    let st = r.status(0);
    assert!(
        !st.amp_fault && st.enabled,
        "none of them is a fault by itself"
    );
    assert_eq!(st.bad_frames, 4);
}

#[test]
fn an_emcy_flood_never_stalls_the_cycle_and_is_said_once() {
    let mut r = enabled_rig();
    for i in 0..20_000u32 {
        let code = 0x1000 + (i % 0x100) as u16;
        r.bus.inject(Frame::new(0x081, &code.to_le_bytes()));
    }
    let (_, before) = r.engine.counters();
    r.cycle();
    assert_eq!(r.status(0).fault_code, faults::EMCY.code);
    let (_, after) = r.engine.counters();
    assert_eq!(after - before, 256, "one read takes its budget and no more");
    r.cycles(200);
    let lines = r.log_lines();
    assert_eq!(
        lines.iter().filter(|l| l.contains("EMCY received")).count(),
        1,
        "{lines:?}"
    );
}

#[test]
fn sdo_toggle_errors_are_aborted_both_ways() {
    let bus = SimBus::with_drives(&[1]);
    let client = bus.open(Filters {
        frames: vec![Filter::exact(0x581)],
        error_mask: 0,
    });
    // A client that gets the toggle wrong in a segmented upload.
    let sdo = SdoClient::new(&client, 1, std::time::Duration::from_millis(200));
    assert!(sdo.read_string(0x1008, 0).is_ok());
    client.send(&Frame::new(0x601, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]));
    bus.pump();
    assert_eq!(client.try_recv().unwrap().data[0], 0x41);
    client.send(&Frame::new(0x601, &[0x70, 0, 0, 0, 0, 0, 0, 0])); // toggle 1 first
    bus.pump();
    let a = client.try_recv().unwrap();
    assert_eq!(a.data[0], 0x80);
    assert_eq!(
        u32::from_le_bytes([a.data[4], a.data[5], a.data[6], a.data[7]]),
        AbortCode::TOGGLE.0
    );
    // A server that gets it wrong: the client aborts.
    let fake = bus.open(Filters {
        frames: vec![Filter::exact(0x609)],
        error_mask: 0,
    });
    let server = std::thread::spawn(move || {
        let t = std::time::Duration::from_secs(5);
        fake.recv_timeout(t).unwrap();
        fake.send(&Frame::new(0x589, &[0x41, 0x08, 0x10, 0, 20, 0, 0, 0]));
        fake.recv_timeout(t).unwrap();
        fake.send(&Frame::new(
            0x589,
            &[0x10, b'a', b'b', b'c', b'd', b'e', b'f', b'g'],
        )); // toggle 1
        fake.recv_timeout(t).unwrap().data
    });
    let e = SdoClient::new(&client_for(&bus, 9), 9, std::time::Duration::from_secs(5))
        .upload(0x1008, 0);
    let abort = server.join().unwrap();
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("toggle bit not alternated"));
    assert_eq!(abort[0], 0x80);
}

fn client_for(bus: &std::sync::Arc<SimBus>, node: u16) -> hal_canservo::bus::SimEndpoint {
    bus.open(Filters {
        frames: vec![Filter::exact(0x580 + node)],
        error_mask: 0,
    })
}

#[test]
fn segmented_transfers_that_never_end_are_cut_off() {
    // A client that starts a segmented download and never finishes: the
    // server aborts it with "SDO protocol timed out" and serves again.
    let bus = SimBus::with_drives(&[1]);
    let client = client_for(&bus, 1);
    client.send(&Frame::new(0x601, &[0x21, 0x08, 0x20, 0, 200, 0, 0, 0]));
    bus.pump();
    assert_eq!(
        client.try_recv().unwrap().data[0],
        0x80,
        "0x2008 does not exist"
    );
    client.send(&Frame::new(0x601, &[0x21, 0x65, 0x60, 0, 4, 0, 0, 0]));
    bus.pump();
    assert_eq!(client.try_recv().unwrap().data[0], 0x60);
    client.send(&Frame::new(0x601, &[0x00, 1, 2, 3, 4, 5, 6, 7]));
    bus.pump();
    assert_eq!(
        client.try_recv().unwrap().data[0],
        0x80,
        "more bytes than announced"
    );
    client.send(&Frame::new(0x601, &[0x20, 0x08, 0x10, 0, 0, 0, 0, 0]));
    bus.pump();
    assert_eq!(
        client.try_recv().unwrap().data[0],
        0x80,
        "0x1008 is read only"
    );
    client.send(&Frame::new(0x601, &[0x20, 0x16, 0x10, 1, 0, 0, 0, 0]));
    bus.pump();
    assert_eq!(
        client.try_recv().unwrap().data[0],
        0x60,
        "a download with no size"
    );
    for _ in 0..10 {
        client.send(&Frame::new(0x601, &[0x00, 1, 2, 3, 4, 5, 6, 7]));
        client.send(&Frame::new(0x601, &[0x10, 1, 2, 3, 4, 5, 6, 7]));
    }
    bus.pump();
    while let Some(f) = client.try_recv() {
        assert_eq!(f.data[0] & 0xE0, 0x20, "segment answers");
    }
    bus.advance(TRANSFER_TIMEOUT_NS + 1_000_000);
    let a = client.try_recv().expect("the server gives up");
    assert_eq!(a.data[0], 0x80);
    assert_eq!(
        u32::from_le_bytes([a.data[4], a.data[5], a.data[6], a.data[7]]),
        AbortCode::TIMEOUT.0
    );
    let sdo = SdoClient::new(&client, 1, std::time::Duration::from_millis(200));
    assert_eq!(
        sdo.read_u32(0x1000, 0).unwrap(),
        0x0002_0192,
        "and serves again"
    );
}
