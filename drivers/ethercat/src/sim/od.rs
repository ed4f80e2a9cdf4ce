//! A simulated slave's object dictionary: entries by (index, sub-index)
//! with a data type, a bit length, access rights and a little-endian
//! value; SDO upload and download with the abort codes a real device
//! gives (no object, no sub-index, read-only, length mismatch, wrong
//! state); and the PDO objects (0x1600.., 0x1A00.., 0x1C12, 0x1C13)
//! whose contents define the process image.

use std::collections::BTreeMap;

use crate::wire::coe::AbortCode;

/// CoE data types used by the devices.
pub mod dtype {
    /// BOOLEAN.
    pub const BOOL: u8 = 0x01;
    /// INTEGER8.
    pub const I8: u8 = 0x02;
    /// INTEGER16.
    pub const I16: u8 = 0x03;
    /// INTEGER32.
    pub const I32: u8 = 0x04;
    /// UNSIGNED8.
    pub const U8: u8 = 0x05;
    /// UNSIGNED16.
    pub const U16: u8 = 0x06;
    /// UNSIGNED32.
    pub const U32: u8 = 0x07;
    /// VISIBLE_STRING.
    pub const STRING: u8 = 0x09;
    /// A gap in a PDO (BIT1..8 types are 0x30..).
    pub const BIT2: u8 = 0x31;
}

/// Who may do what with an entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read only.
    Ro,
    /// Read and write (in PRE-OP; process data objects in any state).
    Rw,
    /// Read and write in PRE-OP only (PDO mapping and assignment).
    RwPreop,
}

/// One entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// Name, for the tool.
    pub name: String,
    /// Data type.
    pub data_type: u8,
    /// Bit length (strings: 8 × bytes).
    pub bits: u16,
    /// Access.
    pub access: Access,
    /// The value, little-endian, ceil(bits / 8) bytes.
    pub value: Vec<u8>,
}

/// A mapped PDO entry: index (0 for a gap), sub-index, bit length.
pub type Mapped = (u16, u8, u8);
/// An assigned PDO: its index and its mapped entries.
pub type AssignedPdo = (u16, Vec<Mapped>);

/// The dictionary.
#[derive(Debug, Clone, Default)]
pub struct Dictionary {
    entries: BTreeMap<(u16, u8), Entry>,
}

impl Dictionary {
    /// Adds (or replaces) an entry of a data type and bit length holding
    /// `value`.
    pub fn add(
        &mut self,
        index: u16,
        sub: u8,
        name: &str,
        (data_type, bits): (u8, u16),
        access: Access,
        value: u64,
    ) {
        let len = usize::from(bits).div_ceil(8).max(1);
        let bytes = value.to_le_bytes();
        let mut v = vec![0u8; len];
        for (i, b) in v.iter_mut().enumerate().take(8) {
            *b = bytes[i];
        }
        self.entries.insert(
            (index, sub),
            Entry {
                name: name.to_string(),
                data_type,
                bits,
                access,
                value: v,
            },
        );
    }

    /// Adds a string entry.
    pub fn add_string(&mut self, index: u16, name: &str, s: &str) {
        self.entries.insert(
            (index, 0),
            Entry {
                name: name.to_string(),
                data_type: dtype::STRING,
                bits: (s.len() * 8) as u16,
                access: Access::Ro,
                value: s.as_bytes().to_vec(),
            },
        );
    }

    /// An entry.
    pub fn entry(&self, index: u16, sub: u8) -> Option<&Entry> {
        self.entries.get(&(index, sub))
    }

    /// All entries, in order.
    pub fn entries(&self) -> impl Iterator<Item = (&(u16, u8), &Entry)> {
        self.entries.iter()
    }

    /// Whether an object (any sub-index) exists.
    pub fn has_object(&self, index: u16) -> bool {
        self.entries
            .range((index, 0)..=(index, 255))
            .next()
            .is_some()
    }

    /// The value as an unsigned number (0 if absent).
    pub fn get(&self, index: u16, sub: u8) -> u64 {
        self.entry(index, sub).map_or(0, |e| {
            let mut b = [0u8; 8];
            for (i, x) in e.value.iter().take(8).enumerate() {
                b[i] = *x;
            }
            u64::from_le_bytes(b)
        })
    }

    /// The value sign-extended from its bit length.
    pub fn get_signed(&self, index: u16, sub: u8) -> i64 {
        let bits = self
            .entry(index, sub)
            .map_or(64, |e| u32::from(e.bits.clamp(1, 64)));
        let v = self.get(index, sub);
        let shift = 64 - bits;
        ((v << shift) as i64) >> shift
    }

    /// Sets a value (truncated to the entry's bytes); false if absent.
    pub fn set(&mut self, index: u16, sub: u8, value: u64) -> bool {
        match self.entries.get_mut(&(index, sub)) {
            Some(e) => {
                let bytes = value.to_le_bytes();
                for (i, b) in e.value.iter_mut().enumerate().take(8) {
                    *b = bytes[i];
                }
                true
            }
            None => false,
        }
    }

    /// SDO upload: the value's bytes, or the abort code a device gives.
    pub fn upload(&self, index: u16, sub: u8, complete: bool) -> Result<Vec<u8>, AbortCode> {
        if complete {
            return self.upload_complete(index, sub);
        }
        match self.entry(index, sub) {
            Some(e) => Ok(e.value.clone()),
            None if self.has_object(index) => Err(AbortCode::NO_SUBINDEX),
            None => Err(AbortCode::NO_OBJECT),
        }
    }

    /// Complete access: sub-index 0 as one byte (from `sub` 0) or not,
    /// then the others packed, each in whole bytes.
    fn upload_complete(&self, index: u16, sub: u8) -> Result<Vec<u8>, AbortCode> {
        if !self.has_object(index) {
            return Err(AbortCode::NO_OBJECT);
        }
        if sub > 1 {
            return Err(AbortCode::UNSUPPORTED_ACCESS);
        }
        let mut out = Vec::new();
        for ((_, s), e) in self.entries.range((index, sub)..=(index, 255)) {
            if *s == 0 {
                out.push(e.value.first().copied().unwrap_or(0));
                // Sub 0 of a record is padded to 16 bits in complete access.
                out.push(0);
            } else {
                out.extend_from_slice(&e.value);
            }
        }
        Ok(out)
    }

    /// SDO download in AL state `preop` (true in PRE-OP, false in
    /// SAFE-OP/OP): checks access, length and the PDO rules.
    pub fn download(
        &mut self,
        index: u16,
        sub: u8,
        complete: bool,
        data: &[u8],
        preop: bool,
    ) -> Result<(), AbortCode> {
        if complete {
            return self.download_complete(index, sub, data, preop);
        }
        let e = match self.entries.get(&(index, sub)) {
            Some(e) => e,
            None if self.has_object(index) => return Err(AbortCode::NO_SUBINDEX),
            None => return Err(AbortCode::NO_OBJECT),
        };
        match e.access {
            Access::Ro => return Err(AbortCode::READ_ONLY),
            Access::RwPreop if !preop => return Err(AbortCode::WRONG_STATE),
            _ => {}
        }
        if e.data_type != dtype::STRING {
            let len = e.value.len();
            if data.len() > len {
                return Err(AbortCode::LENGTH_HIGH);
            }
            if data.len() < len {
                return Err(AbortCode::LENGTH_LOW);
            }
        }
        self.check_pdo_rules(index, sub, data)?;
        if let Some(e) = self.entries.get_mut(&(index, sub)) {
            e.value = data.to_vec();
        }
        Ok(())
    }

    fn download_complete(
        &mut self,
        index: u16,
        sub: u8,
        data: &[u8],
        preop: bool,
    ) -> Result<(), AbortCode> {
        if !self.has_object(index) {
            return Err(AbortCode::NO_OBJECT);
        }
        if sub > 1 {
            return Err(AbortCode::UNSUPPORTED_ACCESS);
        }
        let mut at = 0;
        let mut writes = Vec::new();
        for ((_, s), e) in self.entries.range((index, sub)..=(index, 255)) {
            let len = if *s == 0 { 2 } else { e.value.len() };
            if at + len > data.len() {
                break;
            }
            let bytes = if *s == 0 {
                vec![data[at]]
            } else {
                data[at..at + len].to_vec()
            };
            writes.push((*s, bytes));
            at += len;
        }
        if at != data.len() {
            return Err(AbortCode::LENGTH_MISMATCH);
        }
        // Sub 0 last: entries first, then the count that validates them.
        writes.sort_by_key(|(s, _)| if *s == 0 { 256 } else { u16::from(*s) });
        for (s, bytes) in writes {
            if s != 0 && self.get(index, 0) != 0 && (0x1600..0x1C14).contains(&index) {
                // Writing entries needs sub 0 cleared first.
                self.set(index, 0, 0);
            }
            self.download(index, s, false, &bytes, preop)?;
        }
        Ok(())
    }

    /// The PDO rules: mapping (0x16xx, 0x1Axx) and assignment (0x1C12,
    /// 0x1C13) entries change only while sub 0 is 0; sub 0 may only be
    /// set to a count whose entries are valid.
    fn check_pdo_rules(&self, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let mapping = (0x1600..=0x17FF).contains(&index) || (0x1A00..=0x1BFF).contains(&index);
        let assign = index == 0x1C12 || index == 0x1C13;
        if !mapping && !assign {
            return Ok(());
        }
        let mut v = [0u8; 8];
        for (i, b) in data.iter().take(8).enumerate() {
            v[i] = *b;
        }
        let value = u64::from_le_bytes(v);
        if sub != 0 {
            if self.get(index, 0) != 0 {
                return Err(AbortCode::WRONG_STATE);
            }
            return Ok(());
        }
        for s in 1..=value.min(255) as u8 {
            if self.entry(index, s).is_none() {
                return Err(AbortCode::VALUE_HIGH);
            }
            let e = self.get(index, s);
            if mapping {
                let (i, si, bits) = ((e >> 16) as u16, (e >> 8) as u8, e as u8);
                if i != 0 {
                    match self.entry(i, si) {
                        Some(t) if t.bits == u16::from(bits) => {}
                        Some(_) => return Err(AbortCode::INCOMPATIBLE),
                        None => return Err(AbortCode::NOT_MAPPABLE),
                    }
                }
            } else if !self.has_object(e as u16) {
                return Err(AbortCode::INVALID_VALUE);
            }
        }
        Ok(())
    }

    /// The PDOs assigned to `assign` (0x1C12 or 0x1C13), each with its
    /// mapped entries (index, sub, bits; index 0 is a gap).
    pub fn assigned(&self, assign: u16) -> Vec<AssignedPdo> {
        let n = self.get(assign, 0).min(255) as u8;
        (1..=n)
            .map(|s| {
                let pdo = self.get(assign, s) as u16;
                let m = self.get(pdo, 0).min(255) as u8;
                let entries = (1..=m)
                    .map(|k| {
                        let e = self.get(pdo, k);
                        ((e >> 16) as u16, (e >> 8) as u8, e as u8)
                    })
                    .collect();
                (pdo, entries)
            })
            .collect()
    }

    /// Total bits of the PDOs assigned to `assign`.
    pub fn assigned_bits(&self, assign: u16) -> usize {
        self.assigned(assign)
            .iter()
            .flat_map(|(_, e)| e.iter())
            .map(|(_, _, b)| usize::from(*b))
            .sum()
    }
}

/// Copies `bits` bits from `src` at bit `src_bit` to `dst` at bit
/// `dst_bit` (little-endian bit order, as EtherCAT packs process data).
/// Bits outside either slice are skipped.
pub fn copy_bits(src: &[u8], src_bit: usize, dst: &mut [u8], dst_bit: usize, bits: usize) {
    if src_bit % 8 == 0 && dst_bit % 8 == 0 && bits % 8 == 0 {
        let (s, d, n) = (src_bit / 8, dst_bit / 8, bits / 8);
        let n = n
            .min(src.len().saturating_sub(s))
            .min(dst.len().saturating_sub(d));
        dst[d..d + n].copy_from_slice(&src[s..s + n]);
        return;
    }
    for i in 0..bits {
        let (sb, db) = (src_bit + i, dst_bit + i);
        let (Some(&s), Some(d)) = (src.get(sb / 8), dst.get_mut(db / 8)) else {
            continue;
        };
        let bit = (s >> (sb % 8)) & 1;
        *d = (*d & !(1 << (db % 8))) | bit << (db % 8);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn od() -> Dictionary {
        let mut d = Dictionary::default();
        d.add(0x6000, 1, "in 1", (dtype::BOOL, 1), Access::Ro, 1);
        d.add(0x6010, 1, "in 2", (dtype::I16, 16), Access::Ro, 0xFFFE);
        d.add(0x1A00, 0, "n", (dtype::U8, 8), Access::RwPreop, 1);
        d.add(
            0x1A00,
            1,
            "e1",
            (dtype::U32, 32),
            Access::RwPreop,
            0x6000_0101,
        );
        d.add(0x1A00, 2, "e2", (dtype::U32, 32), Access::RwPreop, 0);
        d.add(0x1C13, 0, "n", (dtype::U8, 8), Access::RwPreop, 1);
        d.add(0x1C13, 1, "p1", (dtype::U16, 16), Access::RwPreop, 0x1A00);
        d
    }

    #[test]
    fn upload_download_and_aborts() {
        let mut d = od();
        assert_eq!(d.upload(0x6000, 1, false), Ok(vec![1]));
        assert_eq!(d.get_signed(0x6010, 1), -2);
        assert_eq!(d.upload(0x6000, 9, false), Err(AbortCode::NO_SUBINDEX));
        assert_eq!(d.upload(0x7000, 0, false), Err(AbortCode::NO_OBJECT));
        assert_eq!(
            d.download(0x6000, 1, false, &[0], true),
            Err(AbortCode::READ_ONLY)
        );
        assert_eq!(
            d.download(0x1A00, 0, false, &[0, 0], true),
            Err(AbortCode::LENGTH_HIGH)
        );
        assert_eq!(
            d.download(0x1A00, 0, false, &[0], false),
            Err(AbortCode::WRONG_STATE)
        );
        // Entries change only with sub 0 at 0.
        assert_eq!(
            d.download(0x1A00, 2, false, &0x6010_0110u32.to_le_bytes(), true),
            Err(AbortCode::WRONG_STATE)
        );
        d.download(0x1A00, 0, false, &[0], true).unwrap();
        d.download(0x1A00, 2, false, &0x6010_0110u32.to_le_bytes(), true)
            .unwrap();
        d.download(0x1A00, 0, false, &[2], true).unwrap();
        assert_eq!(d.assigned_bits(0x1C13), 17);
        // A mapping of an absent object or a wrong length is refused.
        d.download(0x1A00, 0, false, &[0], true).unwrap();
        d.download(0x1A00, 2, false, &0x6010_0108u32.to_le_bytes(), true)
            .unwrap();
        assert_eq!(
            d.download(0x1A00, 0, false, &[2], true),
            Err(AbortCode::INCOMPATIBLE)
        );
    }

    #[test]
    fn complete_access() {
        let mut d = od();
        assert_eq!(d.upload(0x1C13, 0, true), Ok(vec![1, 0, 0x00, 0x1A]));
        d.download(0x1C13, 0, true, &[0, 0, 0x00, 0x1A], true)
            .unwrap();
        assert_eq!(d.get(0x1C13, 0), 0);
        assert_eq!(
            d.download(0x1C13, 0, true, &[1, 0, 0], true),
            Err(AbortCode::LENGTH_MISMATCH)
        );
    }

    #[test]
    fn bit_copies() {
        let mut dst = [0u8; 2];
        copy_bits(&[0b101], 0, &mut dst, 6, 3);
        assert_eq!(dst, [0b0100_0000, 0b1]);
        copy_bits(&[0xAB, 0xCD], 0, &mut dst, 0, 16);
        assert_eq!(dst, [0xAB, 0xCD]);
        // Out of range bits are skipped, never a panic.
        copy_bits(&[0xFF], 0, &mut dst, 12, 40);
    }
}
