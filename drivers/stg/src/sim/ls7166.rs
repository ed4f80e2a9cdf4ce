//! An LS7166 24-bit quadrature counter (hardware.md §3.4), counting a
//! shaft's quadrature count.

use crate::regs::COUNTER_BITS;

const MASK: u32 = (1 << COUNTER_BITS) - 1;

/// One counter chip.
#[derive(Debug, Clone, Default)]
pub struct Ls7166 {
    /// CNTR at the shaft count `origin`.
    at_origin: u32,
    origin: i64,
    /// Shaft counts per CNTR count (4 = x1, 2 = x2, 1 = x4), 0 when the
    /// quadrature register selects non-quadrature (not modelled: no
    /// count).
    divisor: i64,
    /// ICR bit 3: A/B inputs enabled.
    enabled: bool,
    /// ICR bit 5: the load pin (the index) loads OL.
    index_loads_ol: bool,
    /// Output latch.
    ol: u32,
    /// Preset register.
    pr: u32,
    /// Byte pointer of OL reads and PR writes (0..2).
    pointer: u8,
    occr: u8,
}

impl Ls7166 {
    /// CNTR when the shaft is at `shaft`.
    pub fn cntr(&self, shaft: i64) -> u32 {
        if !self.enabled || self.divisor == 0 {
            return self.at_origin;
        }
        let moved = (shaft - self.origin).div_euclid(self.divisor);
        (self.at_origin as i64).wrapping_add(moved) as u32 & MASK
    }

    /// The output latch.
    pub fn ol(&self) -> u32 {
        self.ol
    }

    /// Whether the index loads OL.
    pub fn index_loads_ol(&self) -> bool {
        self.index_loads_ol
    }

    /// Sets CNTR to `value` with the shaft at `shaft`.
    fn load(&mut self, value: u32, shaft: i64) {
        self.at_origin = value & MASK;
        self.origin = shaft;
    }

    /// Keeps CNTR where it is while the counting mode changes.
    fn rebase(&mut self, shaft: i64) {
        let now = self.cntr(shaft);
        self.load(now, shaft);
    }

    /// A byte written to the control port, the shaft at `shaft`.
    pub fn command(&mut self, byte: u8, shaft: i64) {
        match byte >> 6 {
            0 => {
                // MCR, in the order the bits take effect.
                if byte & 0x20 != 0 {
                    *self = Ls7166::default();
                    self.origin = shaft;
                }
                if byte & 0x10 != 0 {
                    self.load(self.pr, shaft);
                }
                if byte & 0x04 != 0 {
                    self.load(0, shaft);
                }
                if byte & 0x02 != 0 {
                    self.ol = self.cntr(shaft);
                }
                if byte & 0x01 != 0 {
                    self.pointer = 0;
                }
            }
            1 => {
                self.rebase(shaft);
                self.enabled = byte & 0x08 != 0;
                self.index_loads_ol = byte & 0x20 != 0;
            }
            2 => self.occr = byte,
            _ => {
                self.rebase(shaft);
                self.divisor = match byte & 3 {
                    0 => 0,
                    1 => 4,
                    2 => 2,
                    _ => 1,
                };
            }
        }
    }

    /// A read of the data port: the OL byte at the pointer.
    pub fn read_data(&mut self) -> u8 {
        let b = (self.ol >> (8 * self.pointer)) as u8;
        self.pointer = (self.pointer + 1) % 3;
        b
    }

    /// A write to the data port: the PR byte at the pointer.
    pub fn write_data(&mut self, byte: u8) {
        let shift = 8 * self.pointer;
        self.pr = (self.pr & !(0xFF << shift)) | (byte as u32) << shift;
        self.pointer = (self.pointer + 1) % 3;
    }

    /// The load pin fired with the shaft at `shaft`.
    pub fn index(&mut self, shaft: i64) {
        if self.index_loads_ol {
            self.ol = self.cntr(shaft);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regs;

    fn initialised(shaft: i64) -> Ls7166 {
        let mut c = Ls7166::default();
        for b in [
            regs::LS_RESET,
            regs::LS_ICR_INDEX_LOADS_OL,
            regs::LS_OCCR_DEFAULT,
            regs::LS_QR_X4,
        ] {
            c.command(b, shaft);
        }
        c
    }

    fn latch_and_read(c: &mut Ls7166, shaft: i64) -> u32 {
        c.command(regs::LS_LATCH, shaft);
        (0..3).fold(0, |v, i| v | (c.read_data() as u32) << (8 * i))
    }

    #[test]
    fn counts_x4_from_reset_and_wraps_at_24_bits() {
        let mut c = initialised(1000);
        assert_eq!(latch_and_read(&mut c, 1000), 0);
        assert_eq!(latch_and_read(&mut c, 1250), 250);
        assert_eq!(latch_and_read(&mut c, 999), 0xFF_FFFF, "-1 in 24 bits");
        assert_eq!(latch_and_read(&mut c, 1000 + (1 << 24) + 5), 5);
    }

    #[test]
    fn other_modes_and_disabled_inputs() {
        let mut c = initialised(0);
        c.command(0xC1, 400); // x1
        assert_eq!(c.cntr(800), 500, "400 at x4, then 400 shaft counts = 100");
        c.command(0xC2, 800); // x2
        assert_eq!(c.cntr(802), 501);
        c.command(0x40, 802); // ICR: A/B disabled
        assert_eq!(c.cntr(5000), 501);
    }

    #[test]
    fn pointer_walks_the_latch_and_preset_loads() {
        let mut c = initialised(0);
        for b in [0x56, 0x34, 0x12] {
            c.write_data(b);
        }
        c.command(0x10 | 0x01, 10); // PR -> CNTR, pointer reset
        assert_eq!(latch_and_read(&mut c, 10), 0x12_3456);
        c.command(regs::LS_RESET_POINTER, 10);
        assert_eq!(c.read_data(), 0x56, "re-read from the first byte");
    }

    #[test]
    fn index_loads_the_latch_when_so_configured() {
        let mut c = initialised(0);
        c.index(4000);
        assert_eq!(c.ol(), 4000);
        c.command(0x48, 5000); // ICR without the load function
        c.index(6000);
        assert_eq!(c.ol(), 4000);
    }
}
