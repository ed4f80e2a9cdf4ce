//! Where each process-data entry of a slave sits in its part of the
//! process image, read in PRE-OP the way EtherCrab sizes that part: from
//! the PDO assignment objects (0x1C10 + sync manager) and the mapping
//! objects they name when the slave speaks CoE, else from the PDO
//! categories of its SII. Each sync manager's data starts on a byte, its
//! entries packed bit by bit in assignment order, as on the wire. The
//! HAL binding finds a pin's bits here by (index, sub-index).

use ethercrab::{MainDevice, SubDevice, SubDeviceRef, SubIndex};

use super::io::Io;
use crate::error::{Error, Result};
use crate::wire::sii::{protocol, sm_type, Pdo, Sii};

/// Bytes of SII read at most (the largest EEPROM is 4 Mibit).
const MAX_SII_BYTES: usize = 1 << 19;

/// One mapped entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MappedEntry {
    /// Object index (0: padding).
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Bits.
    pub bits: u8,
    /// First bit within the slave's inputs or outputs.
    pub bit: usize,
}

/// A slave's mapped entries, both ways.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Layout {
    /// Outputs (master → slave).
    pub outputs: Vec<MappedEntry>,
    /// Inputs (slave → master).
    pub inputs: Vec<MappedEntry>,
    /// The slave → master mailbox (start, bytes) of a slave with CoE.
    pub mailbox_in: Option<(u16, u16)>,
}

impl Layout {
    /// The entry (index, sub) of the outputs (`output`) or the inputs.
    pub fn find(&self, index: u16, sub: u8, output: bool) -> Option<MappedEntry> {
        let list = if output { &self.outputs } else { &self.inputs };
        list.iter()
            .find(|e| e.index == index && e.sub == sub && index != 0)
            .copied()
    }

    /// Builds a direction from PDOs as lists of (index, sub, bits), each
    /// list one sync manager's.
    pub fn pack(sms: &[Vec<(u16, u8, u8)>]) -> Vec<MappedEntry> {
        let mut out = Vec::new();
        let mut bit = 0usize;
        for sm in sms {
            for &(index, sub, bits) in sm {
                out.push(MappedEntry {
                    index,
                    sub,
                    bits,
                    bit,
                });
                bit += usize::from(bits);
            }
            bit = bit.div_ceil(8) * 8;
        }
        out
    }
}

/// Reads slave `sd`'s layout (PRE-OP, after the configuration's SDO
/// writes, before EtherCrab configures the process image).
pub(crate) fn read<S: std::ops::Deref<Target = SubDevice>>(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    sd: &SubDeviceRef<'_, S>,
    position: u16,
) -> Result<Layout> {
    let fail = |what: &str, e: &dyn std::fmt::Display| Error::SlaveMismatch {
        position,
        name: sd.name().to_string(),
        reason: format!("reading its PDO layout: {what}: {e}"),
    };
    let size = io
        .block_on(sd.eeprom_size(md))
        .map_err(|e| fail("SII size", &e))?
        .min(MAX_SII_BYTES);
    let mut image = vec![0u8; size];
    let n = io
        .block_on(sd.eeprom_read_raw(md, 0, &mut image))
        .map_err(|e| fail("SII", &e))?;
    image.truncate(n);
    let sii = Sii::decode(&image, Some(sd.name())).map_err(|e| fail("SII", &e))?;
    let coe = sii
        .mailbox
        .is_some_and(|m| m.protocols & protocol::COE != 0 && m.tx_size > 0);
    let mut dirs = [Vec::new(), Vec::new()];
    for (k, sm) in sii.sync_managers.iter().enumerate() {
        let slot = match sm.kind {
            sm_type::OUTPUTS => 0,
            sm_type::INPUTS => 1,
            _ => continue,
        };
        let entries = if coe {
            coe_entries(io, sd, 0x1C10 + k as u16).map_err(|e| fail("CoE PDO objects", &e))?
        } else {
            let pdos = if slot == 0 {
                &sii.rx_pdos
            } else {
                &sii.tx_pdos
            };
            sii_entries(pdos, k as u8)
        };
        dirs[slot].push(entries);
    }
    Ok(Layout {
        outputs: Layout::pack(&dirs[0]),
        inputs: Layout::pack(&dirs[1]),
        mailbox_in: sii
            .mailbox
            .filter(|_| coe)
            .map(|m| (m.tx_offset, m.tx_size)),
    })
}

/// The entries of the PDOs an SII assigns to sync manager `sm`.
fn sii_entries(pdos: &[Pdo], sm: u8) -> Vec<(u16, u8, u8)> {
    pdos.iter()
        .filter(|p| p.sm == sm)
        .flat_map(|p| p.entries.iter().map(|e| (e.index, e.sub, e.bits)))
        .collect()
}

/// The entries of the PDOs assignment object `assign` names.
fn coe_entries<S: std::ops::Deref<Target = SubDevice>>(
    io: &mut Io<'_>,
    sd: &SubDeviceRef<'_, S>,
    assign: u16,
) -> std::result::Result<Vec<(u16, u8, u8)>, ethercrab::error::Error> {
    let mut out = Vec::new();
    let count: u8 = io.block_on(sd.sdo_read(assign, SubIndex::Index(0)))?;
    for i in 1..=count {
        let pdo: u16 = io.block_on(sd.sdo_read(assign, SubIndex::Index(i)))?;
        let n: u8 = io.block_on(sd.sdo_read(pdo, SubIndex::Index(0)))?;
        for j in 1..=n {
            let m: u32 = io.block_on(sd.sdo_read(pdo, SubIndex::Index(j)))?;
            out.push(((m >> 16) as u16, (m >> 8) as u8, m as u8));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packs_bits_and_starts_each_sync_manager_on_a_byte() {
        let l = Layout {
            outputs: Layout::pack(&[
                vec![(0x7000, 1, 1), (0x7010, 1, 1), (0, 0, 6), (0x7020, 1, 16)],
                vec![(0x7030, 1, 3)],
                vec![(0x7040, 1, 8)],
            ]),
            inputs: Vec::new(),
            mailbox_in: None,
        };
        let bits: Vec<usize> = l.outputs.iter().map(|e| e.bit).collect();
        assert_eq!(bits, [0, 1, 2, 8, 24, 32]);
        assert_eq!(l.find(0x7020, 1, true).map(|e| e.bit), Some(8));
        assert_eq!(l.find(0x7020, 1, false), None);
        assert_eq!(l.find(0, 0, true), None, "padding is never a pin's entry");
    }
}
