//! Board detection (hardware.md §3.3): the signature the board test
//! register (BRDTST) gives one bit per read, Model I and Model II, and
//! the search over the jumper-selectable base addresses.

use hal_driver::bus::{PortBus, PortRange};

use crate::error::StgError;
use crate::regs;

/// The two board generations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// Model I ("stg1"): an 8259 and INTC for index handling.
    One,
    /// Model II ("stg2"): IDLEN/SELDI/IDL index registers.
    Two,
}

impl Model {
    /// The model a signature names.
    pub fn from_signature(signature: u8) -> Option<Model> {
        match signature {
            regs::SIGNATURE_MODEL1 => Some(Model::One),
            regs::SIGNATURE_MODEL2 => Some(Model::Two),
            _ => None,
        }
    }

    /// The model `model=` names (1 or 2).
    pub fn from_number(n: i64) -> Option<Model> {
        match n {
            1 => Some(Model::One),
            2 => Some(Model::Two),
            _ => None,
        }
    }

    /// Its signature.
    pub fn signature(self) -> u8 {
        match self {
            Model::One => regs::SIGNATURE_MODEL1,
            Model::Two => regs::SIGNATURE_MODEL2,
        }
    }

    /// Whether it is a Model II.
    pub fn is_two(self) -> bool {
        self == Model::Two
    }

    /// Whether one BRDTST byte is consistent with this model: its
    /// signature bit is the signature's bit at the position the byte
    /// names. A board gone from the bus reads 0xff, which no model gives
    /// (bit 7 of both signatures is 0).
    #[inline]
    pub fn brdtst_ok(self, byte: u8) -> bool {
        let q = (byte >> regs::BRDTST_Q_SHIFT) & 7;
        (byte & regs::BRDTST_SER != 0) == (self.signature() & (1 << q) != 0)
    }
}

impl std::fmt::Display for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Model::One => "Model I",
            Model::Two => "Model II",
        })
    }
}

/// The two port windows of a board at `base`.
pub fn port_ranges(base: u16) -> Result<[PortRange; 2], StgError> {
    let high = base.checked_add(regs::HIGH_WINDOW).ok_or_else(|| {
        StgError::Backend(format!(
            "base {base:#x} leaves no room for the board's upper window"
        ))
    })?;
    Ok([
        PortRange::new(base, regs::WINDOW_LEN)?,
        PortRange::new(high, regs::WINDOW_LEN)?,
    ])
}

/// The windows of every candidate base (for a search).
pub fn candidate_ranges() -> Vec<PortRange> {
    regs::CANDIDATE_BASES
        .iter()
        .flat_map(|&b| port_ranges(b).unwrap_or_else(|_| unreachable!("candidates fit")))
        .collect()
}

/// What eight BRDTST reads at a base gave.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Signature {
    /// The signature assembled from the bits, at their positions.
    pub value: u8,
    /// Every read returned 0xff: nothing there.
    pub empty: bool,
}

/// Reads the signature at `base`: eight BRDTST reads, each adding its
/// signature bit at the position it names. (On a Model I this also
/// clears the even axis's index latch.)
pub fn read_signature(bus: &dyn PortBus, base: u16) -> Signature {
    let mut value = 0u8;
    let mut empty = true;
    for _ in 0..8 {
        let b = bus.inb(base.wrapping_add(regs::BRDTST));
        empty &= b == 0xFF;
        if b & regs::BRDTST_SER != 0 {
            value |= 1 << ((b >> regs::BRDTST_Q_SHIFT) & 7);
        }
    }
    Signature { value, empty }
}

/// The model of the board at `base`, or why there is none: nothing
/// answers, or something that is not a Servo-To-Go. Only reads; the
/// bring-up probe.
pub fn probe(bus: &dyn PortBus, base: u16) -> Result<Model, StgError> {
    let s = read_signature(bus, base);
    if s.empty {
        return Err(StgError::NothingAnswers { base });
    }
    Model::from_signature(s.value).ok_or(StgError::NotAnStg {
        base,
        signature: s.value,
    })
}

/// Searches the candidate bases from 0x3e0 down to 0x200, as LinuxCNC
/// does, for the first that gives a signature. `bus` must cover
/// [`candidate_ranges`].
pub fn autodetect(bus: &dyn PortBus) -> Result<(u16, Model), StgError> {
    regs::CANDIDATE_BASES
        .iter()
        .find_map(|&base| probe(bus, base).ok().map(|m| (base, m)))
        .ok_or(StgError::NotFound)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::StgModel;
    use hal_driver::sim::SimBoard;

    #[test]
    fn probes_both_models_and_nothing() {
        let one = SimBoard::new(StgModel::new(Model::One, 0x220));
        assert_eq!(probe(&one, 0x220).unwrap(), Model::One);
        let e = probe(&one, 0x300).unwrap_err().to_string();
        assert_eq!(
            e,
            "no board answers at 0x300 (its board test register reads 0xff: nothing decodes \
             the port)"
        );
        let two = SimBoard::new(StgModel::new(Model::Two, 0x3E0));
        assert_eq!(probe(&two, 0x3E0).unwrap(), Model::Two);
        // Read again from any position: the bits carry their positions.
        two.inb(0x3E0 + regs::BRDTST);
        assert_eq!(probe(&two, 0x3E0).unwrap(), Model::Two);
        assert_eq!(autodetect(&one).unwrap(), (0x220, Model::One));
        assert_eq!(autodetect(&two).unwrap(), (0x3E0, Model::Two));
        let gone = SimBoard::new(StgModel::new(Model::Two, 0x300));
        gone.with(|m| m.unplug());
        assert!(matches!(autodetect(&gone), Err(StgError::NotFound)));
    }

    #[test]
    fn brdtst_bytes_check_against_the_model() {
        let two = SimBoard::new(StgModel::new(Model::Two, 0x300));
        for _ in 0..16 {
            let b = two.inb(0x300 + regs::BRDTST);
            assert!(Model::Two.brdtst_ok(b), "{b:#x}");
        }
        assert!(!Model::One.brdtst_ok(0xFF) && !Model::Two.brdtst_ok(0xFF));
        // Position 0 holds the bit the models differ in.
        assert!(Model::One.brdtst_ok(0x80) && !Model::Two.brdtst_ok(0x80));
    }

    #[test]
    fn ranges_of_a_base() {
        let r = port_ranges(0x300).unwrap();
        assert_eq!((r[0].base, r[0].len, r[1].base), (0x300, 0x20, 0x700));
        assert!(port_ranges(0xFC00).is_err());
        assert_eq!(candidate_ranges().len(), 32);
    }
}
