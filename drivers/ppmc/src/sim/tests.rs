//! The simulated port and boards seen through EPP cycles.

use std::sync::Arc;

use hal_driver::sim::SimBoard;

use super::*;
use crate::epp::Epp;
use crate::regs::{dac, dio, enc, stepgen, uxc};
use crate::scan::scan;

fn bus(spec: &str) -> (Arc<SimBoard<PpmcPort>>, Epp) {
    let spec = SimSpec::parse(spec).unwrap();
    let sim = Arc::new(SimBoard::new(PpmcPort::new(0x378, 0x778, &spec)));
    let epp = Epp::new(sim.clone(), 0x378, true);
    epp.set_up(Some(0x778));
    (sim, epp)
}

#[test]
fn the_scan_finds_the_boards_in_slot_order() {
    let (_, epp) = bus("ppmc+usc+upc:2");
    let found = scan(|s| {
        let id = epp.select_read(s as u8 * 16 + 15);
        epp.clear_timeout();
        id
    })
    .unwrap();
    let got: Vec<_> = found.iter().map(|f| (f.slot, f.id.byte())).collect();
    assert_eq!(got, [(0, 0x14), (2, 0x21), (3, 0x32), (4, 0x43), (6, 0x52)]);
}

#[test]
fn an_empty_slot_times_out_and_the_timeout_clears() {
    let (_, epp) = bus("dac");
    assert_eq!(epp.select_read(0x2F), 0xFF);
    assert!(epp.timed_out());
    assert!(epp.clear_timeout());
    assert!(!epp.timed_out());
    assert_eq!(epp.select_read(0x0F), 0x21);
}

#[test]
fn counters_follow_the_dac_driven_motors_and_latch_on_the_strobe() {
    let (sim, epp) = bus("ppmc");
    // DAC board in slot 2: channel 1 at +1 V.
    let code = crate::regs::dac16_code(1.0).to_le_bytes();
    epp.select_write(0x20 + dac::DAC0 + 2, code[0]);
    epp.write_more(code[1]);
    sim.advance(100_000_000);
    epp.select_write(enc::RATE, enc::RATE_STROBE);
    let b = [epp.select_read(3), epp.read_more(), epp.read_more()];
    let counts = u32::from_le_bytes([b[0], b[1], b[2], 0]);
    // 128000 counts/s after the 20 ms time constant: 128000 * (0.1 - 0.02 * (1 - e^-5)).
    assert!((10_250..=10_265).contains(&counts), "{counts}");
    // Without a new strobe the latch holds.
    sim.advance(1_000_000);
    assert_eq!(epp.select_read(3), b[0]);
}

#[test]
fn usc_steps_only_out_of_estop() {
    let (sim, epp) = bus("usc");
    // 10 kHz forward on generator 0: divisor 1000 - 4.
    epp.select_write(stepgen::RATE0, (996 & 0xFF) as u8);
    epp.write_more((996 >> 8) as u8);
    epp.write_more(0);
    epp.select_write(stepgen::CTRL, 0x03);
    sim.advance(10_000_000);
    assert_eq!(sim.with(|p| p.motors[0]), 0.0, "in estop");
    assert_eq!(epp.select_read(uxc::DIN_B) & uxc::ESTOP_BIT, 0);
    epp.select_write(uxc::DOUT, uxc::ESTOP_BIT);
    assert_ne!(epp.select_read(uxc::DIN_B) & uxc::ESTOP_BIT, 0);
    sim.advance(10_000_000);
    assert!((sim.with(|p| p.motors[0]) - 100.0).abs() < 1e-6);
    sim.with(|p| p.chain_closed = false);
    assert_eq!(epp.select_read(uxc::DIN_B) & uxc::ESTOP_BIT, 0);
}

#[test]
fn dio_estop_input_reads_set_while_in_estop() {
    let (sim, epp) = bus("dio");
    assert_eq!(epp.select_read(dio::ESTOP_IN) & 1, 1);
    epp.select_write(dio::ESTOP_OUT, 1);
    assert_eq!(epp.select_read(dio::ESTOP_IN) & 1, 0);
    sim.with(|p| p.board_mut(0).unwrap().inputs = 0x8001);
    assert_eq!((epp.select_read(dio::DIN_A), epp.read_more()), (0x01, 0x80));
}

#[test]
fn an_armed_counter_clears_at_the_index() {
    let (sim, epp) = bus("upc");
    epp.select_write(enc::INDEX, 0x01);
    sim.with(|p| {
        p.motors[0] = 3990.0;
        let c = p.boards[0].counters.as_mut().unwrap();
        c.follow(0, 3990, 0);
        c.follow(0, 4007, 0);
        assert_eq!(c.count(0), 7);
    });
    epp.select_write(enc::RATE, enc::RATE_STROBE);
    assert_eq!(epp.select_read(enc::ISR), 1);
    assert_eq!(epp.select_read(enc::ISR), 0, "clear on read");
}
