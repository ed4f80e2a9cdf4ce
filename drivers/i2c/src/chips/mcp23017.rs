//! The MCP23017 driver: 16 digital inputs and outputs.
//!
//! Set-up: 0 to address 0x05 (IOCON if a previous user left the chip in
//! BANK = 1, a harmless GPINTENB otherwise), IOCON = 0 (BANK = 0,
//! sequential addressing), then with one word write each (A then B):
//! GPINTEN = 0, IPOL = 0, GPPU = the pull-ups, OLAT = the outputs' safe
//! levels, and last IODIR, so every output starts at its safe level.
//!
//! Each cycle: OLAT (one word) when the outputs changed, GPIO (one word
//! read: port A in bits 0..7, B in 8..15); every
//! [`CHECK_EVERY`](super::CHECK_EVERY) cycles IODIR is read back: a chip
//! whose directions are not the configured ones was reset.

use super::{CheckTimer, Chip, ChipFault, Command};
use crate::bus::I2cBus;
use crate::regs::mcp23017::*;

/// Output levels for the 16 pins (pin n on bit n; input pins ignored),
/// and their safe levels.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DioCmd {
    /// The levels to drive.
    pub out: u16,
    /// The safe levels (each output's `invert`).
    pub safe: u16,
}

impl Command for DioCmd {
    fn safe(&self) -> Self {
        DioCmd {
            out: self.safe,
            safe: self.safe,
        }
    }
}

/// One MCP23017.
#[derive(Debug, Clone)]
pub struct Mcp23017Chip {
    addr: u8,
    /// 1 = input.
    iodir: u16,
    pullup: u16,
    /// The latch as written; None when unknown.
    olat: Option<u16>,
    check: CheckTimer,
}

impl Mcp23017Chip {
    /// A chip at `addr` with directions `iodir` (1 = input) and pull-ups
    /// `pullup`.
    pub fn new(addr: u8, iodir: u16, pullup: u16) -> Mcp23017Chip {
        Mcp23017Chip {
            addr,
            iodir,
            pullup,
            olat: None,
            check: CheckTimer::default(),
        }
    }
}

impl Chip for Mcp23017Chip {
    type Cmd = DioCmd;
    type Sample = u16;

    fn address(&self) -> u8 {
        self.addr
    }

    fn init(&mut self, bus: &dyn I2cBus, safe: &DioCmd) -> Result<(), ChipFault> {
        let a = self.addr;
        self.olat = None;
        bus.write_byte_data(a, IOCON_IN_BANK1, 0)?;
        bus.write_byte_data(a, IOCON, 0)?;
        bus.write_word_data(a, GPINTENA, 0)?;
        bus.write_word_data(a, IPOLA, 0)?;
        bus.write_word_data(a, GPPUA, self.pullup)?;
        bus.write_word_data(a, OLATA, safe.out)?;
        self.olat = Some(safe.out);
        bus.write_word_data(a, IODIRA, self.iodir)?;
        self.check.restart();
        Ok(())
    }

    fn cycle(
        &mut self,
        bus: &dyn I2cBus,
        cmd: &DioCmd,
        _now_ns: u64,
        sample: &mut u16,
    ) -> Result<(), ChipFault> {
        if self.check.due() && bus.read_word_data(self.addr, IODIRA)? != self.iodir {
            return Err(ChipFault::LostConfig);
        }
        if self.olat != Some(cmd.out) {
            self.olat = None;
            bus.write_word_data(self.addr, OLATA, cmd.out)?;
            self.olat = Some(cmd.out);
        }
        *sample = bus.read_word_data(self.addr, GPIOA)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Kind, Mcp23017, SimBus};
    use hal_driver::sim::SimClock;
    use std::sync::Arc;

    fn rig() -> SimBus {
        let bus = SimBus::new("sim", Arc::new(SimClock::new(0, 0)));
        bus.add_chip(0x21, Box::new(Mcp23017::new()));
        bus
    }

    #[test]
    fn set_up_sequence_outputs_safe_before_they_are_outputs() {
        let bus = rig();
        let mut chip = Mcp23017Chip::new(0x21, 0xF0F0, 0x1010);
        chip.init(
            &bus,
            &DioCmd {
                out: 0x0F0F,
                safe: 0x0102,
            },
        )
        .unwrap();
        let t: Vec<_> = bus
            .transfers()
            .iter()
            .map(|t| (t.kind, t.reg, t.bytes().to_vec()))
            .collect();
        assert_eq!(
            t,
            vec![
                (Kind::WriteByte, 0x05, vec![0]),
                (Kind::WriteByte, IOCON, vec![0]),
                (Kind::WriteWord, GPINTENA, vec![0, 0]),
                (Kind::WriteWord, IPOLA, vec![0, 0]),
                (Kind::WriteWord, GPPUA, vec![0x10, 0x10]),
                (Kind::WriteWord, OLATA, vec![0x0F, 0x0F]),
                (Kind::WriteWord, IODIRA, vec![0xF0, 0xF0]),
            ]
        );
        bus.with_chip::<Mcp23017, _>(0x21, |c| {
            assert_eq!(c.iodir(), 0xF0F0);
            assert_eq!(c.gppu(), 0x1010);
            assert_eq!(c.pins() & 0x0F0F, 0x0F0F);
        });
    }

    #[test]
    fn a_chip_left_in_bank1_is_brought_back() {
        let bus = rig();
        bus.with_chip::<Mcp23017, _>(0x21, |c| {
            use crate::sim::ChipModel;
            c.write(&[IOCON, IOCON_BANK | IOCON_SEQOP]);
        });
        let mut chip = Mcp23017Chip::new(0x21, 0x00FF, 0);
        chip.init(&bus, &DioCmd::default()).unwrap();
        bus.with_chip::<Mcp23017, _>(0x21, |c| {
            assert_eq!(c.iocon(), 0);
            assert_eq!(c.iodir(), 0x00FF);
        });
    }

    #[test]
    fn cycles_write_on_change_read_inputs_and_check_the_directions() {
        let bus = rig();
        let mut chip = Mcp23017Chip::new(0x21, 0x00FF, 0x00FF);
        chip.init(&bus, &DioCmd::default()).unwrap();
        bus.with_chip::<Mcp23017, _>(0x21, |c| c.set_input(3, false));
        let mut sample = 0;
        let cmd = DioCmd {
            out: 0x8100,
            safe: 0,
        };
        bus.clear_log();
        chip.cycle(&bus, &cmd, 0, &mut sample).unwrap();
        let t = bus.transfers();
        assert_eq!(
            t.iter().map(|t| (t.kind, t.reg)).collect::<Vec<_>>(),
            vec![(Kind::WriteWord, OLATA), (Kind::ReadWord, GPIOA)]
        );
        assert_eq!(
            sample, 0x81F7,
            "outputs read back; input 3 low, others pulled up"
        );
        bus.clear_log();
        chip.cycle(&bus, &cmd, 0, &mut sample).unwrap();
        assert_eq!(bus.transfers().len(), 1, "only the input read");
        bus.with_chip::<Mcp23017, _>(0x21, |c| c.power_cycle());
        let mut lost = 0;
        for _ in 0..super::super::CHECK_EVERY {
            if chip.cycle(&bus, &cmd, 0, &mut sample) == Err(ChipFault::LostConfig) {
                lost += 1;
            }
        }
        assert_eq!(lost, 1);
    }
}
