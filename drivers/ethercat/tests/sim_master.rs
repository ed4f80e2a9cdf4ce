//! The master on EtherCrab brings an in-process simulated segment to OP
//! and exchanges process data with it; faults make the affected slaves
//! unhealthy (safe outputs) and a fault reset brings them back.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use hal_ethercat::link::{InProcess, SharedSegment};
use hal_ethercat::master::{Cyclic, Master, MasterConfig, SdoWrite, SlavePlan};
use hal_ethercat::regs::{al, al_code};
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
