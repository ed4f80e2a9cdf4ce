//! Distributed clocks on the simulated segment: the master sets up the
//! SYNC unit of the slaves whose plan asks for it (registers 0x0980,
//! 0x0981, 0x0990, 0x09A0, 0x09A4 as the simulated ESCs hold them), the
//! first DC slave is the reference clock and takes the application time,
//! SYNC0 pulses start on time, the monitor sees the clocks agree; a
//! slave refuses SAFE-OP for a SYNC it cannot run.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use hal_ethercat::link::{InProcess, SharedSegment};
use hal_ethercat::master::dc::{NOT_HEARD, START_DELAY_NS};
use hal_ethercat::master::{Cyclic, DcPlan, Master, MasterConfig, SlavePlan};
use hal_ethercat::regs;
use hal_ethercat::sim::{self, Segment};

/// EK1100 (DC: the reference), EL1008 (no DC), a servo that needs
/// SYNC0, an EL7041.
fn segment(servo_needs_sync0: bool) -> SharedSegment {
    let mut devices: Vec<_> = ["EK1100", "EL1008", "servo", "EL7041"]
        .iter()
        .enumerate()
        .map(|(i, k)| sim::device_by_name(k, 10 + i as u32).unwrap())
        .collect();
    devices[2].needs_sync0 = servo_needs_sync0;
    Arc::new(Mutex::new(Segment::new(devices)))
}

fn plan(position: u16, dc: DcPlan) -> SlavePlan {
    SlavePlan {
        position,
        name: format!("S{position}"),
        dc: Some(dc),
        ..SlavePlan::default()
    }
}

const SERVO_DC: DcPlan = DcPlan {
    assign_activate: 0x0300,
    sync0_cycle_ns: 1_000_000,
    sync0_shift_ns: 250_000,
    sync1_cycle_ns: 0,
};

const STEPPER_DC: DcPlan = DcPlan {
    assign_activate: 0x0700,
    sync0_cycle_ns: 1_000_000,
    sync0_shift_ns: 0,
    sync1_cycle_ns: 2_000_000,
};

/// One cycle as the servo thread runs it: write, then read until that frame came back or was counted lost.
fn cycle(c: &mut Cyclic) {
    let lost = c.counters().lost.load(Ordering::Relaxed);
    c.write();
    for _ in 0..2000 {
        std::thread::sleep(Duration::from_millis(1));
        if c.read().fresh || c.counters().lost.load(Ordering::Relaxed) != lost {
            break;
        }
    }
}

#[test]
fn sync_units_are_set_up_and_the_clocks_kept_in_step() {
    let seg = segment(true);
    let cfg = MasterConfig {
        slaves: vec![plan(2, SERVO_DC), plan(3, STEPPER_DC)],
        ref_clock_sync_cycles: 1,
        ..MasterConfig::default()
    };
    let (mut master, mut c) = Master::start(Box::new(InProcess::new(seg.clone())), cfg).unwrap();
    {
        let s = seg.lock().unwrap();
        let servo = s.slaves()[2].sync_activation().expect("servo SYNC active");
        assert_eq!(servo.flags, regs::dc::CYCLIC | regs::dc::SYNC0);
        assert_eq!(servo.sync0_cycle, 1_000_000);
        assert!(!servo.start_in_past, "the start time is in the future");
        assert_eq!(
            servo.start % 1_000_000,
            250_000,
            "a whole cycle plus the shift"
        );
        let stepper = s.slaves()[3]
            .sync_activation()
            .expect("stepper SYNC active");
        assert_eq!(stepper.flags, 0x07);
        assert_eq!(stepper.sync1_cycle, 2_000_000);
        assert_eq!(
            s.slaves()[3].registers(regs::DC_CYCLIC_UNIT_CONTROL, 2),
            [0x00, 0x07]
        );
        // Slaves without dcConf, or without DC, are left alone.
        assert_eq!(s.slaves()[0].sync_activation(), None);
        assert_eq!(s.slaves()[1].registers(regs::DC_ACTIVATION, 1), [0]);
        // The start is about START_DELAY_NS after the clocks' time at
        // set-up, which is before now.
        let now = s.slaves()[2].system_time() as u64;
        assert!(servo.start <= now + START_DELAY_NS + 2_000_000);
    }
    assert!(c.dc_status().in_use);
    // Cycles until SYNC0 has pulsed and the monitor sees the clocks
    // within 2 µs of each other.
    let mut n = 0;
    loop {
        cycle(&mut c);
        n += 1;
        let events = seg.lock().unwrap().slaves()[2].sync0_events();
        let dc = c.dc_status();
        if events > 0 && dc.diff < 2_000 {
            break;
        }
        assert!(
            n < 3000,
            "no SYNC0 pulse or no agreement: {events} pulses, {dc:?}"
        );
    }
    let dc = c.dc_status();
    assert_ne!(dc.diff, NOT_HEARD);
    assert!(dc.reference_time > 0);
    // The reference clock (the EK1100, first with DC) takes the
    // application time; the others follow it by FRMW, not by writes of
    // the master's time.
    {
        let s = seg.lock().unwrap();
        assert!(s.slaves()[0].system_time_writes() > 0);
        assert_eq!(s.slaves()[1].system_time_writes(), 0, "no DC, no writes");
        assert!(s.slaves()[2].system_time_writes() > 0);
    }
    master.stop();
}

fn refused(seg: SharedSegment, plans: Vec<SlavePlan>) -> String {
    let cfg = MasterConfig {
        slaves: plans,
        state_timeout: Duration::from_secs(2),
        ..MasterConfig::default()
    };
    Master::start(Box::new(InProcess::new(seg)), cfg)
        .unwrap_err()
        .to_string()
}

#[test]
fn slaves_refuse_a_sync_they_cannot_run() {
    // The servo needs SYNC0 and gets none: it stays out of SAFE-OP.
    let seg = segment(true);
    let e = refused(seg.clone(), vec![]);
    assert!(e.contains("OP"), "{e}");
    let s = seg.lock().unwrap();
    assert_eq!(s.slaves()[2].al_code(), regs::al_code::INVALID_DC_SYNC);
    drop(s);
    // A SYNC0 cycle too short for the slave.
    let seg = segment(false);
    let short = DcPlan {
        sync0_cycle_ns: 10_000,
        ..SERVO_DC
    };
    let e = refused(seg.clone(), vec![plan(2, short)]);
    assert!(e.contains("OP"), "{e}");
    assert_eq!(
        seg.lock().unwrap().slaves()[2].al_code(),
        regs::al_code::DC_SYNC0_CYCLE
    );
    // dcConf on a slave without DC: the master says which and why.
    let e = refused(segment(false), vec![plan(1, SERVO_DC)]);
    assert!(
        e.contains("slave 1 (S1)") && e.contains("no DC sync unit"),
        "{e}"
    );
}
