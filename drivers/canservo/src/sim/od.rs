//! The simulated drive's object dictionary: typed entries with access
//! rights, PDO mappability, value ranges and defaults (hardware.md
//! §6.6, §6.10). Integer values up to 32 bits are stored as their raw
//! little-endian bits; strings as bytes. The dictionary checks what an
//! SDO write can get wrong on its own (existence, access, length,
//! range); rules that depend on other objects (PDO reconfiguration) are
//! the drive's.

use std::collections::BTreeMap;

use crate::codes::AbortCode;
use crate::drivefile::SdoType;

/// An entry's data type: an integer of the SDO types, or a string.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ty {
    /// An integer type.
    Int(SdoType),
    /// VISIBLE_STRING.
    Str,
}

/// UNSIGNED8.
pub const U8: Ty = Ty::Int(SdoType::U8);
/// UNSIGNED16.
pub const U16: Ty = Ty::Int(SdoType::U16);
/// UNSIGNED32.
pub const U32: Ty = Ty::Int(SdoType::U32);
/// INTEGER8.
pub const I8: Ty = Ty::Int(SdoType::I8);
/// INTEGER16.
pub const I16: Ty = Ty::Int(SdoType::I16);
/// INTEGER32.
pub const I32: Ty = Ty::Int(SdoType::I32);

impl Ty {
    /// Size in bytes (strings: None).
    pub fn size(self) -> Option<usize> {
        match self {
            Ty::Int(t) => Some(t.size()),
            Ty::Str => None,
        }
    }

    /// Size in bits, as a PDO mapping entry gives it.
    pub fn bits(self) -> u8 {
        self.size().map_or(0, |s| 8 * s as u8)
    }

    /// `bits` read as this type, widened to i64.
    pub fn to_i64(self, bits: u32) -> i64 {
        match self {
            Ty::Int(t) => t.decode(&bits.to_le_bytes()).unwrap_or(0),
            Ty::Str => i64::from(bits),
        }
    }

    /// The full range of the type.
    fn range(self) -> (i64, i64) {
        match self {
            Ty::Int(t) => t.range(),
            Ty::Str => (0, 0xFFFF_FFFF),
        }
    }
}

/// Access rights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read only (the drive changes it).
    Ro,
    /// Read and write.
    Rw,
    /// Write only.
    Wo,
    /// Constant.
    Const,
}

/// One object dictionary entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Data type.
    pub ty: Ty,
    /// Access.
    pub access: Access,
    /// Whether it may be mapped into a PDO.
    pub mappable: bool,
    /// Current value (raw bits).
    pub bits: u32,
    /// Current value of a string.
    pub text: Vec<u8>,
    /// Lowest value accepted by a write.
    pub min: i64,
    /// Highest value accepted by a write.
    pub max: i64,
    default_bits: u32,
    default_text: Vec<u8>,
}

/// The dictionary.
#[derive(Debug, Clone, Default)]
pub struct Od {
    entries: BTreeMap<(u16, u8), Entry>,
}

impl Od {
    /// An empty dictionary.
    pub fn new() -> Od {
        Od::default()
    }

    /// Adds an integer entry with its default value.
    pub fn add(
        &mut self,
        index: u16,
        sub: u8,
        ty: Ty,
        access: Access,
        mappable: bool,
        default: i64,
    ) {
        let (min, max) = ty.range();
        self.entries.insert(
            (index, sub),
            Entry {
                ty,
                access,
                mappable,
                bits: default as u32,
                text: Vec::new(),
                min,
                max,
                default_bits: default as u32,
                default_text: Vec::new(),
            },
        );
    }

    /// Adds a string entry.
    pub fn add_str(&mut self, index: u16, sub: u8, access: Access, text: &str) {
        self.entries.insert(
            (index, sub),
            Entry {
                ty: Ty::Str,
                access,
                mappable: false,
                bits: 0,
                text: text.as_bytes().to_vec(),
                min: 0,
                max: 0,
                default_bits: 0,
                default_text: text.as_bytes().to_vec(),
            },
        );
    }

    /// Narrows the range a write must respect.
    pub fn limit(&mut self, index: u16, sub: u8, min: i64, max: i64) {
        if let Some(e) = self.entries.get_mut(&(index, sub)) {
            e.min = min;
            e.max = max;
        }
    }

    /// The entry, if it exists.
    pub fn entry(&self, index: u16, sub: u8) -> Option<&Entry> {
        self.entries.get(&(index, sub))
    }

    /// Whether any sub-index of `index` exists.
    pub fn has_index(&self, index: u16) -> bool {
        self.entries
            .range((index, 0)..=(index, 0xFF))
            .next()
            .is_some()
    }

    /// Finds an entry or says which abort code its absence is.
    pub fn find(&self, index: u16, sub: u8) -> Result<&Entry, AbortCode> {
        self.entries
            .get(&(index, sub))
            .ok_or(if self.has_index(index) {
                AbortCode::NO_SUBINDEX
            } else {
                AbortCode::NO_OBJECT
            })
    }

    /// The raw bits of an entry (0 if it does not exist).
    pub fn get(&self, index: u16, sub: u8) -> u32 {
        self.entries.get(&(index, sub)).map_or(0, |e| e.bits)
    }

    /// An entry's value as a signed number per its type.
    pub fn get_i64(&self, index: u16, sub: u8) -> i64 {
        self.entries
            .get(&(index, sub))
            .map_or(0, |e| e.ty.to_i64(e.bits))
    }

    /// Sets an entry's value without checks (the drive's own updates).
    pub fn set(&mut self, index: u16, sub: u8, value: i64) {
        if let Some(e) = self.entries.get_mut(&(index, sub)) {
            e.bits = value as u32;
        }
    }

    /// An SDO read: the value's bytes.
    pub fn read(&self, index: u16, sub: u8) -> Result<Vec<u8>, AbortCode> {
        let e = self.find(index, sub)?;
        if e.access == Access::Wo {
            return Err(AbortCode::WRITE_ONLY);
        }
        Ok(match e.ty.size() {
            Some(n) => e.bits.to_le_bytes()[..n].to_vec(),
            None => e.text.clone(),
        })
    }

    /// Checks an SDO write of `data` and returns the value it would
    /// store (strings: 0), without storing it.
    pub fn check_write(&self, index: u16, sub: u8, data: &[u8]) -> Result<i64, AbortCode> {
        let e = self.find(index, sub)?;
        if matches!(e.access, Access::Ro | Access::Const) {
            return Err(AbortCode::READ_ONLY);
        }
        let Some(size) = e.ty.size() else {
            return if data.len() > 255 {
                Err(AbortCode::LENGTH_HIGH)
            } else {
                Ok(0)
            };
        };
        if data.len() > size {
            return Err(AbortCode::LENGTH_HIGH);
        }
        if data.len() < size {
            return Err(AbortCode::LENGTH_LOW);
        }
        let mut b = [0u8; 4];
        b[..size].copy_from_slice(data);
        let v = e.ty.to_i64(u32::from_le_bytes(b));
        if v > e.max {
            return Err(AbortCode::VALUE_HIGH);
        }
        if v < e.min {
            return Err(AbortCode::VALUE_LOW);
        }
        Ok(v)
    }

    /// Stores a checked write.
    pub fn commit(&mut self, index: u16, sub: u8, data: &[u8], value: i64) {
        if let Some(e) = self.entries.get_mut(&(index, sub)) {
            if e.ty == Ty::Str {
                e.text = data.to_vec();
            } else {
                e.bits = value as u32;
            }
        }
    }

    /// Restores the defaults of the indices in `range` (communication
    /// reset: 0x1000..=0x1FFF; node reset: everything).
    pub fn restore(&mut self, range: std::ops::RangeInclusive<u16>) {
        for ((index, _), e) in self.entries.iter_mut() {
            if range.contains(index) {
                e.bits = e.default_bits;
                e.text = e.default_text.clone();
            }
        }
    }

    /// Makes the present values the defaults of the indices in `range`
    /// (store parameters).
    pub fn store(&mut self, range: std::ops::RangeInclusive<u16>) {
        for ((index, _), e) in self.entries.iter_mut() {
            if range.contains(index) && matches!(e.access, Access::Rw) {
                e.default_bits = e.bits;
                e.default_text = e.text.clone();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn od() -> Od {
        let mut od = Od::new();
        od.add(0x6060, 0, I8, Access::Rw, true, 0);
        od.add(0x6041, 0, U16, Access::Ro, true, 0x250);
        od.add(0x1016, 0, U8, Access::Const, false, 1);
        od.add(0x1016, 1, U32, Access::Rw, false, 0);
        od.add_str(0x1008, 0, Access::Const, "a drive with a long name");
        od.limit(0x6060, 0, -1, 10);
        od
    }

    #[test]
    fn reads_and_writes_check_everything() {
        let mut od = od();
        assert_eq!(od.read(0x6041, 0).unwrap(), vec![0x50, 0x02]);
        assert_eq!(od.read(0x6041, 1).unwrap_err(), AbortCode::NO_SUBINDEX);
        assert_eq!(od.read(0x2000, 0).unwrap_err(), AbortCode::NO_OBJECT);
        assert_eq!(
            od.check_write(0x6041, 0, &[0, 0]).unwrap_err(),
            AbortCode::READ_ONLY
        );
        assert_eq!(
            od.check_write(0x6060, 0, &[1, 0]).unwrap_err(),
            AbortCode::LENGTH_HIGH
        );
        assert_eq!(
            od.check_write(0x1016, 1, &[1]).unwrap_err(),
            AbortCode::LENGTH_LOW
        );
        assert_eq!(
            od.check_write(0x6060, 0, &[11]).unwrap_err(),
            AbortCode::VALUE_HIGH
        );
        assert_eq!(
            od.check_write(0x6060, 0, &[0xFE]).unwrap_err(),
            AbortCode::VALUE_LOW
        );
        let v = od.check_write(0x6060, 0, &[0xFF]).unwrap();
        assert_eq!(v, -1);
        od.commit(0x6060, 0, &[0xFF], v);
        assert_eq!(od.get_i64(0x6060, 0), -1);
        assert_eq!(od.read(0x1008, 0).unwrap().len(), 24);
        od.restore(0x6000..=0x6FFF);
        assert_eq!(od.get_i64(0x6060, 0), 0);
    }
}
