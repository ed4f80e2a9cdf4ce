//! [`Frame`]: one classic CAN 2.0 frame, as the driver and the simulator
//! pass it around: `Copy`, 16 bytes of payload and header, no allocation.
//!
//! The kernel's `struct can_frame` carries data, remote and error frames
//! in one 32-bit `can_id` with flag bits (hardware.md §6.1); here the
//! kind is an enum and the identifier a plain number, so a match on a
//! frame cannot confuse an error frame with a data frame whose
//! identifier happens to have the same low bits.

use std::fmt;

/// `can_id` flag: 29-bit identifier.
pub const CAN_EFF_FLAG: u32 = 0x8000_0000;
/// `can_id` flag: remote transmission request.
pub const CAN_RTR_FLAG: u32 = 0x4000_0000;
/// `can_id` flag: error frame.
pub const CAN_ERR_FLAG: u32 = 0x2000_0000;
/// Mask of an 11-bit identifier.
pub const CAN_SFF_MASK: u32 = 0x7FF;
/// Mask of a 29-bit identifier (and of an error frame's class bits).
pub const CAN_EFF_MASK: u32 = 0x1FFF_FFFF;

/// What kind of frame it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FrameKind {
    /// A data frame.
    Data,
    /// A remote transmission request (no data, `len` is the requested
    /// length).
    Remote,
    /// An error frame made by the local CAN controller driver: `id`
    /// holds the error classes (`CAN_ERR_*` in [`crate::regs::err`]).
    Error,
}

/// One classic CAN frame.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Frame {
    /// Data, remote or error frame.
    pub kind: FrameKind,
    /// The identifier (11 or 29 bits), or an error frame's class bits.
    pub id: u32,
    /// Whether the identifier has 29 bits.
    pub extended: bool,
    /// Data length, 0..=8.
    pub len: u8,
    /// Data bytes; those past `len` are zero.
    pub data: [u8; 8],
}

impl Frame {
    /// A data frame with an 11-bit identifier (`id` is masked to 11 bits)
    /// and the first 8 bytes of `data`.
    pub fn new(id: u16, data: &[u8]) -> Frame {
        let len = data.len().min(8);
        let mut d = [0u8; 8];
        d[..len].copy_from_slice(&data[..len]);
        Frame {
            kind: FrameKind::Data,
            id: u32::from(id) & CAN_SFF_MASK,
            extended: false,
            len: len as u8,
            data: d,
        }
    }

    /// An error frame with class bits `classes` and data `data`, as the
    /// kernel delivers it (length 8).
    pub fn error(classes: u32, data: [u8; 8]) -> Frame {
        Frame {
            kind: FrameKind::Error,
            id: classes & CAN_EFF_MASK,
            extended: false,
            len: 8,
            data,
        }
    }

    /// A remote frame asking for `len` bytes on 11-bit `id`.
    pub fn remote(id: u16, len: u8) -> Frame {
        Frame {
            kind: FrameKind::Remote,
            id: u32::from(id) & CAN_SFF_MASK,
            extended: false,
            len: len.min(8),
            data: [0; 8],
        }
    }

    /// The data bytes in use.
    pub fn payload(&self) -> &[u8] {
        &self.data[..usize::from(self.len.min(8))]
    }

    /// The 11-bit identifier of a standard data frame; None for remote,
    /// error and 29-bit frames, which CANopen's predefined connection set
    /// never uses.
    #[inline]
    pub fn cob_id(&self) -> Option<u16> {
        (self.kind == FrameKind::Data && !self.extended).then_some(self.id as u16)
    }

    /// The kernel's `can_id` word: identifier plus flag bits.
    pub fn can_id(&self) -> u32 {
        match self.kind {
            FrameKind::Error => CAN_ERR_FLAG | (self.id & CAN_EFF_MASK),
            k => {
                let mut id = if self.extended {
                    CAN_EFF_FLAG | (self.id & CAN_EFF_MASK)
                } else {
                    self.id & CAN_SFF_MASK
                };
                if k == FrameKind::Remote {
                    id |= CAN_RTR_FLAG;
                }
                id
            }
        }
    }

    /// The frame the kernel's `can_id`, length and data describe; lengths
    /// past 8 are cut to 8 (the kernel never delivers them for CAN_RAW
    /// without FD frames).
    pub fn from_raw(can_id: u32, len: u8, data: [u8; 8]) -> Frame {
        let len = len.min(8);
        let mut d = [0u8; 8];
        d[..usize::from(len)].copy_from_slice(&data[..usize::from(len)]);
        if can_id & CAN_ERR_FLAG != 0 {
            return Frame {
                kind: FrameKind::Error,
                id: can_id & CAN_EFF_MASK,
                extended: false,
                len,
                data: d,
            };
        }
        let extended = can_id & CAN_EFF_FLAG != 0;
        let remote = can_id & CAN_RTR_FLAG != 0;
        Frame {
            kind: if remote {
                FrameKind::Remote
            } else {
                FrameKind::Data
            },
            id: can_id & if extended { CAN_EFF_MASK } else { CAN_SFF_MASK },
            extended,
            len,
            data: if remote { [0; 8] } else { d },
        }
    }

    /// The longest this frame can take on the wire, in bit times: start
    /// of frame to end of the interframe space (44 + 8·len bits for a
    /// standard frame, 64 + 8·len for an extended one, plus 3 bits of
    /// interframe space), plus the worst-case stuff bits (one per four
    /// bits of the stuffed part: start of frame to the CRC). Error frames
    /// are local and take no bus time.
    pub fn wire_bits_worst(&self) -> u32 {
        if self.kind == FrameKind::Error {
            return 0;
        }
        let data_bits = if self.kind == FrameKind::Remote {
            0
        } else {
            8 * u32::from(self.len.min(8))
        };
        let (fixed, stuffed) = if self.extended {
            (67 + data_bits, 54 + data_bits)
        } else {
            (47 + data_bits, 34 + data_bits)
        };
        fixed + (stuffed - 1) / 4
    }
}

impl fmt::Debug for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl fmt::Display for Frame {
    /// candump's layout: `181   [7]  37 02 00 10 00 00 08`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            FrameKind::Error => write!(f, "ERR {:08X}  [{}]", self.id, self.len)?,
            _ if self.extended => write!(f, "{:08X}  [{}]", self.id, self.len)?,
            _ => write!(f, "{:03X}  [{}]", self.id, self.len)?,
        }
        if self.kind == FrameKind::Remote {
            return write!(f, "  remote request");
        }
        for b in self.payload() {
            write!(f, " {b:02X}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_round_trip_keeps_kind_and_id() {
        let f = Frame::new(0x181, &[0x37, 0x02, 1, 2, 3, 4, 8]);
        assert_eq!(f.can_id(), 0x181);
        assert_eq!(Frame::from_raw(f.can_id(), f.len, f.data), f);
        let r = Frame::remote(0x701, 1);
        assert_eq!(r.can_id(), 0x701 | CAN_RTR_FLAG);
        assert_eq!(Frame::from_raw(r.can_id(), 1, [9; 8]), r);
        assert_eq!(r.cob_id(), None, "remote frames are not CANopen data");
        let e = Frame::error(0x40, [0; 8]);
        assert_eq!(e.can_id(), CAN_ERR_FLAG | 0x40);
        assert_eq!(
            Frame::from_raw(e.can_id(), 8, [0; 8]).kind,
            FrameKind::Error
        );
        let x = Frame::from_raw(CAN_EFF_FLAG | 0x181, 2, [1; 8]);
        assert!(x.extended && x.cob_id().is_none());
        assert_eq!(Frame::from_raw(0x181, 200, [1; 8]).len, 8);
    }

    #[test]
    fn wire_lengths() {
        // 8 data bytes: 47 + 64 = 111 bits, stuffed part 98 bits -> 24.
        assert_eq!(Frame::new(0x181, &[0; 8]).wire_bits_worst(), 135);
        // SYNC: 47 bits + 8 stuff bits.
        assert_eq!(Frame::new(0x80, &[]).wire_bits_worst(), 55);
        assert_eq!(Frame::error(0x40, [0; 8]).wire_bits_worst(), 0);
    }

    #[test]
    fn display_is_candump_like() {
        let f = Frame::new(0x601, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]);
        assert_eq!(f.to_string(), "601  [8] 40 41 60 00 00 00 00 00");
    }
}
