//! The master on EtherCrab brings an in-process simulated segment to OP
//! and exchanges process data with it; faults make the affected slaves
//! unhealthy (safe outputs) and a fault reset brings them back.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use hal_ethercat::link::{InProcess, SharedSegment};
use hal_ethercat::master::{Cyclic, DcPlan, Master, MasterConfig, SdoWrite, SlavePlan};
use hal_ethercat::regs::{self, al, al_code};
use hal_ethercat::sim::{self, Segment};

fn segment() -> SharedSegment {
    let kinds = [
        "EK1100", "EL1008", "EL2008", "EL3102", "EL4102", "EL5101", "EL7041", "servo",
    ];
    let devices = kinds
        .iter()
        .enumerate()
        .map(|(i, k)| sim::device_by_name(k, 100 + i as u32).unwrap())
        .collect();
    Arc::new(Mutex::new(Segment::new(devices)))
}

/// Runs `n` cycles of write, then read until the frame of that write
/// came back or was counted lost (bounded: a loaded machine may run the
/// helper late, but a cycle's outcome is always seen).
fn cycles(c: &mut Cyclic, n: usize, mut each: impl FnMut(&mut Cyclic)) {
    for _ in 0..n {
        each(c);
        let lost = c.counters().lost.load(Ordering::Relaxed);
        c.write();
        for _ in 0..2000 {
            std::thread::sleep(Duration::from_millis(1));
            if c.read().fresh || c.counters().lost.load(Ordering::Relaxed) != lost {
                break;
            }
        }
    }
}

#[test]
fn bring_up_exchange_and_faults() {
    let seg = segment();
    let cfg = MasterConfig {
        slaves: vec![SlavePlan {
            position: 7,
            name: "servo".into(),
            identity: Some((sim::servo::SIM_VENDOR, sim::servo::SIM_SERVO)),
            sdos: vec![SdoWrite {
                index: 0x6081,
                sub: Some(0),
                data: 5000u32.to_le_bytes().to_vec(),
            }],
            dc: None,
            emergencies: false,
        }],
        ..MasterConfig::default()
    };
    let (mut master, mut c) = Master::start(Box::new(InProcess::new(seg.clone())), cfg).unwrap();
    let names: Vec<&str> = master.slaves().iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        ["EK1100", "EL1008", "EL2008", "EL3102", "EL4102", "EL5101", "EL7041", "SimServo"]
    );
    for s in seg.lock().unwrap().slaves() {
        assert_eq!(s.al_state(), (al::OP, false), "{}", s.device.kind);
    }
    // The PRE-OP SDO write arrived.
    assert_eq!(
        seg.lock().unwrap().slaves()[7].device.od.get(0x6081, 0),
        5000
    );
    let sizes: Vec<(usize, usize)> = master
        .slaves()
        .iter()
        .map(|s| (s.inputs.len(), s.outputs.len()))
        .collect();
    assert_eq!(sizes[1], (1, 0));
    assert_eq!(sizes[2], (0, 1));
    assert_eq!(sizes[3], (6, 0));
    assert_eq!(sizes[7], (13, 11));

    // Inputs: EL1008 channel 3 and EL3102 channel 1; outputs: EL2008 bit 5.
    {
        let mut s = seg.lock().unwrap();
        s.slave_mut(1).unwrap().device.od.set(0x6020, 1, 1);
        s.slave_mut(3).unwrap().device.od.set(0x3101, 2, 0x1234);
    }
    cycles(&mut c, 5, |c| c.outputs_mut(2)[0] = 0b0010_0000);
    let st = c.read();
    assert!(st.all_op && st.link_up, "{st:?}");
    assert_eq!(st.wkc, st.expected_wkc);
    assert_eq!(c.inputs(1), &[0b100]);
    assert_eq!(&c.inputs(3)[1..3], &0x1234u16.to_le_bytes());
    assert_eq!(seg.lock().unwrap().slaves()[2].device.od.get(0x7050, 1), 1);

    // A slave lost: the line is cut before the EL4102. The working
    // counter is short, every slave unhealthy, outputs go to zero.
    seg.lock().unwrap().cut_before(Some(4));
    cycles(&mut c, 5, |c| c.outputs_mut(2)[0] = 0b0010_0000);
    let st = c.read();
    assert!(!st.all_op && st.wkc < st.expected_wkc, "{st:?}");
    assert!(!c.healthy(2));
    assert_eq!(
        seg.lock().unwrap().slaves()[2].device.od.get(0x7050, 1),
        0,
        "safe output"
    );
    assert!(c.counters().wkc_short.load(Ordering::Relaxed) > 0);
    // Reconnected: the slaves kept OP, data flows again.
    seg.lock().unwrap().cut_before(None);
    cycles(&mut c, 5, |c| c.outputs_mut(2)[0] = 0b0010_0000);
    assert!(c.read().all_op);

    // An AL error: the EL5101 drops to SAFE-OP with 0x001B; a fault
    // reset brings it back to OP.
    seg.lock()
        .unwrap()
        .slave_mut(5)
        .unwrap()
        .raise_al_error(al_code::SM_WATCHDOG);
    cycles(&mut c, 3, |_| {});
    assert!(!c.read().all_op);
    assert_eq!(c.al_state(5) & al::STATE_MASK, al::SAFEOP);
    c.fault_reset();
    let mut ok = false;
    for _ in 0..200 {
        cycles(&mut c, 1, |_| {});
        if c.read().all_op {
            ok = true;
            break;
        }
    }
    assert!(ok, "the fault reset brought the slave back to OP");
    assert_eq!(seg.lock().unwrap().slaves()[5].al_state(), (al::OP, false));

    // The link down: frames are lost and counted, never waited for.
    seg.lock().unwrap().set_link_down(true);
    cycles(&mut c, 3, |_| {});
    let st = c.read();
    assert!(!st.fresh && !st.all_op);
    master.stop();
    assert!(master.counters().lost.load(Ordering::Relaxed) > 0);
}

#[test]
fn a_wrong_slave_is_a_load_error_naming_it() {
    let seg = segment();
    let cfg = MasterConfig {
        slaves: vec![SlavePlan {
            position: 1,
            name: "D1".into(),
            identity: Some((2, 0x07D8_3052)),
            sdos: vec![],
            dc: None,
            emergencies: false,
        }],
        ..MasterConfig::default()
    };
    let e = Master::start(Box::new(InProcess::new(seg)), cfg)
        .unwrap_err()
        .to_string();
    assert!(e.contains("slave 1 (D1)") && e.contains("EL1008"), "{e}");
}

/// Runs cycles until `cond` holds, for at most `limit`.
fn cycles_until(
    c: &mut Cyclic,
    limit: Duration,
    mut cond: impl FnMut(&mut Cyclic) -> bool,
) -> bool {
    let start = std::time::Instant::now();
    while start.elapsed() < limit {
        cycles(c, 1, |_| {});
        if cond(c) {
            return true;
        }
    }
    false
}

#[test]
fn a_power_cycled_slave_is_brought_back_to_op_and_a_different_device_is_refused() {
    let seg = segment();
    let cfg = MasterConfig {
        slaves: vec![SlavePlan {
            position: 7,
            name: "servo".into(),
            identity: Some((sim::servo::SIM_VENDOR, sim::servo::SIM_SERVO)),
            sdos: vec![SdoWrite {
                index: 0x6081,
                sub: Some(0),
                data: 5000u32.to_le_bytes().to_vec(),
            }],
            dc: Some(DcPlan {
                assign_activate: 0x0300,
                sync0_cycle_ns: 1_000_000,
                sync0_shift_ns: 0,
                sync1_cycle_ns: 0,
            }),
            emergencies: false,
        }],
        ..MasterConfig::default()
    };
    let (mut master, mut c) = Master::start(Box::new(InProcess::new(seg.clone())), cfg).unwrap();
    cycles(&mut c, 5, |_| {});
    assert!(c.read().all_op);
    let station = seg.lock().unwrap().slaves()[7].station_address();

    // The drive and the EL2008 power-cycle: INIT, no station address,
    // the drive's PRE-OP configuration forgotten.
    {
        let mut s = seg.lock().unwrap();
        s.slave_mut(7).unwrap().device.od.set(0x6081, 0, 1);
        s.reset_slave(7);
        s.reset_slave(2);
        assert_eq!(s.slaves()[7].al_state(), (al::INIT, false));
        assert_eq!(s.slaves()[7].station_address(), 0);
    }
    cycles(&mut c, 2, |_| {});
    assert!(!c.read().all_op, "the lost slaves are seen");
    // No fault reset: the master brings them back on its own, the
    // others exchanging data meanwhile.
    let back = cycles_until(&mut c, Duration::from_secs(20), |c| c.read().all_op);
    assert!(
        back,
        "all slaves back in OP; states {:?}",
        (0..8).map(|i| c.al_state(i)).collect::<Vec<_>>()
    );
    {
        let s = seg.lock().unwrap();
        assert_eq!(s.slaves()[7].station_address(), station);
        assert_eq!(
            s.slaves()[7].device.od.get(0x6081, 0),
            5000,
            "the SDO write again"
        );
        assert_eq!(s.slaves()[2].al_state(), (al::OP, false));
        // Its clock given its offset again (power-on cleared it), its
        // SYNC unit running.
        let offset = s.slaves()[7].registers(regs::DC_SYSTEM_TIME_OFFSET, 8);
        assert!(offset.iter().any(|b| *b != 0), "the DC offset set again");
        let sync = s.slaves()[7].sync_activation().expect("SYNC set up again");
        assert_eq!(sync.sync0_cycle, 1_000_000);
    }
    // Outputs reach the EL2008 again.
    cycles(&mut c, 5, |c| c.outputs_mut(2)[0] = 0b0010_0000);
    assert_eq!(seg.lock().unwrap().slaves()[2].device.od.get(0x7050, 1), 1);
    assert_eq!(c.refused(2), None);

    // An EL1008 plugged where the EL2008 was: refused, named, left in
    // INIT; the rest keep running.
    {
        let mut s = seg.lock().unwrap();
        let el1008 = sim::device_by_name("EL1008", 999).unwrap();
        *s.slave_mut(2).unwrap() = sim::esc::Esc::new(el1008, 2);
        s.reset_slave(2);
    }
    let seen = cycles_until(&mut c, Duration::from_secs(20), |c| c.refused(2).is_some());
    assert!(seen, "the other device is refused");
    let (vendor, product) = c.refused(2).unwrap();
    assert_eq!((vendor, product), (2, 0x03F0_3052), "EL1008's identity");
    cycles(&mut c, 20, |_| {});
    assert!(!c.read().all_op);
    assert!(c.healthy(7) || c.read().wkc < c.read().expected_wkc);
    let s2 = seg.lock().unwrap().slaves()[2].al_state().0;
    assert!(
        s2 == al::INIT,
        "the other device stays in INIT, not {s2:#x}"
    );
    master.stop();
}
