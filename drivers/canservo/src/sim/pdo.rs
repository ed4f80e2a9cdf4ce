//! The simulated drive's PDO engine (hardware.md §6.7): the rules an SDO
//! write to a PDO parameter must follow, packing mapped objects into a
//! frame and unpacking a received one, and the per-PDO transmission
//! state (SYNC counting, inhibit and event timers, the last data sent).

use super::od::{Access, Od};
use crate::codes::AbortCode;
use crate::regs::obj;

/// Number of PDOs of each direction the drive has.
pub const PDOS: u16 = 4;

/// Which direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dir {
    /// Received by the drive.
    Rpdo,
    /// Sent by the drive.
    Tpdo,
}

impl Dir {
    /// The communication parameter index of PDO `n` (0-based).
    pub fn comm(self, n: u16) -> u16 {
        match self {
            Dir::Rpdo => obj::RPDO_COMM + n,
            Dir::Tpdo => obj::TPDO_COMM + n,
        }
    }

    /// The mapping index of PDO `n`.
    pub fn map(self, n: u16) -> u16 {
        match self {
            Dir::Rpdo => obj::RPDO_MAP + n,
            Dir::Tpdo => obj::TPDO_MAP + n,
        }
    }
}

/// Which PDO parameter `index` is: (direction, PDO number, is mapping).
pub fn classify(index: u16) -> Option<(Dir, u16, bool)> {
    let n = index & 0x1FF;
    if n >= PDOS {
        return None;
    }
    match index & 0xFE00 {
        0x1400 => Some((Dir::Rpdo, n, false)),
        0x1600 => Some((Dir::Rpdo, n, true)),
        0x1800 => Some((Dir::Tpdo, n, false)),
        0x1A00 => Some((Dir::Tpdo, n, true)),
        _ => None,
    }
}

/// Whether PDO `n` of `dir` is valid (COB-ID bit 31 clear).
pub fn is_valid(od: &Od, dir: Dir, n: u16) -> bool {
    od.get(dir.comm(n), 1) & obj::COB_INVALID == 0
}

/// The COB-ID of PDO `n` (11 bits).
pub fn cob_id(od: &Od, dir: Dir, n: u16) -> u16 {
    (od.get(dir.comm(n), 1) & 0x7FF) as u16
}

/// The transmission type of PDO `n`.
pub fn transmission_type(od: &Od, dir: Dir, n: u16) -> u8 {
    od.get(dir.comm(n), 2) as u8
}

/// One mapping entry: (index, sub, bits).
pub type MapEntry = (u16, u8, u8);

/// The mapped objects of PDO `n` and their total length in bytes.
pub fn mapping(od: &Od, dir: Dir, n: u16) -> ([MapEntry; 8], usize, usize) {
    let idx = dir.map(n);
    let count = (od.get(idx, 0) as usize).min(8);
    let mut out = [(0u16, 0u8, 0u8); 8];
    let mut bits = 0usize;
    for (i, slot) in out.iter_mut().enumerate().take(count) {
        let e = od.get(idx, i as u8 + 1);
        *slot = ((e >> 16) as u16, (e >> 8) as u8, e as u8);
        bits += usize::from(e as u8);
    }
    (out, count, bits.div_ceil(8))
}

/// Checks a mapping entry value for `dir`: the object exists, may be
/// mapped in that direction, and the length matches its type.
fn check_entry(od: &Od, dir: Dir, value: u32) -> Result<u8, AbortCode> {
    let (index, sub, bits) = ((value >> 16) as u16, (value >> 8) as u8, value as u8);
    let e = od.find(index, sub)?;
    let direction_ok = match dir {
        Dir::Rpdo => matches!(e.access, Access::Rw | Access::Wo),
        Dir::Tpdo => matches!(e.access, Access::Rw | Access::Ro | Access::Const),
    };
    if !e.mappable || !direction_ok {
        return Err(AbortCode::NOT_MAPPABLE);
    }
    if e.ty.bits() != bits {
        return Err(AbortCode::INCOMPATIBLE);
    }
    Ok(bits)
}

/// Checks an SDO write of `value` to PDO parameter `index:sub` against
/// the reconfiguration rules of §6.7.
pub fn check_write(od: &Od, index: u16, sub: u8, value: i64) -> Result<(), AbortCode> {
    let Some((dir, n, is_map)) = classify(index) else {
        return Ok(());
    };
    let value = value as u32;
    if !is_map {
        return match sub {
            1 => {
                let now = od.get(index, 1);
                if value & 0x2000_0000 != 0 {
                    return Err(AbortCode::INVALID_VALUE); // 29-bit: not offered
                }
                let both_valid = now & obj::COB_INVALID == 0 && value & obj::COB_INVALID == 0;
                if both_valid && (now & 0x7FF) != (value & 0x7FF) {
                    return Err(AbortCode::INVALID_VALUE);
                }
                if value & obj::COB_INVALID == 0 && value & 0x7FF == 0 {
                    return Err(AbortCode::INVALID_VALUE);
                }
                Ok(())
            }
            2 => {
                let ok = match dir {
                    Dir::Rpdo => matches!(value, 0..=240 | 254 | 255),
                    Dir::Tpdo => matches!(value, 0..=240 | 252..=255),
                };
                if ok {
                    Ok(())
                } else {
                    Err(AbortCode::INVALID_VALUE)
                }
            }
            3 if is_valid(od, dir, n) => Err(AbortCode::WRONG_STATE),
            _ => Ok(()),
        };
    }
    if is_valid(od, dir, n) {
        return Err(AbortCode::WRONG_STATE);
    }
    if sub == 0 {
        let mut bits = 0u32;
        for s in 1..=value.min(8) as u8 {
            bits += u32::from(check_entry(od, dir, od.get(index, s))?);
        }
        if bits > 64 {
            return Err(AbortCode::PDO_TOO_LONG);
        }
        return Ok(());
    }
    if od.get(index, 0) != 0 {
        return Err(AbortCode::WRONG_STATE);
    }
    check_entry(od, dir, value).map(|_| ())
}

/// Packs the mapped objects of TPDO `n` into a frame payload.
pub fn pack(od: &Od, n: u16) -> ([u8; 8], u8) {
    let (entries, count, len) = mapping(od, Dir::Tpdo, n);
    let mut data = [0u8; 8];
    let mut bit = 0usize;
    for &(index, sub, bits) in &entries[..count] {
        let v = u64::from(od.get(index, sub));
        let bytes = usize::from(bits / 8);
        let at = bit / 8;
        if at + bytes > 8 {
            break;
        }
        data[at..at + bytes].copy_from_slice(&v.to_le_bytes()[..bytes]);
        bit += usize::from(bits);
    }
    (data, len.min(8) as u8)
}

/// Unpacks a received RPDO `n` payload into its mapped objects; the
/// caller has checked the length.
pub fn unpack(od: &mut Od, n: u16, data: &[u8]) {
    let (entries, count, _) = mapping(od, Dir::Rpdo, n);
    let mut at = 0usize;
    for &(index, sub, bits) in &entries[..count] {
        let bytes = usize::from(bits / 8);
        if at + bytes > data.len() {
            break;
        }
        let mut b = [0u8; 4];
        b[..bytes.min(4)].copy_from_slice(&data[at..at + bytes.min(4)]);
        let raw = u32::from_le_bytes(b);
        let v = od
            .entry(index, sub)
            .map_or(i64::from(raw), |e| e.ty.to_i64(raw));
        od.set(index, sub, v);
        at += bytes;
    }
}

/// Runtime state of one TPDO.
#[derive(Debug, Clone, Default)]
pub struct TpdoState {
    /// SYNCs counted towards the next transmission.
    pub syncs: u32,
    /// Whether counting has started (a SYNC start value may delay it).
    pub started: bool,
    /// The data last sent, for "on change".
    pub last: Option<([u8; 8], u8)>,
    /// Time of the last transmission.
    pub last_ns: u64,
    /// Data sampled at SYNC for type 252.
    pub sampled: Option<([u8; 8], u8)>,
}

/// Runtime state of one RPDO.
#[derive(Debug, Clone, Default)]
pub struct RpdoState {
    /// Data received with a synchronous type, applied at the next SYNC.
    pub latched: Option<([u8; 8], u8)>,
}

#[cfg(test)]
mod tests {
    use super::super::dictionary::{build, Identity};
    use super::*;

    #[test]
    fn reconfiguration_follows_the_sequence() {
        let mut od = build(1, &Identity::simulated(1));
        let m = obj::TPDO_MAP;
        // Mapping a valid PDO is refused.
        assert_eq!(check_write(&od, m, 0, 0), Err(AbortCode::WRONG_STATE));
        od.set(obj::TPDO_COMM, 1, i64::from(obj::COB_INVALID | 0x181));
        assert_eq!(
            check_write(&od, m, 1, 0x6041_0010),
            Err(AbortCode::WRONG_STATE),
            "sub 0 first"
        );
        od.set(m, 0, 0);
        assert_eq!(check_write(&od, m, 1, 0x6041_0010), Ok(()));
        assert_eq!(
            check_write(&od, m, 1, 0x6041_0020),
            Err(AbortCode::INCOMPATIBLE)
        );
        assert_eq!(
            check_write(&od, m, 1, 0x1018_0120),
            Err(AbortCode::NOT_MAPPABLE)
        );
        assert_eq!(
            check_write(&od, m, 1, 0x2000_0010),
            Err(AbortCode::NO_OBJECT)
        );
        assert_eq!(
            check_write(&od, obj::RPDO_MAP, 1, 0x6041_0010),
            Err(AbortCode::WRONG_STATE),
            "RPDO1 still valid"
        );
        for s in 1..=3 {
            od.set(m, s, i64::from(obj::map_entry(0x6064, 0, 32)));
        }
        assert_eq!(check_write(&od, m, 0, 3), Err(AbortCode::PDO_TOO_LONG));
        assert_eq!(check_write(&od, m, 0, 2), Ok(()));
        // Changing the identifier of a valid PDO is refused.
        od.set(obj::TPDO_COMM, 1, 0x181);
        assert_eq!(
            check_write(&od, obj::TPDO_COMM, 1, 0x182),
            Err(AbortCode::INVALID_VALUE)
        );
        assert_eq!(
            check_write(&od, obj::TPDO_COMM, 2, 245),
            Err(AbortCode::INVALID_VALUE)
        );
        assert_eq!(
            check_write(&od, obj::RPDO_COMM, 2, 252),
            Err(AbortCode::INVALID_VALUE)
        );
    }

    #[test]
    fn pack_and_unpack() {
        let mut od = build(1, &Identity::simulated(1));
        od.set(0x6041, 0, 0x0237);
        od.set(0x6064, 0, -5);
        let (data, len) = pack(&od, 2);
        assert_eq!(
            (len, &data[..6]),
            (6, &[0x37, 0x02, 0xFB, 0xFF, 0xFF, 0xFF][..])
        );
        unpack(&mut od, 2, &[0x0F, 0x00, 0x10, 0x27, 0, 0]);
        assert_eq!((od.get(0x6040, 0), od.get_i64(0x607A, 0)), (0x0F, 10_000));
    }
}
