//! The evdev user API (`linux/input.h`): the `input_event` record that
//! reads and writes of an event node carry, the event types, the ioctl
//! request numbers hal_input uses, and the decoding of what those ioctls
//! fill in (`input_id`, `input_absinfo`, capability bitmaps).

use crate::error::{InputError, Result};

/// `EV_SYN`: a report boundary (and `SYN_DROPPED`).
pub const EV_SYN: u16 = 0x00;
/// `EV_KEY`: keys and buttons.
pub const EV_KEY: u16 = 0x01;
/// `EV_REL`: relative axes (mice, jog wheels).
pub const EV_REL: u16 = 0x02;
/// `EV_ABS`: absolute axes (joysticks, knobs).
pub const EV_ABS: u16 = 0x03;
/// `EV_MSC`: miscellaneous (scan codes).
pub const EV_MSC: u16 = 0x04;
/// `EV_LED`: LEDs (written to the device).
pub const EV_LED: u16 = 0x11;
/// `EV_SND`: sounds.
pub const EV_SND: u16 = 0x12;
/// The largest event type (`EV_MAX`).
pub const EV_MAX: u16 = 0x1f;

/// `SYN_REPORT`: the end of one report.
pub const SYN_REPORT: u16 = 0;
/// `SYN_DROPPED`: the kernel's buffer overflowed; events were lost.
pub const SYN_DROPPED: u16 = 3;

/// The largest code of each type the kernel has (`KEY_MAX`...); bitmaps
/// are asked for with room for these.
pub const KEY_MAX: u16 = 0x2ff;
/// `ABS_MAX`.
pub const ABS_MAX: u16 = 0x3f;
/// `REL_MAX`.
pub const REL_MAX: u16 = 0x0f;
/// `LED_MAX`.
pub const LED_MAX: u16 = 0x0f;

/// Bytes of one `input_event`: a `struct timeval` of two C longs (or the
/// kernel's two `__kernel_ulong_t` words on 32-bit), `__u16 type`,
/// `__u16 code`, `__s32 value`: 24 bytes on 64-bit, 16 on 32-bit.
pub const EVENT_SIZE: usize = 2 * std::mem::size_of::<libc::c_ulong>() + 8;
/// Where `type` starts in the record.
const TYPE_AT: usize = 2 * std::mem::size_of::<libc::c_ulong>();

/// One event, without its time stamp (hal_input does not use it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Event {
    /// `EV_*`.
    pub kind: u16,
    /// The key, axis or LED code.
    pub code: u16,
    /// The value: 0/1/2 (release, press, repeat) for keys, the position
    /// of an absolute axis, the motion of a relative one.
    pub value: i32,
}

impl Event {
    /// Decodes one record (native byte order, as the kernel writes it).
    pub fn from_record(rec: &[u8; EVENT_SIZE]) -> Event {
        let u16_at = |i: usize| u16::from_ne_bytes([rec[i], rec[i + 1]]);
        Event {
            kind: u16_at(TYPE_AT),
            code: u16_at(TYPE_AT + 2),
            value: i32::from_ne_bytes([
                rec[TYPE_AT + 4],
                rec[TYPE_AT + 5],
                rec[TYPE_AT + 6],
                rec[TYPE_AT + 7],
            ]),
        }
    }

    /// The record for a write to the device (time zero: the kernel
    /// stamps events itself).
    pub fn to_record(self) -> [u8; EVENT_SIZE] {
        let mut rec = [0u8; EVENT_SIZE];
        rec[TYPE_AT..TYPE_AT + 2].copy_from_slice(&self.kind.to_ne_bytes());
        rec[TYPE_AT + 2..TYPE_AT + 4].copy_from_slice(&self.code.to_ne_bytes());
        rec[TYPE_AT + 4..TYPE_AT + 8].copy_from_slice(&self.value.to_ne_bytes());
        rec
    }
}

/// Decodes what one `read(2)` of an event node returned into `out`
/// (cleared first). The kernel hands out whole records only, so a
/// length that is not a multiple of [`EVENT_SIZE`] is refused, with its
/// length, and nothing is decoded.
pub fn parse_events(bytes: &[u8], out: &mut Vec<Event>) -> Result<()> {
    out.clear();
    if bytes.len() % EVENT_SIZE != 0 {
        return Err(InputError::PartialRecord {
            len: bytes.len(),
            record: EVENT_SIZE,
        });
    }
    for chunk in bytes.chunks_exact(EVENT_SIZE) {
        let mut rec = [0u8; EVENT_SIZE];
        rec.copy_from_slice(chunk);
        out.push(Event::from_record(&rec));
    }
    Ok(())
}

/// `struct input_id`: bus type, vendor, product, version.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct InputId {
    /// `BUS_*`.
    pub bustype: u16,
    /// Vendor id.
    pub vendor: u16,
    /// Product id.
    pub product: u16,
    /// Version.
    pub version: u16,
}

/// Bytes of `struct input_id`.
pub const INPUT_ID_SIZE: usize = 8;

impl InputId {
    /// Decodes what `EVIOCGID` filled in.
    pub fn from_bytes(b: &[u8; INPUT_ID_SIZE]) -> InputId {
        let w = |i: usize| u16::from_ne_bytes([b[2 * i], b[2 * i + 1]]);
        InputId {
            bustype: w(0),
            vendor: w(1),
            product: w(2),
            version: w(3),
        }
    }
}

/// `struct input_absinfo`: an absolute axis's value and range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AbsInfo {
    /// The current position.
    pub value: i32,
    /// The smallest position.
    pub minimum: i32,
    /// The largest position.
    pub maximum: i32,
    /// Noise the kernel filters out.
    pub fuzz: i32,
    /// The dead band around the centre.
    pub flat: i32,
    /// Units per millimetre (or per radian).
    pub resolution: i32,
}

/// Bytes of `struct input_absinfo`.
pub const ABSINFO_SIZE: usize = 24;

impl AbsInfo {
    /// Decodes what `EVIOCGABS` filled in.
    pub fn from_bytes(b: &[u8; ABSINFO_SIZE]) -> AbsInfo {
        let w = |i: usize| i32::from_ne_bytes([b[4 * i], b[4 * i + 1], b[4 * i + 2], b[4 * i + 3]]);
        AbsInfo {
            value: w(0),
            minimum: w(1),
            maximum: w(2),
            fuzz: w(3),
            flat: w(4),
            resolution: w(5),
        }
    }
}

/// The codes whose bits are set in a capability bitmap (`EVIOCGBIT`,
/// `EVIOCGKEY`: bit `n` is bit `n % 8` of byte `n / 8`), up to `max`.
pub fn bits_set(bitmap: &[u8], max: u16) -> Vec<u16> {
    let mut codes = Vec::new();
    for (i, byte) in bitmap.iter().enumerate() {
        for bit in 0..8 {
            if byte & (1 << bit) == 0 {
                continue;
            }
            match u16::try_from(i * 8 + bit) {
                Ok(code) if code <= max => codes.push(code),
                _ => return codes,
            }
        }
    }
    codes
}

/// Bytes of a bitmap with room for codes `0..=max`.
pub const fn bitmap_len(max: u16) -> usize {
    (max as usize) / 8 + 1
}

const IOC_WRITE: u64 = 1;
const IOC_READ: u64 = 2;

/// `_IOC(dir, 'E', nr, size)`.
const fn ioc(dir: u64, nr: u64, size: usize) -> u64 {
    (dir << 30) | ((size as u64) << 16) | ((b'E' as u64) << 8) | nr
}

/// `EVIOCGID`: the device's `input_id`.
pub const EVIOCGID: u64 = ioc(IOC_READ, 0x02, INPUT_ID_SIZE);

/// `EVIOCGNAME(len)`: the device's name.
pub const fn eviocgname(len: usize) -> u64 {
    ioc(IOC_READ, 0x06, len)
}

/// `EVIOCGPHYS(len)`: where the device is connected.
pub const fn eviocgphys(len: usize) -> u64 {
    ioc(IOC_READ, 0x07, len)
}

/// `EVIOCGKEY(len)`: the keys held now.
pub const fn eviocgkey(len: usize) -> u64 {
    ioc(IOC_READ, 0x18, len)
}

/// `EVIOCGBIT(ev, len)`: the codes of type `ev` the device has (`ev` 0:
/// the types it has).
pub const fn eviocgbit(ev: u16, len: usize) -> u64 {
    ioc(IOC_READ, 0x20 + ev as u64, len)
}

/// `EVIOCGABS(abs)`: an absolute axis's `input_absinfo`.
pub const fn eviocgabs(abs: u16) -> u64 {
    ioc(IOC_READ, 0x40 + abs as u64, ABSINFO_SIZE)
}

/// `EVIOCGRAB`: exclusive access (argument 1) or its release (0).
pub const EVIOCGRAB: u64 = ioc(IOC_WRITE, 0x90, std::mem::size_of::<libc::c_int>());

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn request_numbers_are_the_kernels() {
        assert_eq!(EVIOCGID, 0x8008_4502);
        assert_eq!(eviocgname(256), 0x8100_4506);
        assert_eq!(eviocgphys(256), 0x8100_4507);
        assert_eq!(eviocgkey(96), 0x8060_4518);
        assert_eq!(eviocgbit(EV_KEY, 96), 0x8060_4521);
        assert_eq!(eviocgabs(0), 0x8018_4540);
        assert_eq!(eviocgabs(ABS_MAX), 0x8018_457f);
        assert_eq!(EVIOCGRAB, 0x4004_4590);
    }

    #[test]
    fn records_round_trip_and_partial_reads_are_refused() {
        let e = Event {
            kind: EV_REL,
            code: 8,
            value: -3,
        };
        let rec = e.to_record();
        assert_eq!(Event::from_record(&rec), e);
        let mut bytes = rec.to_vec();
        bytes.extend_from_slice(
            &Event {
                kind: EV_SYN,
                code: 0,
                value: 0,
            }
            .to_record(),
        );
        let mut out = Vec::new();
        parse_events(&bytes, &mut out).unwrap();
        assert_eq!(out.len(), 2);
        assert_eq!(out[0], e);
        let err = parse_events(&bytes[..EVENT_SIZE + 3], &mut out).unwrap_err();
        assert!(
            err.to_string().contains(&format!("{}", EVENT_SIZE + 3)),
            "{err}"
        );
        assert!(out.is_empty());
    }

    #[test]
    fn bitmaps_list_their_codes_up_to_the_limit() {
        assert_eq!(bits_set(&[0b1000_0101, 0x01], 0xff), vec![0, 2, 7, 8]);
        assert_eq!(bits_set(&[0xff], 3), vec![0, 1, 2, 3]);
        assert!(bits_set(&[], 10).is_empty());
        assert_eq!(bitmap_len(KEY_MAX), 96);
    }

    #[test]
    fn absinfo_and_id_decode() {
        let mut b = [0u8; ABSINFO_SIZE];
        for (i, v) in [5i32, -10, 10, 1, 2, 3].iter().enumerate() {
            b[4 * i..4 * i + 4].copy_from_slice(&v.to_ne_bytes());
        }
        let a = AbsInfo::from_bytes(&b);
        assert_eq!(
            (a.value, a.minimum, a.maximum, a.fuzz, a.flat),
            (5, -10, 10, 1, 2)
        );
        let mut id = [0u8; INPUT_ID_SIZE];
        for (i, v) in [3u16, 0x046d, 0xc21d, 0x111].iter().enumerate() {
            id[2 * i..2 * i + 2].copy_from_slice(&v.to_ne_bytes());
        }
        let id = InputId::from_bytes(&id);
        assert_eq!((id.bustype, id.vendor, id.product), (3, 0x046d, 0xc21d));
    }
}
