//! Simulated IOPort: the port registers and how each pin's level comes
//! out of the latch, the alternate source, open drain, inversion and the
//! outside world (hardware.md 5.9.1).

use crate::regs::ioport as r;

/// One connector's registers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PortRegs {
    /// Output latch.
    pub data: u32,
    /// Data direction.
    pub ddr: u32,
    /// Alternate source.
    pub alt: u32,
    /// Open drain.
    pub od: u32,
    /// Output invert.
    pub inv: u32,
}

/// The IOPort registers of every connector.
#[derive(Debug, Clone, Default)]
pub struct SimIoPort {
    /// Per connector.
    pub ports: Vec<PortRegs>,
    /// Pins per connector.
    pub width: u32,
}

impl SimIoPort {
    /// `ports` connectors of `width` pins.
    pub fn new(ports: usize, width: u32) -> SimIoPort {
        SimIoPort {
            ports: vec![PortRegs::default(); ports],
            width,
        }
    }

    /// A register write.
    pub fn write(&mut self, reg: usize, port: usize, v: u32) {
        let Some(p) = self.ports.get_mut(port) else {
            return;
        };
        match reg {
            r::DATA => p.data = v,
            r::DDR => p.ddr = v,
            r::ALT_SOURCE => p.alt = v,
            r::OPEN_DRAIN => p.od = v,
            r::OUTPUT_INVERT => p.inv = v,
            _ => {}
        }
    }

    /// A register read (Data reads the pin levels, which the caller
    /// supplies).
    pub fn read(&self, reg: usize, port: usize, levels: u32) -> u32 {
        let Some(p) = self.ports.get(port) else {
            return 0;
        };
        match reg {
            r::DATA => levels,
            r::DDR => p.ddr,
            r::ALT_SOURCE => p.alt,
            r::OPEN_DRAIN => p.od,
            r::OUTPUT_INVERT => p.inv,
            _ => 0,
        }
    }

    fn at(&self, io: usize) -> Option<(&PortRegs, u32)> {
        let w = self.width.max(1) as usize;
        self.ports.get(io / w).map(|p| (p, 1u32 << (io % w)))
    }

    /// Whether the pin is switched to its module.
    pub fn alt(&self, io: usize) -> bool {
        self.at(io).is_some_and(|(p, b)| p.alt & b != 0)
    }

    /// What the board drives on pin `io` given its module's output:
    /// `Some(level)` when it drives, `None` when the pin is an input or an
    /// open drain released high.
    pub fn driven(&self, io: usize, module_out: bool) -> Option<bool> {
        let (p, b) = self.at(io)?;
        let source = if p.alt & b != 0 {
            module_out
        } else {
            p.data & b != 0
        };
        let level = source != (p.inv & b != 0);
        if p.od & b != 0 {
            (!level).then_some(false)
        } else if p.ddr & b != 0 {
            Some(level)
        } else {
            None
        }
    }

    /// Whether a module output reaches the connector through pin `io`.
    pub fn module_drives(&self, io: usize) -> bool {
        self.at(io)
            .is_some_and(|(p, b)| p.alt & b != 0 && (p.ddr | p.od) & b != 0)
    }

    /// A watchdog bite: every pin an input, no open drain.
    pub fn release_all(&mut self) {
        for p in &mut self.ports {
            p.ddr = 0;
            p.od = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pin_levels_follow_the_registers() {
        let mut io = SimIoPort::new(1, 8);
        assert_eq!(io.driven(0, false), None, "input by default");
        io.write(r::DDR, 0, 0b11);
        io.write(r::DATA, 0, 0b01);
        assert_eq!(io.driven(0, false), Some(true));
        assert_eq!(io.driven(1, false), Some(false));
        io.write(r::OUTPUT_INVERT, 0, 0b01);
        assert_eq!(io.driven(0, false), Some(false), "inverted");
        io.write(r::ALT_SOURCE, 0, 0b10);
        assert_eq!(io.driven(1, true), Some(true), "module drives");
        assert!(io.module_drives(1));
        io.write(r::OPEN_DRAIN, 0, 0b100);
        io.write(r::DATA, 0, 0b101);
        assert_eq!(io.driven(2, false), None, "open drain released");
        io.write(r::DATA, 0, 0b001);
        assert_eq!(io.driven(2, false), Some(false), "open drain pulls low");
        io.release_all();
        assert_eq!(io.driven(0, false), None);
        assert!(!io.module_drives(1));
        assert_eq!(io.driven(20, false), None, "no such pin");
    }
}
