//! A simulated parallel port in EPP mode with a HostMot2 board behind it
//! (the 7I43 and 7I90 as `hm2_7i43` and `hm2_7i90` reach them), on the
//! shared driver layer's port bus: the driver cannot tell it from a real
//! port reached with `inb`/`outb`.
//!
//! The port decodes its eight registers at `base` and the ECP extended
//! control register at `base_hi + 2` ([`crate::epp`] has the map). An EPP
//! cycle reaches the board only while the ECR selects EPP mode and the
//! cable is connected ([`EppPortModel::connected`]); otherwise the cycle
//! times out: the status register's bit 0 goes high, reads give 0xFF,
//! writes are lost, and every further cycle fails the same way until the
//! driver clears the bit (writing it as 1, as many port chips want).
//!
//! The board's EPP interface, as the 7I43's firmware has it: each byte
//! written to the address register shifts into a 16-bit address latch
//! from the top (two writes, low byte then high, load an address); bit
//! 15 asks for auto-increment, bits 14..0 are the byte address. A data
//! cycle moves one byte of the 32-bit register at the address: reading
//! byte 0 latches the whole register (so its read side effects happen
//! once), writing byte 3 stores the four bytes written. A 32-bit port
//! access at `base + 4` is four data cycles, as the port chip makes it.
//!
//! The firmware presets [`preset`] knows:
//!
//! | name | board | connectors | firmware |
//! |---|---|---|---|
//! | `7i43`, `7i43-2` | 7I43-4 (400k gates), 7I43-2 (200k) | P4, P3 × 24 | P4: 4 encoders (A, B, index), 4 PWM generators (PWM, dir, /enable); P3: 4 step generators (step/dir), 16 GPIO; watchdog, 8 LEDs; ClockLow 50 MHz, ClockHigh 100 MHz |
//! | `7i90` | 7I90HD | P1, P2, P3 × 24 | P1: 5 step generators, 14 GPIO; P2: 4 encoders, 4 PWM generators; P3: 24 GPIO; watchdog, 2 LEDs; 100 / 200 MHz |

use std::sync::Arc;

use hal_driver::sim::{BoardModel, PortModel, Width};

use super::boards::{firmware, Identity};
use super::cpld::SimCpld;
use super::SimHm2;
use crate::epp::{self, cpld, ecr, reg};
use crate::image::{gpio, pd, FirmwareSpec, ModuleSpec};
use crate::regs::gtag;

/// The EPP board presets `sim=` takes.
pub const EPP_PRESETS: &[&str] = &["7i43", "7i43-2", "7i90"];

/// A parallel port in EPP mode with a HostMot2 board on its cable.
pub struct EppPortModel {
    base: u16,
    base_hi: u16,
    /// The design that answers the port (`None`: none runs).
    board: Option<Arc<SimHm2>>,
    /// The 7I43's CPLD, on a card that loads its FPGA from the port.
    cpld: Option<SimCpld>,
    spp_data: u8,
    control: u8,
    ecr: u8,
    timeout: bool,
    address: u16,
    read_latch: u32,
    write_latch: [u8; 4],
    /// Whether the cable is plugged in (false: every EPP cycle times out).
    pub connected: bool,
    /// EPP data cycles that reached the board.
    pub data_cycles: u64,
    /// EPP address cycles that reached the board.
    pub address_cycles: u64,
    /// Cycles that timed out.
    pub timeouts: u64,
}

impl std::fmt::Debug for EppPortModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&BoardModel::describe(self))
    }
}

impl EppPortModel {
    /// A port at `base` (ECR at `base_hi + 2`) with `board` behind it.
    pub fn new(base: u16, base_hi: u16, board: Arc<SimHm2>) -> EppPortModel {
        EppPortModel {
            base,
            base_hi,
            board: Some(board),
            cpld: None,
            spp_data: 0,
            control: 0,
            // A PC's port comes up in plain (SPP) mode.
            ecr: ecr::SPP,
            timeout: false,
            address: 0,
            read_latch: 0,
            write_latch: [0; 4],
            connected: true,
            data_cycles: 0,
            address_cycles: 0,
            timeouts: 0,
        }
    }

    /// A 7I43 with FPGA `part` and its CPLD: the design given to
    /// [`new`](Self::new) runs as if loaded from the card's EEPROM until
    /// the driver writes the release key; then the CPLD answers and takes
    /// a bitstream ([`crate::sim::cpld`]).
    pub fn with_cpld(mut self, part: &str) -> EppPortModel {
        self.cpld = Some(SimCpld::new(part, self.board.is_some()));
        self
    }

    /// The design behind the port, if one runs.
    pub fn board(&self) -> Option<&Arc<SimHm2>> {
        self.board.as_ref()
    }

    /// The design the FPGA was loaded with through the CPLD, once DONE.
    pub fn loaded_design(&self) -> Option<String> {
        let cpld = self.cpld.as_ref()?;
        (!cpld.answers()).then(|| cpld.design().map(str::to_string))?
    }

    /// Puts the simulator's HostMot2 for the loaded design behind the
    /// port.
    pub fn install(&mut self, board: Arc<SimHm2>) {
        self.board = Some(board);
    }

    /// The CPLD, while it answers the port.
    fn answering_cpld(&mut self) -> Option<&mut SimCpld> {
        self.cpld.as_mut().filter(|c| c.answers())
    }

    /// The address latch (bit 15: auto-increment).
    pub fn address(&self) -> u16 {
        self.address
    }

    /// Whether the status register shows an EPP timeout.
    pub fn timed_out(&self) -> bool {
        self.timeout
    }

    /// Whether an EPP cycle can happen now; a cycle that cannot times out.
    fn cycle_ok(&mut self) -> bool {
        let epp_mode = self.ecr & ecr::MODE_MASK == ecr::EPP & ecr::MODE_MASK;
        if self.timeout || !self.connected || !epp_mode {
            if !self.timeout {
                self.timeouts += 1;
            }
            self.timeout = true;
            return false;
        }
        true
    }

    /// The byte address a data cycle reaches, stepping the latch on.
    fn data_address(&mut self) -> u16 {
        let at = self.address & epp::ADDRESS_MASK;
        if self.address & epp::AUTO_INCREMENT != 0 {
            self.address = epp::AUTO_INCREMENT | (at.wrapping_add(1) & epp::ADDRESS_MASK);
        }
        at
    }

    /// The board a HostMot2 cycle reaches; without one (no design runs
    /// and no CPLD answers) the cycle times out.
    fn design_or_timeout(&mut self) -> Option<Arc<SimHm2>> {
        let board = self.board.clone();
        if board.is_none() {
            self.timeouts += 1;
            self.timeout = true;
        }
        board
    }

    fn read_data(&mut self) -> u8 {
        if !self.cycle_ok() {
            return 0xFF;
        }
        self.data_cycles += 1;
        if let Some(cpld) = self.answering_cpld() {
            return cpld.read();
        }
        let Some(board) = self.design_or_timeout() else {
            return 0xFF;
        };
        let at = self.data_address();
        let lane = (at & 3) as usize;
        if lane == 0 {
            self.read_latch = hal_driver::bus::RegWindow::read32(&*board, (at & !3) as usize);
        }
        self.read_latch.to_le_bytes()[lane]
    }

    fn write_data(&mut self, v: u8) {
        if !self.cycle_ok() {
            return;
        }
        self.data_cycles += 1;
        if let Some(cpld) = self.answering_cpld() {
            cpld.write(v);
            return;
        }
        if let Some(cpld) = self.cpld.as_mut() {
            // Any design loaded through the CPLD watches for the key,
            // even one the simulator has not been given a model of.
            let at = self.address & epp::ADDRESS_MASK;
            if at == cpld::RELEASE_AT && v == cpld::RELEASE_KEY {
                cpld.take_port_back();
                self.board = None;
                self.data_address();
                return;
            }
        }
        let Some(board) = self.design_or_timeout() else {
            return;
        };
        let at = self.data_address();
        let lane = (at & 3) as usize;
        self.write_latch[lane] = v;
        if lane == 3 {
            let word = u32::from_le_bytes(self.write_latch);
            hal_driver::bus::RegWindow::write32(&*board, (at & !3) as usize, word);
        }
    }

    fn write_address(&mut self, v: u8) {
        if !self.cycle_ok() {
            return;
        }
        self.address_cycles += 1;
        if let Some(cpld) = self.answering_cpld() {
            cpld.address(v);
            return;
        }
        self.address = (self.address >> 8) | (v as u16) << 8;
    }

    fn inb(&mut self, port: u16) -> u8 {
        match port.wrapping_sub(self.base) {
            reg::DATA => self.spp_data,
            reg::STATUS => u8::from(self.timeout) | epp::STATUS_IDLE,
            reg::CONTROL => self.control,
            reg::EPP_ADDRESS => (self.address & 0xFF) as u8,
            reg::EPP_DATA..=reg::EPP_DATA_LAST => self.read_data(),
            _ if port == self.base_hi.wrapping_add(reg::ECR_HI) => self.ecr,
            _ => 0xFF,
        }
    }

    fn outb(&mut self, port: u16, v: u8) {
        match port.wrapping_sub(self.base) {
            reg::DATA => self.spp_data = v,
            // Writing the timeout bit as 1 clears it.
            reg::STATUS if v & epp::STATUS_TIMEOUT != 0 => self.timeout = false,
            reg::CONTROL => self.control = v,
            reg::EPP_ADDRESS => self.write_address(v),
            reg::EPP_DATA..=reg::EPP_DATA_LAST => self.write_data(v),
            _ if port == self.base_hi.wrapping_add(reg::ECR_HI) => self.ecr = v,
            _ => {}
        }
    }
}

/// Time belongs to the board behind the port (the driver's `read`
/// advances it), so the port's own clock moves nothing.
impl BoardModel for EppPortModel {
    fn describe(&self) -> String {
        let behind = match (&self.board, &self.cpld) {
            (Some(board), _) => hal_driver::bus::RegWindow::describe(&**board),
            (None, Some(_)) => "a 7I43 whose FPGA runs no design (its CPLD answers)".into(),
            (None, None) => "nothing answering".into(),
        };
        format!(
            "simulated parallel port at {:#x} (EPP) with {behind}",
            self.base
        )
    }
}

impl PortModel for EppPortModel {
    fn read(&mut self, port: u16, width: Width) -> u32 {
        // A wide access at the EPP data register is that many data
        // cycles; elsewhere the bytes of consecutive registers.
        let mut v = 0u32;
        for i in 0..width.bytes() {
            let p = if port.wrapping_sub(self.base) == reg::EPP_DATA {
                port
            } else {
                port.wrapping_add(i)
            };
            v |= (self.inb(p) as u32) << (8 * i);
        }
        v
    }

    fn write(&mut self, port: u16, width: Width, value: u32) {
        for i in 0..width.bytes() {
            let p = if port.wrapping_sub(self.base) == reg::EPP_DATA {
                port
            } else {
                port.wrapping_add(i)
            };
            self.outb(p, (value >> (8 * i)) as u8);
        }
    }
}

/// The firmware of a simulated EPP board, by name ([`EPP_PRESETS`]).
pub fn preset(name: &str) -> Option<FirmwareSpec> {
    match name {
        "7i43" => Some(seven_i43(cpld::PART_400K, 400)),
        "7i43-2" => Some(seven_i43(cpld::PART_200K, 200)),
        "7i90" => Some(seven_i90()),
        _ => None,
    }
}

/// The board type (`7i43`) of a simulated EPP board's name (`7i43-2`).
pub fn board_of(name: &str) -> Option<&'static str> {
    match name {
        "7i43" | "7i43-2" => Some("7i43"),
        "7i90" => Some("7i90"),
        _ => None,
    }
}

/// The FPGA part of a simulated 7I43 (`7i43`: the 400k-gate 7I43-4,
/// `7i43-2`: the 200k-gate one); `None` for other boards.
pub fn seven_i43_part(name: &str) -> Option<&'static str> {
    match name {
        "7i43" => Some(cpld::PART_400K),
        "7i43-2" => Some(cpld::PART_200K),
        _ => None,
    }
}

/// Encoder `k`'s A, B and index pins.
fn encoder_pins(k: u8) -> [crate::pins::PinDescriptor; 3] {
    [
        pd(gtag::ENCODER, k, 1),
        pd(gtag::ENCODER, k, 2),
        pd(gtag::ENCODER, k, 3),
    ]
}

/// PWM generator `k`'s PWM, direction and /enable pins.
fn pwm_pins(k: u8) -> [crate::pins::PinDescriptor; 3] {
    [
        pd(gtag::PWMGEN, k, 0x81),
        pd(gtag::PWMGEN, k, 0x82),
        pd(gtag::PWMGEN, k, 0x83),
    ]
}

/// 7I43 with FPGA `part` of `kgates`: servo I/O on P4, steppers and
/// GPIO on P3.
fn seven_i43(part: &'static str, kgates: u32) -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..4u8 {
        pins.extend(encoder_pins(k));
    }
    for k in 0..4u8 {
        pins.extend(pwm_pins(k));
    }
    for k in 0..4u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    pins.extend(std::iter::repeat_n(gpio(), 16));
    let mut fw = firmware(
        Identity {
            board: "7i43",
            idrom_name: "MESA7I43",
            fpga_part: part,
            fpga_size: kgates,
            fpga_pins: 144,
            connectors: &["P4", "P3"],
            port_width: 24,
            clock_low: 50_000_000,
        },
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 2),
            ModuleSpec::standard(gtag::ENCODER, 2, 4),
            ModuleSpec::standard(gtag::STEPGEN, 2, 4),
            ModuleSpec::standard(gtag::PWMGEN, 1, 4),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    );
    fw.clock_high = 100_000_000;
    fw.leds = 8;
    fw
}

/// 7I90HD: steppers on P1, servo I/O on P2, GPIO on P3.
fn seven_i90() -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..5u8 {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    pins.extend(std::iter::repeat_n(gpio(), 14));
    for k in 0..4u8 {
        pins.extend(encoder_pins(k));
    }
    for k in 0..4u8 {
        pins.extend(pwm_pins(k));
    }
    pins.extend(std::iter::repeat_n(gpio(), 24));
    firmware(
        Identity {
            board: "7i90",
            idrom_name: "MESA7I90",
            fpga_part: "6slx9tq144",
            fpga_size: 9,
            fpga_pins: 144,
            connectors: &["P1", "P2", "P3"],
            port_width: 24,
            clock_low: 100_000_000,
        },
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, 3),
            ModuleSpec::standard(gtag::ENCODER, 2, 4),
            ModuleSpec::standard(gtag::STEPGEN, 2, 5),
            ModuleSpec::standard(gtag::PWMGEN, 1, 4),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn port() -> EppPortModel {
        let (board, _) = crate::sim::board(
            preset("7i90").unwrap(),
            Box::new(super::super::machine::preset("7i90")),
        );
        let mut p = EppPortModel::new(0x278, 0x678, board);
        p.outb(0x67A, ecr::EPP);
        p
    }

    #[test]
    fn without_auto_increment_every_cycle_reaches_the_same_byte() {
        let mut p = port();
        // 0x0100 without bit 15: the cookie's low byte, again and again.
        p.outb(0x27B, 0x00);
        p.outb(0x27B, 0x01);
        assert_eq!(p.address(), 0x0100);
        assert_eq!(p.inb(0x27C), 0xFE);
        assert_eq!(p.inb(0x27C), 0xFE);
        // With it, the bytes in order; a 32-bit access is four cycles.
        p.outb(0x27B, 0x00);
        p.outb(0x27B, 0x81);
        assert_eq!(p.read(0x27C, Width::Long), 0x55AA_CAFE);
        assert_eq!(p.address(), 0x8104);
        assert!(!p.timed_out());
        assert_eq!(p.data_cycles, 6);
    }

    #[test]
    fn out_of_epp_mode_a_cycle_times_out_until_cleared() {
        let mut p = port();
        p.outb(0x67A, ecr::SPP);
        assert_eq!(p.inb(0x27C), 0xFF);
        assert!(p.timed_out());
        assert_eq!(p.inb(0x279) & epp::STATUS_TIMEOUT, 1);
        p.outb(0x67A, ecr::EPP);
        assert_eq!(p.inb(0x27C), 0xFF, "still timed out");
        p.outb(0x279, 0x00);
        assert!(p.timed_out(), "writing 0 does not clear it here");
        p.outb(0x279, 0x01);
        assert!(!p.timed_out());
        assert_eq!(p.timeouts, 1);
        // Nothing else decodes.
        assert_eq!(p.inb(0x300), 0xFF);
    }

    #[test]
    fn the_presets_fit_their_boards() {
        for (name, connectors) in [("7i43", 2), ("7i90", 3)] {
            let spec = preset(name).unwrap();
            assert_eq!(spec.pins.len(), 24 * connectors, "{name}");
            assert_eq!(spec.connectors.len(), connectors);
            assert_eq!(spec.port_width, 24);
        }
        assert!(preset("7i92").is_none());
    }
}
