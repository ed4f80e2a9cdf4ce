//! The records a remote card describes itself with (hostmot2-more.md
//! 2.5): the process-data table (PTOC) and the globals table (GTOC) are
//! lists of 16-bit record addresses ending with 0; a data record (0xA0)
//! is 14 packed bytes and two NUL-terminated strings (unit, name), a
//! mode record (0xB0) 4 bytes and a name.
//!
//! Reading goes through a byte source (the driver reads one byte per
//! transfer over the serial link; the fuzz target reads from a buffer),
//! so a garbage table or record is refused with a reason instead of
//! being followed without end.

use thiserror::Error;

/// Record types.
pub mod kind {
    /// A data record: process data (in the PTOC) or a global (in the GTOC).
    pub const DATA: u8 = 0xA0;
    /// A mode record (in the GTOC).
    pub const MODE: u8 = 0xB0;
}

/// Data types of a data record.
pub mod data_type {
    /// Padding: bits skipped.
    pub const PAD: u8 = 0x00;
    /// A bit field: one HAL bit per bit.
    pub const BITS: u8 = 0x01;
    /// An unsigned number, scaled to ParmMax.
    pub const UNSIGNED: u8 = 0x02;
    /// A signed number, scaled to ParmMax.
    pub const SIGNED: u8 = 0x03;
    /// A non-volatile unsigned (globals only).
    pub const NV_UNSIGNED: u8 = 0x04;
    /// A non-volatile signed (globals only).
    pub const NV_SIGNED: u8 = 0x05;
    /// A raw stream word.
    pub const STREAM: u8 = 0x06;
    /// A boolean.
    pub const BOOLEAN: u8 = 0x07;
    /// An encoder counter.
    pub const ENCODER: u8 = 0x08;
    /// A float (32 or 64 bits).
    pub const FLOAT: u8 = 0x10;
    /// A non-volatile float (globals only).
    pub const NV_FLOAT: u8 = 0x11;
    /// The high part of a split encoder counter.
    pub const ENCODER_HIGH: u8 = 0x18;
    /// The low part of a split encoder counter.
    pub const ENCODER_LOW: u8 = 0x28;

    /// Whether the type lives in the remote's EEPROM.
    pub fn is_nonvolatile(t: u8) -> bool {
        matches!(t, NV_UNSIGNED | NV_SIGNED | NV_FLOAT)
    }
}

/// Data directions, as the remote sees them.
pub mod dir {
    /// Remote to host (a HAL output).
    pub const IN: u8 = 0x00;
    /// Both ways (a HAL I/O pin).
    pub const BOTH: u8 = 0x40;
    /// Host to remote (a HAL input).
    pub const OUT: u8 = 0x80;
}

/// Longest name LinuxCNC keeps.
pub const MAX_NAME: usize = 48;
/// Most entries of a table.
pub const MAX_TABLE: usize = 64;
/// Bytes of a data record before its strings.
pub const DATA_FIXED: usize = 14;
/// Bytes of a mode record before its name.
pub const MODE_FIXED: usize = 4;

/// A data record.
#[derive(Debug, Clone, PartialEq)]
pub struct DataRecord {
    /// Bits of data.
    pub bits: u8,
    /// Its type ([`data_type`]).
    pub data_type: u8,
    /// Its direction ([`dir`]).
    pub dir: u8,
    /// ParmMin.
    pub min: f32,
    /// ParmMax.
    pub max: f32,
    /// ParmAddr: where a global's value is in the remote's memory.
    pub addr: u16,
    /// Unit text.
    pub unit: String,
    /// Name, as the remote spells it.
    pub name: String,
}

/// A mode record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModeRecord {
    /// The mode's number (the `sserial_port_N` digit).
    pub index: u8,
    /// A software mode (else a hardware mode).
    pub software: bool,
    /// Its name.
    pub name: String,
}

/// A record of either kind.
#[derive(Debug, Clone, PartialEq)]
pub enum Record {
    /// Data.
    Data(DataRecord),
    /// A mode.
    Mode(ModeRecord),
}

/// Why a table or record is refused.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum RecordError {
    /// A record type that is neither data nor mode.
    #[error("record at 0x{addr:04X} has type 0x{kind:02X}, expected 0xA0 (data) or 0xB0 (mode)")]
    BadKind {
        /// Where.
        addr: u16,
        /// The type byte.
        kind: u8,
    },
    /// A string that does not end within 48 characters or is not text.
    #[error("record at 0x{addr:04X}: its {what} is not a NUL-terminated name of at most 48 printable characters")]
    BadString {
        /// Where the record is.
        addr: u16,
        /// Which string.
        what: &'static str,
    },
    /// A table that does not end within 64 entries.
    #[error("record table at 0x{addr:04X} has no end within {MAX_TABLE} entries")]
    TableTooLong {
        /// Where the table is.
        addr: u16,
    },
    /// A record whose address or strings run past the 64 KiB space.
    #[error("record at 0x{addr:04X} runs past the end of the remote's memory")]
    OutOfMemory {
        /// Where.
        addr: u16,
    },
}

impl DataRecord {
    /// The record's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let mut v = vec![kind::DATA, self.bits, self.data_type, self.dir];
        v.extend_from_slice(&self.min.to_le_bytes());
        v.extend_from_slice(&self.max.to_le_bytes());
        v.extend_from_slice(&self.addr.to_le_bytes());
        v.extend_from_slice(self.unit.as_bytes());
        v.push(0);
        v.extend_from_slice(self.name.as_bytes());
        v.push(0);
        v
    }

    /// The name as LinuxCNC uses it in HAL names: lower-cased.
    pub fn hal_name(&self) -> String {
        self.name.to_ascii_lowercase()
    }

    /// Whether the host sends it.
    pub fn is_out(&self) -> bool {
        self.dir & dir::OUT != 0 || self.dir & dir::BOTH != 0
    }

    /// Whether the host receives it.
    pub fn is_in(&self) -> bool {
        self.dir & dir::OUT == 0
    }
}

impl ModeRecord {
    /// The record's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let mut v = vec![kind::MODE, self.index, u8::from(self.software), 0];
        v.extend_from_slice(self.name.as_bytes());
        v.push(0);
        v
    }
}

/// Reads a NUL-terminated name from `at`.
fn read_string<E: From<RecordError>>(
    record: u16,
    at: u16,
    what: &'static str,
    byte: &mut dyn FnMut(u16) -> Result<u8, E>,
) -> Result<(String, u16), E> {
    let mut s = String::new();
    let mut a = at;
    loop {
        let b = byte(a)?;
        if b == 0 {
            break;
        }
        if !(b.is_ascii_graphic() || b == b' ') || s.len() == MAX_NAME {
            return Err(RecordError::BadString { addr: record, what }.into());
        }
        s.push(b as char);
        a = a
            .checked_add(1)
            .ok_or(RecordError::OutOfMemory { addr: record })?;
    }
    Ok((s, a.wrapping_add(1)))
}

/// Reads `n` bytes from `at`.
fn read_bytes<E: From<RecordError>, const N: usize>(
    record: u16,
    at: u16,
    byte: &mut dyn FnMut(u16) -> Result<u8, E>,
) -> Result<[u8; N], E> {
    let mut out = [0u8; N];
    for (i, o) in out.iter_mut().enumerate() {
        let a = at
            .checked_add(i as u16)
            .ok_or(RecordError::OutOfMemory { addr: record })?;
        *o = byte(a)?;
    }
    Ok(out)
}

/// Reads the record at `addr` through `byte`.
pub fn read_record<E: From<RecordError>>(
    addr: u16,
    byte: &mut dyn FnMut(u16) -> Result<u8, E>,
) -> Result<Record, E> {
    let kind = byte(addr)?;
    match kind {
        kind::DATA => {
            let f: [u8; DATA_FIXED] = read_bytes(addr, addr, byte)?;
            let after = addr
                .checked_add(DATA_FIXED as u16)
                .ok_or(RecordError::OutOfMemory { addr })?;
            let (unit, next) = read_string(addr, after, "unit", byte)?;
            let (name, _) = read_string(addr, next, "name", byte)?;
            if name.is_empty() || name.contains(' ') {
                return Err(RecordError::BadString { addr, what: "name" }.into());
            }
            Ok(Record::Data(DataRecord {
                bits: f[1],
                data_type: f[2],
                dir: f[3],
                min: f32::from_le_bytes([f[4], f[5], f[6], f[7]]),
                max: f32::from_le_bytes([f[8], f[9], f[10], f[11]]),
                addr: u16::from_le_bytes([f[12], f[13]]),
                unit,
                name,
            }))
        }
        kind::MODE => {
            let f: [u8; MODE_FIXED] = read_bytes(addr, addr, byte)?;
            let after = addr
                .checked_add(MODE_FIXED as u16)
                .ok_or(RecordError::OutOfMemory { addr })?;
            let (name, _) = read_string(addr, after, "mode name", byte)?;
            Ok(Record::Mode(ModeRecord {
                index: f[1],
                software: f[2] != 0,
                name,
            }))
        }
        kind => Err(RecordError::BadKind { addr, kind }.into()),
    }
}

/// Reads a table of record addresses at `addr` (16-bit entries up to a 0).
pub fn read_table<E: From<RecordError>>(
    addr: u16,
    byte: &mut dyn FnMut(u16) -> Result<u8, E>,
) -> Result<Vec<u16>, E> {
    let mut v = Vec::new();
    for i in 0..=MAX_TABLE {
        let at = addr
            .checked_add(2 * i as u16)
            .ok_or(RecordError::OutOfMemory { addr })?;
        let w: [u8; 2] = read_bytes(addr, at, byte)?;
        let entry = u16::from_le_bytes(w);
        if entry == 0 {
            return Ok(v);
        }
        if i == MAX_TABLE {
            break;
        }
        v.push(entry);
    }
    Err(RecordError::TableTooLong { addr }.into())
}

/// A table's bytes.
pub fn encode_table(entries: &[u16]) -> Vec<u8> {
    entries
        .iter()
        .chain(std::iter::once(&0))
        .flat_map(|e| e.to_le_bytes())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reader(mem: &[u8]) -> impl FnMut(u16) -> Result<u8, RecordError> + '_ {
        move |a| {
            mem.get(a as usize)
                .copied()
                .ok_or(RecordError::OutOfMemory { addr: a })
        }
    }

    #[test]
    fn records_round_trip() {
        let d = DataRecord {
            bits: 16,
            data_type: data_type::UNSIGNED,
            dir: dir::OUT,
            min: 0.0,
            max: 10.0,
            addr: 0x400,
            unit: "V".into(),
            name: "SpinOut".into(),
        };
        let m = ModeRecord {
            index: 2,
            software: true,
            name: "io_enc_ana_spin_fv".into(),
        };
        let mut mem = vec![0u8; 16];
        let at_d = mem.len() as u16;
        mem.extend(d.encode());
        let at_m = mem.len() as u16;
        mem.extend(m.encode());
        let at_t = mem.len() as u16;
        mem.extend(encode_table(&[at_d, at_m]));
        let mut r = reader(&mem);
        assert_eq!(read_table(at_t, &mut r).unwrap(), vec![at_d, at_m]);
        assert_eq!(read_record(at_d, &mut r).unwrap(), Record::Data(d.clone()));
        assert_eq!(read_record(at_m, &mut r).unwrap(), Record::Mode(m));
        assert_eq!(d.hal_name(), "spinout");
        assert!(d.is_out() && !d.is_in());
    }

    #[test]
    fn garbage_is_refused_with_a_reason() {
        let mut mem = vec![0xA0, 1, 1, 0];
        mem.extend([0u8; 10]);
        mem.extend(b"none\0");
        mem.extend([b'x'; 60]);
        mem.push(0);
        let mut r = reader(&mem);
        let e = read_record(0, &mut r).unwrap_err();
        assert_eq!(
            e,
            RecordError::BadString {
                addr: 0,
                what: "name"
            }
        );
        let e = read_record(5, &mut r).unwrap_err();
        assert!(matches!(e, RecordError::BadKind { kind: 0, .. }), "{e}");
        let ones = vec![1u8; 300];
        let mut r = reader(&ones);
        assert_eq!(
            read_table(0, &mut r).unwrap_err(),
            RecordError::TableTooLong { addr: 0 }
        );
        let end = [0xB0u8, 0, 0, 0, b'a'];
        let mut r = reader(&end);
        assert!(matches!(
            read_record(0, &mut r).unwrap_err(),
            RecordError::OutOfMemory { .. }
        ));
    }
}
