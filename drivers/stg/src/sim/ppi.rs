//! An 8255 programmable peripheral interface in mode 0: three 8-bit
//! ports, each (port C by nibble) an input or a latched output.

/// One chip.
#[derive(Debug, Clone)]
pub struct Ppi {
    control: u8,
    latch: [u8; 3],
}

impl Default for Ppi {
    /// After reset every port is an input.
    fn default() -> Ppi {
        Ppi {
            control: 0x9B,
            latch: [0; 3],
        }
    }
}

impl Ppi {
    /// Which bits of port `p` (0 = A, 1 = B, 2 = C) are inputs.
    pub fn input_mask(&self, p: usize) -> u8 {
        let c = self.control;
        match p {
            0 => {
                if c & 0x10 != 0 {
                    0xFF
                } else {
                    0
                }
            }
            1 => {
                if c & 0x02 != 0 {
                    0xFF
                } else {
                    0
                }
            }
            _ => (if c & 0x08 != 0 { 0xF0 } else { 0 }) | (if c & 0x01 != 0 { 0x0F } else { 0 }),
        }
    }

    /// A write to the control register: a mode set (bit 7; it clears
    /// every output latch) or a port C bit set/reset.
    pub fn write_control(&mut self, v: u8) {
        if v & 0x80 != 0 {
            self.control = v;
            self.latch = [0; 3];
        } else {
            let bit = 1 << ((v >> 1) & 7);
            if v & 1 != 0 {
                self.latch[2] |= bit;
            } else {
                self.latch[2] &= !bit;
            }
        }
    }

    /// A read of port `p` with `outside` on its input lines.
    pub fn read(&self, p: usize, outside: u8) -> u8 {
        let m = self.input_mask(p);
        (outside & m) | (self.latch[p] & !m)
    }

    /// A write to port `p`'s latch.
    pub fn write(&mut self, p: usize, v: u8) {
        self.latch[p] = v;
    }

    /// What the chip drives on port `p`'s output bits (the input bits
    /// read as 0), and which bits those are.
    pub fn driven(&self, p: usize) -> (u8, u8) {
        let out = !self.input_mask(p);
        (self.latch[p] & out, out)
    }

    /// Port `p`'s output latch, whatever the direction.
    pub fn latch(&self, p: usize) -> u8 {
        self.latch[p]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_set_directions_and_clears_latches() {
        let mut p = Ppi::default();
        assert_eq!(
            (p.input_mask(0), p.input_mask(1), p.input_mask(2)),
            (0xFF, 0xFF, 0xFF)
        );
        p.write_control(0x92); // A in, B in, C out
        p.write(2, 0xA5);
        assert_eq!(p.read(2, 0x00), 0xA5);
        assert_eq!(p.read(0, 0x3C), 0x3C);
        assert_eq!(p.driven(2), (0xA5, 0xFF));
        p.write_control(0x0F); // set PC7
        p.write_control(0x04); // reset PC2
        assert_eq!(p.latch(2), 0xA1);
        p.write_control(0x89); // C in, A and B out: latches cleared
        assert_eq!(p.latch(2), 0);
        assert_eq!(p.read(2, 0x77), 0x77);
        assert_eq!(p.driven(0), (0, 0xFF));
    }
}
