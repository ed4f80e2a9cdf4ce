//! The board-model harness with toy models: a memory-mapped board whose
//! counter counts in simulated time and whose PWM drives a motor with an
//! encoder, and a port board. The driver side sees only the bus traits.

use std::sync::Arc;

use hal_driver::bus::{PortBus, RegWindow};
use hal_driver::plant::{DcMotor, DcMotorParams, QuadEncoder};
use hal_driver::sim::{
    Access, AccessLog, BoardModel, Dir, MemModel, PortModel, SimBoard, SimClock, Width,
};

/// Registers of the toy board.
const ID: usize = 0x00;
const CONTROL: usize = 0x04;
const COUNTER: usize = 0x08;
const ENCODER: usize = 0x0C;
const PWM: usize = 0x10;
const BOARD_ID: u32 = 0xC0DE_0001;

#[derive(Debug)]
struct Toy {
    counting: bool,
    /// Microseconds counted, and the nanoseconds not yet a whole one.
    counter: u32,
    ns_left: u64,
    motor: DcMotor,
    encoder: QuadEncoder,
}

impl Toy {
    fn new() -> Toy {
        Toy {
            counting: false,
            counter: 0,
            ns_left: 0,
            motor: DcMotor::new(DcMotorParams {
                speed_per_volt: 0.5, // revolutions per second per volt
                time_constant: 0.01,
                friction: 0.0,
            }),
            encoder: QuadEncoder::new(400),
        }
    }
}

impl BoardModel for Toy {
    fn advance(&mut self, dt_ns: u64) {
        if self.counting {
            let ns = self.ns_left + dt_ns;
            self.counter = self.counter.wrapping_add((ns / 1000) as u32);
            self.ns_left = ns % 1000;
        }
        self.motor.advance(dt_ns);
        self.encoder.set_revs(self.motor.position());
    }
    fn describe(&self) -> String {
        "simulated toy board".into()
    }
}

impl MemModel for Toy {
    fn len(&self) -> usize {
        0x20
    }
    fn read32(&mut self, offset: usize) -> u32 {
        match offset {
            ID => BOARD_ID,
            CONTROL => self.counting as u32,
            COUNTER => self.counter,
            ENCODER => self.encoder.count() as u32,
            _ => 0,
        }
    }
    fn write32(&mut self, offset: usize, value: u32) {
        match offset {
            CONTROL => self.counting = value & 1 != 0,
            COUNTER => self.counter = 0,
            // Signed per-mille duty of a 12 V supply.
            PWM => self.motor.set_duty(value as i32 as f64 / 1000.0, 12.0),
            _ => {}
        }
    }
}

/// A driver written against the trait only.
fn driver_cycle(bus: &dyn RegWindow, duty: i32) -> (u32, u32) {
    bus.write32(PWM, duty as u32);
    (bus.read32(COUNTER), bus.read32(ENCODER))
}

#[test]
fn the_log_shows_access_order_and_time() {
    let board = SimBoard::new(Toy::new()).with_log(AccessLog::new(64));
    assert_eq!(board.read32(ID), BOARD_ID);
    board.write32(CONTROL, 1);
    board.advance(2_500);
    board.write32(COUNTER, 0);
    board.advance(1_000);
    let mut two = [0u32; 2];
    board.read_burst(COUNTER, &mut two);
    let log: Vec<(u64, u64, Dir, u32)> = board
        .accesses()
        .iter()
        .map(|a| (a.time_ns, a.addr, a.dir, a.value))
        .collect();
    assert_eq!(
        log,
        vec![
            (0, ID as u64, Dir::Read, BOARD_ID),
            (0, CONTROL as u64, Dir::Write, 1),
            (2_500, COUNTER as u64, Dir::Write, 0),
            (3_500, COUNTER as u64, Dir::Read, 1),
            (3_500, ENCODER as u64, Dir::Read, 0),
        ]
    );
    assert!(board.accesses().iter().all(|a| a.width == Width::Long));
    assert_eq!(board.access_count(), 5);
    board.clear_log();
    assert!(board.accesses().is_empty());
}

#[test]
fn time_passes_only_when_told() {
    let board = SimBoard::new(Toy::new());
    board.write32(CONTROL, 1);
    assert_eq!(board.read32(COUNTER), 0);
    assert_eq!(board.read32(COUNTER), 0, "reading does not move time");
    board.advance(999);
    assert_eq!(board.read32(COUNTER), 0);
    board.advance(1);
    assert_eq!(board.read32(COUNTER), 1);
    board.advance(1_000_000);
    assert_eq!(board.read32(COUNTER), 1001);
    assert_eq!(board.now_ns(), 1_001_000);
    // An explicit clock ignores the thread's time.
    board.tick(5_000_000_000);
    board.tick(6_000_000_000);
    assert_eq!(board.read32(COUNTER), 1001);
}

#[test]
fn under_loadrt_the_board_follows_thread_time() {
    let board = SimBoard::new(Toy::new()).with_clock(Arc::new(SimClock::following_thread()));
    board.write32(CONTROL, 1);
    let t0 = 77_000_000_000;
    board.tick(t0);
    assert_eq!(
        board.read32(COUNTER),
        0,
        "the first tick only sets the origin"
    );
    for cycle in 1..=3 {
        board.tick(t0 + cycle * 1_000_000);
    }
    assert_eq!(board.read32(COUNTER), 3_000);
    assert_eq!(board.now_ns(), 3_000_000);
}

#[test]
fn the_plant_moves_what_the_registers_drive() {
    let board = SimBoard::new(Toy::new());
    // 50 % of 12 V at 0.5 rev/s/V: 3 rev/s once up to speed; 400 counts
    // per revolution.
    for _ in 0..2000 {
        driver_cycle(&board, 500);
        board.advance(1_000_000);
    }
    let (v, x) = board.with(|m| (m.motor.velocity(), m.motor.position()));
    assert!((v - 3.0).abs() < 1e-9, "{v}");
    // x(t) = 3 (t - tau (1 - e^-t/tau)) at t = 2 s, tau = 10 ms.
    assert!((x - 3.0 * (2.0 - 0.01)).abs() < 1e-6, "{x}");
    let (_, counts) = driver_cycle(&board, -500);
    assert_eq!(counts as i64, (x * 400.0).floor() as i64);
    // The outside world is set through the plant API, never registers.
    board.with(|m| m.motor.set_load(100.0));
    board.advance(1_000_000_000);
    assert!(board.with(|m| m.motor.velocity()) < -30.0);
}

#[test]
fn bad_offsets_never_reach_the_model() {
    let board = SimBoard::new(Toy::new()).with_log(AccessLog::new(8));
    assert_eq!(board.read32(0x20), u32::MAX, "past the window");
    assert_eq!(board.read32(0x06), u32::MAX, "misaligned");
    board.write32(0x1E, 1);
    let mut out = [0u32; 4];
    board.read_burst(0x14, &mut out);
    assert_eq!(out, [u32::MAX; 4]);
    assert_eq!(board.refused(), 4);
    assert_eq!(RegWindow::errors(&board), 4);
    assert!(board.accesses().is_empty());
    assert_eq!(RegWindow::describe(&board), "simulated toy board");
    assert_eq!(board.len(), 0x20);
}

/// A toy ISA board: an 8-bit status port and a 16-bit latch.
#[derive(Debug, Default)]
struct PortToy {
    latch: u16,
}

impl BoardModel for PortToy {}

impl PortModel for PortToy {
    fn read(&mut self, port: u16, width: Width) -> u32 {
        match (port, width) {
            (0x300, Width::Byte) => 0x5A,
            (0x302, Width::Word) => self.latch as u32,
            _ => u32::MAX,
        }
    }
    fn write(&mut self, port: u16, width: Width, value: u32) {
        if (port, width) == (0x302, Width::Word) {
            self.latch = value as u16;
        }
    }
}

#[test]
fn a_port_board_logs_widths_and_reads_ones_where_nothing_decodes() {
    let board = SimBoard::new(PortToy::default()).with_log(AccessLog::writes_only(4));
    let bus: &dyn PortBus = &board;
    assert_eq!(bus.inb(0x300), 0x5A);
    bus.outw(0x302, 0xBEEF);
    assert_eq!(bus.inw(0x302), 0xBEEF);
    assert_eq!(bus.inb(0x310), 0xFF);
    assert_eq!(bus.inl(0x310), u32::MAX);
    bus.outl(0x304, 1);
    assert_eq!(
        board.accesses(),
        vec![
            Access {
                time_ns: 0,
                addr: 0x302,
                width: Width::Word,
                value: 0xBEEF,
                dir: Dir::Write
            },
            Access {
                time_ns: 0,
                addr: 0x304,
                width: Width::Long,
                value: 1,
                dir: Dir::Write
            },
        ]
    );
    assert_eq!(board.with(|m| m.latch), 0xBEEF);
}

#[test]
fn log_stamps_can_come_from_the_drivers_clock() {
    // A stepping clock shared with a driver: each logged access reads it
    // once, unlogged reads do not step it.
    let clock = Arc::new(SimClock::new(100, 10));
    let board = SimBoard::new(PortToy::default())
        .with_log(AccessLog::writes_only(4))
        .stamp_log_with(clock.clone());
    board.outw(0x302, 1);
    board.inb(0x300);
    board.outw(0x302, 2);
    let t: Vec<u64> = board.accesses().iter().map(|a| a.time_ns).collect();
    assert_eq!(t, vec![100, 110]);
    assert_eq!(clock.peek(), 120);
}
