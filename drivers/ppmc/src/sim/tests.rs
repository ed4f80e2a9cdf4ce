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

/// A port bus that counts the EPP address cycles and records the
/// control register values written, in front of a simulated port.
struct Counting {
    inner: Arc<SimBoard<PpmcPort>>,
    address_cycles: std::sync::atomic::AtomicU32,
    controls: std::sync::Mutex<Vec<u8>>,
}

impl hal_driver::bus::PortBus for Counting {
    fn inb(&self, port: u16) -> u8 {
        self.inner.inb(port)
    }
    fn outb(&self, port: u16, value: u8) {
        match port {
            0x37B => {
                self.address_cycles
                    .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
            0x37A => self.controls.lock().unwrap().push(value),
            _ => {}
        }
        self.inner.outb(port, value)
    }
    fn inw(&self, port: u16) -> u16 {
        self.inner.inw(port)
    }
    fn outw(&self, port: u16, value: u16) {
        self.inner.outw(port, value)
    }
    fn inl(&self, port: u16) -> u32 {
        self.inner.inl(port)
    }
    fn outl(&self, port: u16, value: u32) {
        self.inner.outl(port, value)
    }
    fn errors(&self) -> u64 {
        0
    }
    fn describe(&self) -> String {
        "counting".into()
    }
}

fn counting(spec: &str, turn_for_reads: bool) -> (Arc<Counting>, Epp) {
    let spec = SimSpec::parse(spec).unwrap();
    let c = Arc::new(Counting {
        inner: Arc::new(SimBoard::new(PpmcPort::new(0x378, 0x778, &spec))),
        address_cycles: Default::default(),
        controls: Default::default(),
    });
    let epp = Epp::new(c.clone(), 0x378, turn_for_reads);
    (c, epp)
}

#[test]
fn a_run_of_registers_is_one_address_cycle() {
    use crate::epp::block;
    use std::sync::atomic::Ordering::Relaxed;
    let (c, epp) = counting("upc", true);
    let mut buf = [0u8; 32];
    // Counters and ISR, then the timestamps: two runs.
    epp.read_map(
        0,
        block(enc::COUNT0, enc::ISR) | block(enc::TS0, enc::TB + 1),
        &mut buf,
    );
    assert_eq!(c.address_cycles.swap(0, Relaxed), 2);
    // The PWM generators and their control block: two runs.
    let wr = [0x11u8; 32];
    epp.write_map(0, block(0x10, 0x17) | block(0x1C, 0x1E), &wr);
    assert_eq!(c.address_cycles.swap(0, Relaxed), 2);
    c.inner.with(|p| {
        let w = &p.boards[0].written;
        assert_eq!(&w[0x10..0x18], &[0x11; 8]);
        assert_eq!(&w[0x18..0x1C], &[0; 4], "outside the map");
        assert_eq!(&w[0x1C..0x1F], &[0x11; 3]);
    });
}

#[test]
fn epp_dir_decides_whether_reads_turn_the_data_lines() {
    for (turn, want) in [(true, vec![0x04, 0x24]), (false, vec![0x04])] {
        let (c, epp) = counting("dac", turn);
        assert_eq!(epp.select_read(0x0F), 0x21);
        assert_eq!(
            *c.controls.lock().unwrap(),
            want,
            "epp_dir={}",
            u8::from(!turn)
        );
    }
}

#[test]
fn timestamps_and_timebase_latch_with_the_counts() {
    let (sim, epp) = bus("encoder+dac");
    let code = crate::regs::dac16_code(1.0).to_le_bytes();
    epp.select_write(0x20, code[0]);
    epp.write_more(code[1]);
    sim.advance(50_000_000);
    epp.select_write(enc::RATE, enc::RATE_STROBE);
    let ts = u16::from_le_bytes([epp.select_read(enc::TS0), epp.read_more()]);
    let tb = u16::from_le_bytes([epp.select_read(enc::TB), epp.read_more()]);
    assert_eq!(tb, 50_000, "the 1 MHz timebase at the strobe");
    assert!(
        tb.wrapping_sub(ts) < 20,
        "a count just before the strobe: {ts}"
    );
}
