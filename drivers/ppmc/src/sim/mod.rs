//! A simulated parallel port in EPP mode with Pico boards on its cable,
//! on the shared driver layer's port bus: the driver cannot tell it from
//! a real port reached with `inb`/`outb`.
//!
//! The port decodes its eight registers at `base` and the ECP extended
//! control register at `base_hi + 2`. A byte written to the EPP address
//! register (`base + 3`) is an address cycle; a byte read or written at
//! `base + 4` a data cycle at that address, after which the address
//! steps by one (16- and 32-bit accesses at `base + 4` are two and four
//! data cycles, as a port chip makes them). A data cycle no board
//! decodes, or any cycle while the cable is out ([`PpmcPort::connected`])
//! or the ECR selects another mode than EPP, times out: the status
//! register's bit 0 goes high, reads give 0xFF, until the driver clears
//! it (a second status read, or writing it as 1).
//!
//! Boards sit in consecutive slots from 0 in the order `sim=` names them
//! ([`SimSpec`]). The machine behind them: one motor per output channel,
//! numbered per bus in slot order: DAC channel n, step generator n and
//! PWM generator n each drive motor n, and encoder counter n counts motor
//! n. DAC and PWM channels drive DC servo motors on velocity-mode
//! amplifiers ([`DcMotor`], first order, no friction): a DAC volt runs
//! its motor at [`DAC_COUNTS_PER_VOLT`] counts/s with a
//! [`DAC_TIME_CONSTANT_S`] time constant, full PWM duty at
//! [`PWM_COUNTS_AT_FULL_DUTY`] counts/s with [`PWM_TIME_CONSTANT_S`]. A step moves a stepper one
//! count. So LinuxCNC's `ppmc` sample (INPUT_SCALE -128000, OUTPUT_SCALE
//! -1), its `univpwm` (4000 and 5) and its `univstep` samples close their
//! loops at unity gain, with their own PID tunings.
//! Index pulses come every [`INDEX_COUNTS`] counts. The safety chain of
//! the estop circuit is closed unless a test opens it
//! ([`PpmcPort::chain_closed`]). The USC/UPC watchdog (a jumper option
//! that also wants writes to two adjacent velocity outputs before the
//! board leaves estop) is not modelled: the boards act as with the
//! jumper off.

pub mod boards;

use hal_driver::plant::{DcMotor, DcMotorParams};
use hal_driver::sim::{BoardModel, PortModel, Width};
use hal_parport::regs as port;

pub use boards::{Board, Counters, INDEX_COUNTS};

use crate::regs::{SLOTS, SLOT_SIZE};
use crate::scan::{BoardId, Kind};

/// Motor counts per second for each volt of a DAC channel.
pub const DAC_COUNTS_PER_VOLT: f64 = 128_000.0;
/// Motor counts per second at 100 % PWM duty.
pub const PWM_COUNTS_AT_FULL_DUTY: f64 = 20_000.0;
/// The time constant of the motors on DAC channels (the `ppmc` sample's
/// D gain of 20 needs one above 10 ms at a 1 ms servo period).
pub const DAC_TIME_CONSTANT_S: f64 = 0.02;
/// The time constant of the motors on PWM channels (the `univpwm`
/// sample, with no FF2, follows its 20 units/s² ramps within its
/// following error only on a motor this quick).
pub const PWM_TIME_CONSTANT_S: f64 = 0.005;

/// A servo motor of `counts_per_volt` (the drive is volts, or the duty)
/// and time constant `tau`.
fn servo(counts_per_volt: f64, tau: f64) -> DcMotor {
    DcMotor::new(DcMotorParams {
        speed_per_volt: counts_per_volt,
        time_constant: tau,
        friction: 0.0,
    })
}

/// Why a `sim=` item names no bus of boards.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SimSpecError {
    /// A revision that is not 1 to 14.
    #[error("'{0}' is not a firmware revision (1..14)")]
    Revision(String),
    /// A name that is no simulated board.
    #[error(
        "'{0}' is not a simulated board (encoder, dac, dio, usc, upc, or ppmc for \
         encoder+dac+dio; a revision may follow, as upc:2)"
    )]
    Board(String),
    /// More boards than a bus has slots.
    #[error("these boards need {0} slots; a bus has {SLOTS}")]
    Slots(usize),
}

/// The boards `sim=` puts on one bus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimSpec {
    /// The boards, in slot order.
    pub boards: Vec<BoardId>,
}

impl SimSpec {
    /// Parses a `sim` item: board names joined by `+` (`encoder`, `dac`,
    /// `dio`, `usc`, `upc`; `ppmc` is `encoder+dac+dio`), each with an
    /// optional firmware revision (`upc:2`). Without one a board has the
    /// newest revision this driver knows (encoder 4, DAC 1, DIO 2, USC 3,
    /// UPC 4).
    pub fn parse(text: &str) -> Result<SimSpec, SimSpecError> {
        let mut boards = Vec::new();
        for word in text.split('+').map(str::trim) {
            let (name, rev) = match word.split_once(':') {
                Some((n, r)) => {
                    let rev = r
                        .parse::<u8>()
                        .ok()
                        .filter(|r| (1..=14).contains(r))
                        .ok_or_else(|| SimSpecError::Revision(r.to_string()))?;
                    (n, Some(rev))
                }
                None => (word, None),
            };
            let kinds: &[(Kind, u8)] = match name.to_ascii_lowercase().as_str() {
                "encoder" => &[(Kind::Encoder, 4)],
                "dac" => &[(Kind::Dac, 1)],
                "dio" => &[(Kind::Dio, 2)],
                "usc" => &[(Kind::Usc, 3)],
                "upc" => &[(Kind::Upc, 4)],
                "ppmc" if rev.is_none() => &[(Kind::Encoder, 4), (Kind::Dac, 1), (Kind::Dio, 2)],
                _ => return Err(SimSpecError::Board(name.to_string())),
            };
            boards.extend(kinds.iter().map(|&(kind, r)| BoardId {
                kind,
                rev: rev.unwrap_or(r),
            }));
        }
        let slots: usize = boards.iter().map(|b| b.slots()).sum();
        if slots > SLOTS {
            return Err(SimSpecError::Slots(slots));
        }
        Ok(SimSpec { boards })
    }
}

/// A parallel port with Pico boards behind it.
#[derive(Debug, Clone)]
pub struct PpmcPort {
    base: u16,
    base_hi: u16,
    /// The boards, in slot order.
    pub boards: Vec<Board>,
    /// Motor positions in counts, one per output channel (a test may
    /// move one by hand).
    pub motors: Vec<f64>,
    /// The servo motors' dynamics (DAC and PWM channels; `None`: a
    /// stepper).
    servos: Vec<Option<DcMotor>>,
    /// Whether the cable is plugged in (false: every EPP cycle times out).
    pub connected: bool,
    /// Whether the estop safety chain is closed.
    pub chain_closed: bool,
    spp_data: u8,
    control: u8,
    ecr: u8,
    timeout: bool,
    address: u8,
    now_ns: u64,
    /// Timeouts seen (for tests).
    pub timeouts: u64,
    /// Scratch of `advance`, one per motor (no allocation per period):
    /// the drives (a servo's volts or duty, a stepper's steps/s) and when
    /// each motor last crossed a whole count.
    rates: Vec<f64>,
    last_count_ns: Vec<u64>,
}

impl PpmcPort {
    /// A port at `base` (ECR block at `base_hi`) with the boards of `spec`.
    pub fn new(base: u16, base_hi: u16, spec: &SimSpec) -> PpmcPort {
        let mut slot = 0;
        let boards: Vec<Board> = spec
            .boards
            .iter()
            .map(|&id| {
                let b = Board::new(id, slot);
                slot += id.slots();
                b
            })
            .collect();
        let mut servos: Vec<Option<DcMotor>> = Vec::new();
        for b in &boards {
            let motor = match b.id.kind {
                Kind::Dac => Some(servo(DAC_COUNTS_PER_VOLT, DAC_TIME_CONSTANT_S)),
                Kind::Upc => Some(servo(PWM_COUNTS_AT_FULL_DUTY, PWM_TIME_CONSTANT_S)),
                Kind::Usc => None,
                _ => continue,
            };
            servos.extend(std::iter::repeat_n(motor, 4));
        }
        let motors = servos.len();
        PpmcPort {
            servos,
            base,
            base_hi,
            boards,
            motors: vec![0.0; motors],
            connected: true,
            chain_closed: true,
            spp_data: 0,
            control: 0,
            ecr: port::ECR_EPP_MODE,
            timeout: false,
            address: 0,
            now_ns: 0,
            timeouts: 0,
            rates: vec![0.0; motors],
            last_count_ns: vec![0; motors],
        }
    }

    /// The board whose first slot is `slot`.
    pub fn board(&self, slot: usize) -> Option<&Board> {
        self.boards.iter().find(|b| b.slot == slot)
    }

    /// The board whose first slot is `slot`, to change its inputs.
    pub fn board_mut(&mut self, slot: usize) -> Option<&mut Board> {
        self.boards.iter_mut().find(|b| b.slot == slot)
    }

    /// Whether board `b`'s outputs are live: the chain closed and its
    /// estop output on (a slave follows the bus's first board with an
    /// estop circuit that is not one).
    pub fn enabled(&self, b: &Board) -> bool {
        if !self.chain_closed {
            return false;
        }
        if b.is_slave() {
            return self
                .boards
                .iter()
                .find(|m| m.has_estop() && !m.is_slave())
                .is_some_and(Board::estop_out);
        }
        b.estop_out()
    }

    fn timebase(&self) -> u16 {
        (self.now_ns / 1000) as u16
    }

    fn epp_live(&self) -> bool {
        self.connected && self.ecr & 0xE0 == port::ECR_EPP_MODE & 0xE0
    }

    /// The board decoding bus address `addr` and the offset in it.
    fn decode(&self, addr: u8) -> Option<(usize, u8)> {
        let slot = (addr / SLOT_SIZE) as usize;
        self.boards
            .iter()
            .position(|b| slot >= b.slot && (slot - b.slot) < b.id.slots())
            .map(|i| (i, addr - (self.boards[i].slot as u8) * SLOT_SIZE))
    }

    fn data_read(&mut self) -> u8 {
        let addr = self.address;
        self.address = addr.wrapping_add(1);
        if !self.epp_live() {
            return self.time_out();
        }
        match self.decode(addr) {
            Some((i, off)) => {
                let enabled = self.enabled(&self.boards[i]);
                self.boards[i].read(off, enabled)
            }
            None => self.time_out(),
        }
    }

    fn data_write(&mut self, v: u8) {
        let addr = self.address;
        self.address = addr.wrapping_add(1);
        if !self.epp_live() {
            self.time_out();
            return;
        }
        match self.decode(addr) {
            Some((i, off)) => {
                if self.boards[i].write(off, v) {
                    let now = self.timebase();
                    for c in self.boards.iter_mut().filter_map(|b| b.counters.as_mut()) {
                        c.latch(now);
                    }
                }
            }
            None => {
                self.time_out();
            }
        }
    }

    fn time_out(&mut self) -> u8 {
        self.timeout = true;
        self.timeouts += 1;
        0xFF
    }

    fn status(&self) -> u8 {
        0x78 | port::STATUS_UNUSED & !1 | u8::from(self.timeout)
    }
}

impl BoardModel for PpmcPort {
    fn advance(&mut self, dt_ns: u64) {
        let dt = dt_ns as f64 * 1e-9;
        let t0 = self.now_ns;
        let mut m = 0;
        for i in 0..self.boards.len() {
            let b = &self.boards[i];
            let on = self.enabled(b);
            for c in 0..4 {
                // The servos' drive (volts or duty), the steppers' rate.
                let rate = match b.id.kind {
                    Kind::Dac => b.dac_volts(c),
                    Kind::Usc => b.step_rate(c, on),
                    Kind::Upc => b.pwm_duty(c, on),
                    _ => continue,
                };
                if let Some(r) = self.rates.get_mut(m) {
                    *r = rate;
                }
                m += 1;
            }
        }
        let last_count_ns = &mut self.last_count_ns;
        let servos = &mut self.servos;
        for (m, (p, v)) in self.motors.iter_mut().zip(&self.rates).enumerate() {
            let p0 = *p;
            let p1 = match servos.get_mut(m) {
                Some(Some(motor)) => {
                    motor.set_position(p0);
                    motor.set_volts(*v);
                    motor.advance(dt_ns);
                    motor.position()
                }
                _ => p0 + v * dt,
            };
            // When the last whole count was crossed in this step.
            let k = if p1 > p0 {
                p1.floor()
            } else {
                p1.floor() + 1.0
            };
            let frac = if p1 != p0 {
                ((k - p0) / (p1 - p0)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            last_count_ns[m] = t0 + (frac * dt_ns as f64) as u64;
            *p = p1;
        }
        self.now_ns = t0 + dt_ns;
        let mut e = 0;
        let motors = &self.motors;
        let last_count_ns = &self.last_count_ns;
        for c in self.boards.iter_mut().filter_map(|b| b.counters.as_mut()) {
            for ch in 0..4 {
                if let Some(&p) = motors.get(e) {
                    c.follow(ch, p.floor() as i64, (last_count_ns[e] / 1000) as u16);
                }
                e += 1;
            }
        }
    }

    fn describe(&self) -> String {
        format!("simulated Pico EPP bus at {:#x}", self.base)
    }
}

impl PortModel for PpmcPort {
    fn read(&mut self, at: u16, width: Width) -> u32 {
        let off = at.wrapping_sub(self.base);
        if at == self.base_hi.wrapping_add(port::ECR) {
            return self.ecr as u32;
        }
        match (off, width) {
            (port::DATA, _) => self.spp_data as u32,
            (port::STATUS, _) => self.status() as u32,
            (port::CONTROL, _) => self.control as u32,
            (port::EPP_ADDR, _) => self.address as u32,
            (4, Width::Byte) => self.data_read() as u32,
            (4, Width::Word) => u16::from_le_bytes([self.data_read(), self.data_read()]) as u32,
            (4, Width::Long) => u32::from_le_bytes([
                self.data_read(),
                self.data_read(),
                self.data_read(),
                self.data_read(),
            ]),
            (5..=7, _) => self.data_read() as u32,
            _ => u32::MAX,
        }
    }

    fn write(&mut self, at: u16, width: Width, value: u32) {
        if at == self.base_hi.wrapping_add(port::ECR) {
            self.ecr = value as u8;
            return;
        }
        let v = value as u8;
        match at.wrapping_sub(self.base) {
            port::DATA => self.spp_data = v,
            // Writing the timeout bit as 1 clears it.
            port::STATUS if v & 1 != 0 => self.timeout = false,
            port::CONTROL => self.control = v,
            port::EPP_ADDR => {
                if self.epp_live() {
                    self.address = v;
                } else {
                    self.time_out();
                }
            }
            4 => {
                let n = match width {
                    Width::Byte => 1,
                    Width::Word => 2,
                    Width::Long => 4,
                };
                for b in value.to_le_bytes().iter().take(n) {
                    self.data_write(*b);
                }
            }
            5..=7 => self.data_write(v),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests;
