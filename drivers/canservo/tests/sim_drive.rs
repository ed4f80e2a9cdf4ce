//! The simulated drive on its own (hardware.md §6.12): NMT gating and
//! heartbeats, the PDO engine's transmission types, timers and the SYNC
//! counter, EMCY and the error history, the master-heartbeat consumer,
//! software limits and digital inputs.

use hal_canservo::frame::Frame;
use hal_canservo::power::PowerState;
use hal_canservo::regs::obj;
use hal_canservo::sim::{NmtState, SimDrive, SimDriveConfig};
use hal_driver::plant::Switch;

fn drive() -> (SimDrive, Vec<Frame>) {
    let mut d = SimDrive::new(SimDriveConfig::new(1));
    let mut out = Vec::new();
    d.power_up(&mut out);
    assert_eq!(out, vec![Frame::new(0x701, &[0])], "boot-up");
    out.clear();
    (d, out)
}

fn sdo_write(d: &mut SimDrive, out: &mut Vec<Frame>, index: u16, sub: u8, data: &[u8]) -> Frame {
    let i = index.to_le_bytes();
    let mut f = [
        0x23 | ((4 - data.len() as u8) << 2),
        i[0],
        i[1],
        sub,
        0,
        0,
        0,
        0,
    ];
    f[4..4 + data.len()].copy_from_slice(data);
    out.clear();
    d.receive(&Frame::new(0x601, &f), out);
    out.pop().expect("an answer")
}

fn ids(out: &[Frame]) -> Vec<u32> {
    out.iter().map(|f| f.id).collect()
}

#[test]
fn nmt_states_gate_the_services() {
    let (mut d, mut out) = drive();
    assert_eq!(d.nmt_state(), NmtState::PreOperational);
    d.receive(&Frame::new(0, &[0x02, 1]), &mut out);
    assert_eq!(d.nmt_state(), NmtState::Stopped);
    d.receive(
        &Frame::new(0x601, &[0x40, 0, 0x10, 0, 0, 0, 0, 0]),
        &mut out,
    );
    assert!(out.is_empty(), "no SDO while stopped");
    sdo_write_heartbeat(&mut d, &mut out);
    d.receive(&Frame::new(0, &[0x80, 0]), &mut out);
    assert_eq!(d.nmt_state(), NmtState::PreOperational, "broadcast");
    d.receive(&Frame::new(0, &[0x01, 2]), &mut out);
    assert_eq!(
        d.nmt_state(),
        NmtState::PreOperational,
        "someone else's start"
    );
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    assert_eq!(d.nmt_state(), NmtState::Operational);
    out.clear();
    d.advance(100_000_000, &mut out);
    assert!(
        out.contains(&Frame::new(0x701, &[0x05])),
        "heartbeat says operational: {out:?}"
    );
}

fn sdo_write_heartbeat(d: &mut SimDrive, out: &mut Vec<Frame>) {
    d.receive(&Frame::new(0, &[0x80, 1]), out);
    let a = sdo_write(d, out, obj::PRODUCER_HEARTBEAT, 0, &50u16.to_le_bytes());
    assert_eq!(a.data[0], 0x60);
    out.clear();
    d.advance(120_000_000, out);
    let beats = out.iter().filter(|f| f.id == 0x701).count();
    assert_eq!(beats, 3, "at 0, 50 and 100 ms");
}

#[test]
fn pdo_transmission_types_timers_and_sync_counter() {
    let (mut d, mut out) = drive();
    // TPDO1 every 2nd SYNC; TPDO2 on change only (type 0); TPDO3 event
    // driven with a 20 ms timer and 5 ms inhibit; TPDO4 on RTR (253).
    for (p, t) in [(0u16, 2u8), (1, 0), (2, 254), (3, 253)] {
        assert_eq!(
            sdo_write(&mut d, &mut out, obj::TPDO_COMM + p, 2, &[t]).data[0],
            0x60
        );
    }
    sdo_write(
        &mut d,
        &mut out,
        obj::TPDO_COMM + 2,
        1,
        &(0x8000_0381u32).to_le_bytes(),
    );
    sdo_write(
        &mut d,
        &mut out,
        obj::TPDO_COMM + 2,
        3,
        &50u16.to_le_bytes(),
    );
    sdo_write(
        &mut d,
        &mut out,
        obj::TPDO_COMM + 2,
        5,
        &20u16.to_le_bytes(),
    );
    sdo_write(
        &mut d,
        &mut out,
        obj::TPDO_COMM + 2,
        1,
        &(0x381u32).to_le_bytes(),
    );
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    out.clear();
    let sync = Frame::new(0x80, &[]);
    let mut per_sync = Vec::new();
    for _ in 0..4 {
        out.clear();
        d.receive(&sync, &mut out);
        per_sync.push(ids(&out));
    }
    assert_eq!(
        per_sync[0],
        vec![0x281],
        "type 0 sends its first data; type 2 waits"
    );
    assert_eq!(per_sync[1], vec![0x181]);
    assert_eq!(per_sync[2], Vec::<u32>::new(), "nothing changed");
    assert_eq!(per_sync[3], vec![0x181]);
    out.clear();
    for _ in 0..50 {
        d.advance(1_000_000, &mut out); // event timers run at each advance
    }
    let timed = out.iter().filter(|f| f.id == 0x381).count();
    assert!((2..=4).contains(&timed), "event timer every 20 ms: {timed}");
    out.clear();
    d.receive(&Frame::remote(0x481, 6), &mut out);
    assert_eq!(ids(&out), vec![0x481], "RTR answered for type 253");
    // The SYNC counter and a start value: TPDO1 starts counting at 3.
    d.receive(&Frame::new(0, &[0x80, 1]), &mut out);
    sdo_write(&mut d, &mut out, obj::SYNC_COUNTER_OVERFLOW, 0, &[4]);
    sdo_write(
        &mut d,
        &mut out,
        obj::TPDO_COMM,
        1,
        &(0x8000_0181u32).to_le_bytes(),
    );
    sdo_write(&mut d, &mut out, obj::TPDO_COMM, 6, &[3]);
    sdo_write(
        &mut d,
        &mut out,
        obj::TPDO_COMM,
        1,
        &(0x181u32).to_le_bytes(),
    );
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    let mut at = Vec::new();
    for c in [1u8, 2, 3, 4, 1, 2] {
        out.clear();
        d.receive(&Frame::new(0x80, &[c]), &mut out);
        if out.iter().any(|f| f.id == 0x181) {
            at.push(c);
        }
    }
    assert_eq!(at, vec![3, 1], "from counter 3, every 2nd SYNC");
    assert_eq!(
        sdo_write(&mut d, &mut out, obj::SYNC_COUNTER_OVERFLOW, 0, &[1]).data[0],
        0x80
    );
}

#[test]
fn rpdo_lengths_are_checked_with_emcy() {
    let (mut d, mut out) = drive();
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    out.clear();
    d.receive(&Frame::new(0x401, &[0x0F, 0]), &mut out); // RPDO3 maps 6 bytes
    assert_eq!(out[0].id, 0x81);
    assert_eq!(&out[0].data[..2], &[0x10, 0x82], "EMCY 0x8210");
    out.clear();
    d.advance(1_000_000, &mut out);
    out.clear();
    d.receive(&Frame::new(0x401, &[0x0F, 0, 1, 2, 3, 4, 5]), &mut out);
    assert_eq!(&out[0].data[..2], &[0x20, 0x82], "EMCY 0x8220");
    assert_eq!(d.object(obj::ERROR_HISTORY, 0), 2);
    assert_eq!(d.object(obj::ERROR_HISTORY, 1), 0x8220, "newest first");
    assert_eq!(
        sdo_write(&mut d, &mut out, obj::ERROR_HISTORY, 0, &[0]).data[0],
        0x60
    );
    assert_eq!(d.object(obj::ERROR_HISTORY, 0), 0, "cleared");
}

#[test]
fn emcy_inhibit_time_delays_the_next_emcy() {
    let (mut d, mut out) = drive();
    sdo_write(
        &mut d,
        &mut out,
        obj::EMCY_INHIBIT,
        0,
        &100u16.to_le_bytes(),
    ); // 10 ms
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    out.clear();
    d.receive(&Frame::new(0x401, &[0x0F]), &mut out);
    d.receive(&Frame::new(0x401, &[0x0F, 0]), &mut out);
    assert_eq!(ids(&out), vec![0x81], "the second waits");
    out.clear();
    d.advance(5_000_000, &mut out);
    assert!(out.iter().all(|f| f.id != 0x81));
    d.advance(6_000_000, &mut out);
    assert_eq!(out.iter().filter(|f| f.id == 0x81).count(), 1);
}

#[test]
fn a_lost_master_heartbeat_faults_the_drive_and_drops_it_to_pre_operational() {
    let (mut d, mut out) = drive();
    sdo_write(
        &mut d,
        &mut out,
        obj::CONSUMER_HEARTBEAT,
        1,
        &(127u32 << 16 | 30).to_le_bytes(),
    );
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    d.receive(&Frame::new(0x77F, &[0x05]), &mut out);
    d.advance(20_000_000, &mut out);
    d.receive(&Frame::new(0x77F, &[0x05]), &mut out);
    d.advance(20_000_000, &mut out);
    assert_eq!(d.nmt_state(), NmtState::Operational, "heartbeats on time");
    out.clear();
    d.advance(20_000_000, &mut out);
    assert!(
        out.iter()
            .any(|f| f.id == 0x81 && f.data[..2] == [0x30, 0x81]),
        "EMCY 0x8130"
    );
    assert_eq!(d.power_state(), PowerState::Fault, "0x6007 = 1: fault");
    assert_eq!(d.nmt_state(), NmtState::PreOperational, "0x1029 = 0");
}

#[test]
fn store_restore_signatures_and_pdo_mapping_rules() {
    let (mut d, mut out) = drive();
    assert_eq!(
        sdo_write(
            &mut d,
            &mut out,
            obj::STORE,
            1,
            &0x6576_6173u32.to_le_bytes()
        )
        .data[0],
        0x60
    );
    assert_eq!(
        sdo_write(
            &mut d,
            &mut out,
            obj::RESTORE,
            1,
            &0x6461_6F6Cu32.to_le_bytes()
        )
        .data[0],
        0x60
    );
    let a = sdo_write(&mut d, &mut out, obj::RESTORE, 1, &1u32.to_le_bytes());
    assert_eq!(
        u32::from_le_bytes([a.data[4], a.data[5], a.data[6], a.data[7]]),
        0x0800_0020
    );
    let a = sdo_write(
        &mut d,
        &mut out,
        obj::RPDO_MAP,
        1,
        &0x6041_0010u32.to_le_bytes(),
    );
    assert_eq!(
        u32::from_le_bytes([a.data[4], a.data[5], a.data[6], a.data[7]]),
        0x0800_0022,
        "PDO valid"
    );
}

#[test]
fn software_limits_and_digital_inputs() {
    let mut cfg = SimDriveConfig::new(1);
    cfg.home_switch = Some(Switch::between(100.0, 200.0));
    cfg.positive_limit = Some(Switch::at_or_above(5000.0));
    let mut d = SimDrive::new(cfg);
    let mut out = Vec::new();
    d.power_up(&mut out);
    assert_eq!(d.object(obj::DIGITAL_INPUTS, 0), 0);
    d.set_motor_position(150.0);
    assert_eq!(d.object(obj::DIGITAL_INPUTS, 0), 0b100);
    d.set_motor_position(6000.0);
    assert_eq!(d.object(obj::DIGITAL_INPUTS, 0), 0b010);
    d.set_motor_position(0.0);
    // CSP with limits -1000..1000: a target of 3000 stops at 1000.
    sdo_write(
        &mut d,
        &mut out,
        obj::SOFTWARE_LIMIT,
        1,
        &(-1000i32).to_le_bytes(),
    );
    sdo_write(
        &mut d,
        &mut out,
        obj::SOFTWARE_LIMIT,
        2,
        &1000i32.to_le_bytes(),
    );
    sdo_write(&mut d, &mut out, obj::MODES_OF_OPERATION, 0, &[8]);
    for cw in [6u16, 7, 15] {
        sdo_write(&mut d, &mut out, obj::CONTROLWORD, 0, &cw.to_le_bytes());
    }
    assert_eq!(d.power_state(), PowerState::OperationEnabled);
    // RPDO3 (controlword + target position, event driven by default).
    d.receive(&Frame::new(0, &[0x01, 1]), &mut out);
    let t = 3000i32.to_le_bytes();
    d.receive(
        &Frame::new(0x401, &[0x0F, 0, t[0], t[1], t[2], t[3]]),
        &mut out,
    );
    d.advance(500_000_000, &mut out);
    assert!((d.position() - 1000.0).abs() < 2.0, "{}", d.position());
    assert!(d.statusword() & 0x0800 != 0, "internal limit active");
}
