//! One MOTENC board at register level: identification, the
//! initialisation LinuxCNC does, and the accesses the HAL functions are
//! made of. No HAL here: values in, values out.

use std::sync::Arc;

use hal_driver::bus::{RegWindow, ALL_ONES};

use crate::error::MotencError;
use crate::regs;

/// The two boards of the family.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoardKind {
    /// 8 encoders, 68 inputs, 32 outputs, 8 DACs, 8 ADCs; two FPGAs.
    Motenc100,
    /// 4 encoders, 32 inputs, 16 outputs, 8 DACs, 8 ADCs; one FPGA.
    MotencLite,
}

impl BoardKind {
    /// The kind a boardVersion value names.
    pub fn from_version(version: u32) -> Option<BoardKind> {
        match version {
            regs::VERSION_100 => Some(BoardKind::Motenc100),
            regs::VERSION_LITE => Some(BoardKind::MotencLite),
            _ => None,
        }
    }

    /// Its boardVersion value.
    pub fn version(self) -> u32 {
        match self {
            BoardKind::Motenc100 => regs::VERSION_100,
            BoardKind::MotencLite => regs::VERSION_LITE,
        }
    }

    /// How many FPGA blocks it has.
    pub fn fpgas(self) -> usize {
        match self {
            BoardKind::Motenc100 => 2,
            BoardKind::MotencLite => 1,
        }
    }

    /// Encoder channels.
    pub fn encoders(self) -> usize {
        self.fpgas() * regs::ENCODERS_PER_FPGA
    }

    /// Digital inputs: 32 on FPGA 0, 36 more on FPGA 1.
    pub fn inputs(self) -> usize {
        match self {
            BoardKind::Motenc100 => 68,
            BoardKind::MotencLite => 32,
        }
    }

    /// Digital outputs.
    pub fn outputs(self) -> usize {
        self.fpgas() * regs::OUTPUTS_PER_FPGA
    }

    /// The name printed for it.
    pub fn name(self) -> &'static str {
        match self {
            BoardKind::Motenc100 => "MOTENC-100",
            BoardKind::MotencLite => "MOTENC-Lite",
        }
    }
}

impl std::fmt::Display for BoardKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a board says about itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Identity {
    /// MOTENC-100 or MOTENC-Lite, from boardVersion.
    pub kind: BoardKind,
    /// The boardVersion register.
    pub version: u32,
    /// The board ID set by its two jumpers (0..3).
    pub jumper_id: u8,
}

impl std::fmt::Display for Identity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} (boardVersion {}, board ID jumpers {})",
            self.kind, self.version, self.jumper_id
        )
    }
}

/// Reads a board's identity: boardVersion and the ID jumpers of FPGA 0's
/// statusControl. Only reads, so a bring-up tool may call it on any
/// MOTENC. A window that reads all ones has no board behind it.
pub fn identify(bus: &dyn RegWindow) -> Result<Identity, MotencError> {
    let version = bus.read32(regs::BOARD_VERSION);
    let status = bus.read32(regs::status_control(0));
    if version == ALL_ONES && status == ALL_ONES {
        return Err(MotencError::NoAnswer {
            board: bus.describe(),
        });
    }
    let kind = BoardKind::from_version(version).ok_or_else(|| MotencError::UnknownVersion {
        board: bus.describe(),
        found: version,
    })?;
    Ok(Identity {
        kind,
        version,
        jumper_id: ((status >> regs::STATUS_ID_SHIFT) & 3) as u8,
    })
}

/// A board's registers, as the HAL functions use them.
pub struct Motenc {
    bus: Arc<dyn RegWindow>,
    id: Identity,
}

impl std::fmt::Debug for Motenc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Motenc")
            .field("bus", &self.bus.describe())
            .field("id", &self.id)
            .finish()
    }
}

impl Motenc {
    /// A board identified as `id` on `bus`.
    pub fn new(bus: Arc<dyn RegWindow>, id: Identity) -> Motenc {
        Motenc { bus, id }
    }

    /// The bus.
    pub fn bus(&self) -> &Arc<dyn RegWindow> {
        &self.bus
    }

    /// What the board is.
    pub fn identity(&self) -> Identity {
        self.id
    }

    /// LinuxCNC's initialisation: every output off, every counter reset
    /// and disarmed, every DAC at 0 V, the timer interrupt off and the
    /// watchdog off.
    pub fn init(&self) {
        for fpga in 0..self.id.kind.fpgas() {
            self.bus.write32(regs::digital_io(fpga), 0x0000_FFFF);
            self.bus
                .write32(regs::status_control(fpga), regs::RESET_ALL_COUNTERS);
            for j in 0..regs::ENCODERS_PER_FPGA {
                self.bus.write32(regs::encoder_count(fpga, j), 0);
            }
        }
        self.zero_dacs();
        self.bus.write32(regs::TIMER_IRQ_DISABLE, 1);
        self.bus.write32(regs::WATCHDOG_CONTROL, 0);
    }

    /// Whether the board still answers: boardVersion reads what it read
    /// at identification (a board that is gone reads all ones).
    #[inline]
    pub fn answers(&self) -> bool {
        self.bus.read32(regs::BOARD_VERSION) == self.id.version
    }

    /// statusControl of FPGA `fpga`.
    #[inline]
    pub fn status(&self, fpga: usize) -> u32 {
        self.bus.read32(regs::status_control(fpga))
    }

    /// digitalIo of FPGA `fpga` (inputs in bits 31..16).
    #[inline]
    pub fn digital_io(&self, fpga: usize) -> u32 {
        self.bus.read32(regs::digital_io(fpga))
    }

    /// The count of encoder `enc` (0..8).
    #[inline]
    pub fn count(&self, enc: usize) -> u32 {
        self.bus.read32(Self::count_reg(enc))
    }

    /// Arms (`true`) or disarms encoder `enc`'s clear-on-index.
    #[inline]
    pub fn arm_index(&self, enc: usize, arm: bool) {
        self.bus.write32(Self::count_reg(enc), arm as u32);
    }

    fn count_reg(enc: usize) -> usize {
        regs::encoder_count(enc / regs::ENCODERS_PER_FPGA, enc % regs::ENCODERS_PER_FPGA)
    }

    /// Writes DAC `n`'s code.
    #[inline]
    pub fn write_dac(&self, n: usize, code: u32) {
        self.bus.write32(regs::dac(n), code);
    }

    /// Every DAC to 0 V.
    pub fn zero_dacs(&self) {
        for n in 0..regs::DACS {
            self.write_dac(n, regs::DAC_ZERO);
        }
    }

    /// Drives FPGA `fpga`'s 16 outputs: bit i set turns output i on. The
    /// board's outputs are active low, so the complement is written.
    #[inline]
    pub fn write_outputs(&self, fpga: usize, on: u16) {
        self.bus.write32(regs::digital_io(fpga), !(on as u32));
    }

    /// Selects the next ADC conversion list and starts it.
    #[inline]
    pub fn adc_start(&self, command: u32) {
        self.bus.write32(regs::ADC_DATA_COMMAND, command);
        self.bus.write32(regs::ADC_START, 1);
    }

    /// The next ADC result, as a signed count.
    #[inline]
    pub fn adc_result(&self) -> i32 {
        regs::adc_count(self.bus.read32(regs::ADC_DATA_COMMAND))
    }

    /// Writes the watchdog control register.
    pub fn set_watchdog(&self, control: u32) {
        self.bus.write32(regs::WATCHDOG_CONTROL, control);
    }

    /// Restarts the watchdog.
    pub fn kick_watchdog(&self) {
        self.bus.write32(regs::WATCHDOG_RESET, regs::WATCHDOG_KICK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::MotencModel;
    use hal_driver::sim::SimBoard;

    #[test]
    fn identifies_both_kinds_and_the_jumpers() {
        let b = SimBoard::new(MotencModel::new(BoardKind::MotencLite, 2));
        let id = identify(&b).unwrap();
        assert_eq!(
            (id.kind, id.version, id.jumper_id),
            (BoardKind::MotencLite, 1, 2)
        );
        assert_eq!(
            id.to_string(),
            "MOTENC-Lite (boardVersion 1, board ID jumpers 2)"
        );
        let b = SimBoard::new(MotencModel::new(BoardKind::Motenc100, 3));
        let id = identify(&b).unwrap();
        assert_eq!((id.kind, id.jumper_id), (BoardKind::Motenc100, 3));
    }

    #[test]
    fn no_answer_and_unknown_versions_are_refused() {
        let b = SimBoard::new(MotencModel::new(BoardKind::Motenc100, 0));
        b.with(|m| m.unplug());
        let e = identify(&b).unwrap_err().to_string();
        assert!(e.contains("nothing answers"), "{e}");
        let b = SimBoard::new(MotencModel::new(BoardKind::Motenc100, 0));
        b.with(|m| m.set_version_register(7));
        let e = identify(&b).unwrap_err().to_string();
        assert!(
            e.contains("boardVersion is 0x7, expected 0 (MOTENC-100) or 1"),
            "{e}"
        );
    }

    #[test]
    fn kinds_have_their_channel_counts() {
        let k = BoardKind::Motenc100;
        assert_eq!((k.encoders(), k.inputs(), k.outputs()), (8, 68, 32));
        let k = BoardKind::MotencLite;
        assert_eq!((k.encoders(), k.inputs(), k.outputs()), (4, 32, 16));
        assert_eq!(BoardKind::from_version(2), None);
    }
}
