//! A register model of the MCP23017 (hardware.md 7.2): the register file
//! in both maps (IOCON.BANK), sequential addressing (IOCON.SEQOP), the
//! pins (direction, input polarity, pull-ups, output latches), and
//! interrupt-on-change (INTF, INTCAP, cleared by reading GPIO or INTCAP).
//!
//! The outside world drives input pins through [`Mcp23017::set_input`];
//! a pin nobody drives reads 1 with its pull-up on and 0 without.

use std::any::Any;

use super::ChipModel;
use crate::regs::mcp23017::*;

/// The chip.
#[derive(Debug, Clone)]
pub struct Mcp23017 {
    /// Registers by their BANK = 0 address.
    regs: [u8; REGISTERS as usize],
    /// The address pointer, in the current map.
    pointer: u8,
    /// Levels the outside drives, pin n on bit n.
    driven: u16,
    /// Pins the outside drives at all.
    connected: u16,
    /// Pin levels at the last interrupt evaluation.
    last_pins: u16,
}

impl Default for Mcp23017 {
    fn default() -> Self {
        Self::new()
    }
}

fn word(lo: u8, hi: u8) -> u16 {
    lo as u16 | (hi as u16) << 8
}

impl Mcp23017 {
    /// A chip at power-up: all pins inputs, nothing connected.
    pub fn new() -> Mcp23017 {
        let mut regs = [0u8; REGISTERS as usize];
        regs[IODIRA as usize] = 0xFF;
        regs[IODIRB as usize] = 0xFF;
        Mcp23017 {
            regs,
            pointer: 0,
            driven: 0,
            connected: 0,
            last_pins: 0,
        }
    }

    fn pair(&self, a_reg: u8) -> u16 {
        word(self.regs[a_reg as usize], self.regs[a_reg as usize + 1])
    }

    /// A register's value by its BANK = 0 address.
    pub fn reg(&self, r: u8) -> u8 {
        self.regs[r as usize]
    }

    /// IODIR of both ports (1 = input), A on bits 0..7.
    pub fn iodir(&self) -> u16 {
        self.pair(IODIRA)
    }

    /// The output latches, A on bits 0..7.
    pub fn olat(&self) -> u16 {
        self.pair(OLATA)
    }

    /// The pull-ups.
    pub fn gppu(&self) -> u16 {
        self.pair(GPPUA)
    }

    /// IOCON.
    pub fn iocon(&self) -> u8 {
        self.regs[IOCON as usize]
    }

    /// Whether the chip drives pin `n` (it is an output).
    pub fn is_output(&self, n: u8) -> bool {
        self.iodir() & (1 << n) == 0
    }

    /// The electrical level of every pin: outputs their latch, inputs what
    /// the outside drives or their pull.
    pub fn pins(&self) -> u16 {
        let dir = self.iodir();
        let inputs = (self.driven & self.connected) | (self.gppu() & !self.connected);
        (self.olat() & !dir) | (inputs & dir)
    }

    /// The outside drives pin `n` at `level`.
    pub fn set_input(&mut self, n: u8, level: bool) {
        let bit = 1u16 << n;
        self.connected |= bit;
        if level {
            self.driven |= bit;
        } else {
            self.driven &= !bit;
        }
        self.evaluate_interrupts();
    }

    /// The outside lets pin `n` float.
    pub fn release(&mut self, n: u8) {
        self.connected &= !(1 << n);
        self.evaluate_interrupts();
    }

    /// Whether INTA (port A; both ports with MIRROR) is asserted.
    pub fn int_a(&self) -> bool {
        let f = self.pair(INTFA);
        if self.iocon() & IOCON_MIRROR != 0 {
            f != 0
        } else {
            f & 0xFF != 0
        }
    }

    /// A power cycle: every register back to its power-up value, the
    /// outside world unchanged.
    pub fn power_cycle(&mut self) {
        let (driven, connected) = (self.driven, self.connected);
        *self = Mcp23017::new();
        self.driven = driven;
        self.connected = connected;
        self.last_pins = self.pins();
    }

    fn bank(&self) -> bool {
        self.iocon() & IOCON_BANK != 0
    }

    /// The BANK = 0 address of `addr` in the current map.
    fn canonical(&self, addr: u8) -> Option<u8> {
        if self.bank() {
            let (port, kind) = (addr >> 4, addr & 0x0F);
            (port < 2 && kind <= 0x0A).then_some(kind * 2 + port)
        } else {
            (addr < REGISTERS).then_some(addr)
        }
    }

    fn next(&self, p: u8) -> u8 {
        if self.iocon() & IOCON_SEQOP != 0 {
            return p;
        }
        if self.bank() {
            let (port, kind) = (p >> 4, p & 0x0F);
            if kind >= 0x0A {
                port << 4
            } else {
                p + 1
            }
        } else if p + 1 >= REGISTERS {
            0
        } else {
            p + 1
        }
    }

    /// Sets the flags of enabled inputs that changed (or differ from
    /// DEFVAL), capturing the port on its first flag.
    fn evaluate_interrupts(&mut self) {
        let pins = self.pins();
        let en = self.pair(GPINTENA) & self.iodir();
        let against =
            (self.pair(INTCONA) & self.pair(DEFVALA)) | (!self.pair(INTCONA) & self.last_pins);
        let fire = en & (pins ^ against);
        let before = self.pair(INTFA);
        for port in 0..2u8 {
            let bits = ((fire >> (8 * port)) & 0xFF) as u8;
            if bits != 0 && (before >> (8 * port)) & 0xFF == 0 {
                self.regs[(INTCAPA + port) as usize] = (pins >> (8 * port)) as u8;
            }
            self.regs[(INTFA + port) as usize] |= bits;
        }
        self.last_pins = pins;
    }

    fn write_reg(&mut self, r: u8, v: u8) {
        match r {
            IOCON | IOCON_B => {
                self.regs[IOCON as usize] = v;
                self.regs[IOCON_B as usize] = v;
            }
            GPIOA | GPIOB => self.regs[(r + 2) as usize] = v,
            INTFA | INTFB | INTCAPA | INTCAPB => {}
            _ => self.regs[r as usize] = v,
        }
        self.evaluate_interrupts();
    }

    fn read_reg(&mut self, r: u8) -> u8 {
        match r {
            GPIOA | GPIOB => {
                let port = r - GPIOA;
                let pol = self.regs[(IPOLA + port) as usize];
                let dir = self.regs[(IODIRA + port) as usize];
                let level = (self.pins() >> (8 * port)) as u8;
                self.regs[(INTFA + port) as usize] = 0;
                level ^ (pol & dir)
            }
            INTCAPA | INTCAPB => {
                self.regs[(INTFA + r - INTCAPA) as usize] = 0;
                self.regs[r as usize]
            }
            _ => self.regs[r as usize],
        }
    }
}

impl ChipModel for Mcp23017 {
    fn write(&mut self, bytes: &[u8]) {
        let Some((&p, data)) = bytes.split_first() else {
            return;
        };
        self.pointer = p;
        for &b in data {
            if let Some(r) = self.canonical(self.pointer) {
                self.write_reg(r, b);
            }
            self.pointer = self.next(self.pointer);
        }
    }

    fn read(&mut self, out: &mut [u8]) {
        for b in out {
            *b = match self.canonical(self.pointer) {
                Some(r) => self.read_reg(r),
                None => 0,
            };
            self.pointer = self.next(self.pointer);
        }
    }

    fn describe(&self) -> String {
        "simulated MCP23017".into()
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(c: &mut Mcp23017, reg: u8, n: usize) -> Vec<u8> {
        c.write(&[reg]);
        let mut out = vec![0; n];
        c.read(&mut out);
        out
    }

    #[test]
    fn pins_direction_pullups_polarity() {
        let mut c = Mcp23017::new();
        assert_eq!(c.iodir(), 0xFFFF);
        assert_eq!(read(&mut c, GPIOA, 2), [0, 0], "floating, no pull-ups");
        c.write(&[GPPUA, 0x0F, 0x01]);
        assert_eq!(read(&mut c, GPIOA, 2), [0x0F, 0x01], "pull-ups, sequential");
        c.set_input(0, false);
        c.set_input(9, true);
        assert_eq!(read(&mut c, GPIOA, 2), [0x0E, 0x03]);
        c.write(&[IPOLA, 0x01]);
        assert_eq!(read(&mut c, GPIOA, 1), [0x0F], "polarity inverts inputs");
        // Port B low nibble outputs: they read their latch.
        c.write(&[OLATB, 0x05]);
        c.write(&[IODIRB, 0xF0]);
        assert_eq!(read(&mut c, GPIOB, 1), [0x05]);
        assert!(c.is_output(8) && !c.is_output(12));
        c.write(&[GPIOB, 0x0A]);
        assert_eq!(c.olat() >> 8, 0x0A, "a GPIO write goes to OLAT");
        assert_eq!(c.pins() >> 8 & 0x0F, 0x0A);
    }

    #[test]
    fn bank1_seqop_and_the_bank_switch_address() {
        let mut c = Mcp23017::new();
        c.write(&[IOCON, IOCON_BANK]);
        // Under BANK = 1, 0x05 is IOCON and 0x10 IODIRB.
        c.write(&[0x10, 0x00]);
        assert_eq!(c.iodir(), 0x00FF);
        c.write(&[IOCON_IN_BANK1, 0x00]);
        assert!(!c.bank(), "back to BANK = 0");
        c.write(&[IOCON, IOCON_SEQOP]);
        c.write(&[OLATA, 1, 2]);
        assert_eq!(c.olat(), 0x0002, "no increment: both bytes to OLATA");
    }

    #[test]
    fn interrupt_on_change_captures_and_clears_on_read() {
        let mut c = Mcp23017::new();
        c.set_input(2, false);
        c.write(&[GPINTENA, 0x04]);
        assert!(!c.int_a());
        c.set_input(2, true);
        assert!(c.int_a());
        assert_eq!(c.reg(INTFA), 0x04);
        assert_eq!(c.reg(INTCAPA), 0x04);
        c.set_input(2, false);
        assert_eq!(c.reg(INTCAPA), 0x04, "capture holds the first change");
        assert_eq!(read(&mut c, INTCAPA, 1), [0x04]);
        assert!(!c.int_a(), "reading INTCAP clears");
        // Compare with DEFVAL: fires while different.
        c.write(&[DEFVALA, 0x04]);
        c.write(&[INTCONA, 0x04]);
        assert!(c.int_a());
        read(&mut c, GPIOA, 1);
        assert!(!c.int_a());
        c.power_cycle();
        assert_eq!(c.iodir(), 0xFFFF);
        assert_eq!(c.reg(GPINTENA), 0);
    }
}
