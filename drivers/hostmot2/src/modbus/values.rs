//! Register data to pin values and back: the byte orders (`_AB` ..
//! `_HGFEDCBA`, and the 8-bit `A`/`B` halves), half/single/double floats,
//! clamping, and the scale/offset pins, as hm2_modbus documents them.

use super::mbccb::{pinf, HalType, ModbusType, PinSpec};

/// A pin's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// bit
    Bit(bool),
    /// float
    Float(f64),
    /// s32
    S32(i32),
    /// u32
    U32(u32),
    /// s64
    S64(i64),
    /// u64
    U64(u64),
}

impl Value {
    /// The zero of a HAL type.
    pub fn zero(t: HalType) -> Value {
        match t {
            HalType::Bit => Value::Bit(false),
            HalType::Float => Value::Float(0.0),
            HalType::S32 => Value::S32(0),
            HalType::U32 => Value::U32(0),
            HalType::S64 => Value::S64(0),
            HalType::U64 => Value::U64(0),
        }
    }
}

/// Wire positions of the value's big-endian bytes, per byte-order code
/// (0 AB .. 13 HGFEDCBA): wire byte i is big-endian byte `ORDER[code][i]`.
const ORDER: [&[usize]; 14] = [
    &[0, 1],
    &[1, 0],
    &[0, 1, 2, 3],
    &[1, 0, 3, 2],
    &[2, 3, 0, 1],
    &[3, 2, 1, 0],
    &[0, 1, 2, 3, 4, 5, 6, 7],
    &[1, 0, 3, 2, 5, 4, 7, 6],
    &[2, 3, 0, 1, 6, 7, 4, 5],
    &[3, 2, 1, 0, 7, 6, 5, 4],
    &[4, 5, 6, 7, 0, 1, 2, 3],
    &[5, 4, 7, 6, 1, 0, 3, 2],
    &[6, 7, 4, 5, 2, 3, 0, 1],
    &[7, 6, 5, 4, 3, 2, 1, 0],
];

/// A register value as read, in all three readings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Raw {
    /// As unsigned (masked to the type's width).
    pub u: u64,
    /// As signed (sign-extended).
    pub s: i64,
    /// As float.
    pub f: f64,
}

fn half_to_f64(h: u16) -> f64 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = (h >> 10) & 0x1F;
    let man = f64::from(h & 0x3FF);
    sign * match exp {
        0 => man * 2f64.powi(-24),
        0x1F if man == 0.0 => f64::INFINITY,
        0x1F => f64::NAN,
        e => (1.0 + man / 1024.0) * 2f64.powi(i32::from(e) - 15),
    }
}

fn f64_to_half(v: f64) -> u16 {
    if v.is_nan() {
        return 0x7E00;
    }
    let sign = if v.is_sign_negative() { 0x8000 } else { 0 };
    let a = v.abs().min(65504.0);
    if a < 2f64.powi(-24) {
        return sign;
    }
    if a < 2f64.powi(-14) {
        return sign | (a / 2f64.powi(-24)).round() as u16;
    }
    let e = a.log2().floor() as i32;
    let m = ((a / 2f64.powi(e) - 1.0) * 1024.0).round() as u16;
    let (e, m) = if m == 1024 { (e + 1, 0) } else { (e, m) };
    sign | (((e + 15) as u16) << 10) | m
}

/// Reads the value of type `t` at the start of `b` (register data).
pub fn decode(t: ModbusType, b: &[u8]) -> Raw {
    let code = t.order() as usize;
    let (be, width): ([u8; 8], u32) = if code >= 14 {
        let byte = if code == 14 { b[1] } else { b[0] };
        let mut be = [0; 8];
        be[7] = byte;
        (be, 8)
    } else {
        let ord = ORDER[code];
        let n = ord.len();
        let mut v = [0u8; 8];
        for (i, &p) in ord.iter().enumerate() {
            v[8 - n + p] = b[i];
        }
        (v, 8 * n as u32)
    };
    let u = u64::from_be_bytes(be);
    let s = if width == 64 {
        u as i64
    } else {
        ((u << (64 - width)) as i64) >> (64 - width)
    };
    let f = match (t.kind(), width) {
        (2, 16) => half_to_f64(u as u16),
        (2, 32) => f64::from(f32::from_bits(u as u32)),
        (2, 64) => f64::from_bits(u),
        (1, _) => s as f64,
        _ => u as f64,
    };
    Raw { u, s, f }
}

/// The value to send, before its type's conversion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Send {
    /// Unsigned.
    U(u64),
    /// Signed.
    S(i64),
    /// Float.
    F(f64),
}

/// Writes `v` as type `t` into `out` (2 bytes per register), clamping to
/// the type's range when `clamp` is set (otherwise keeping the low bits).
pub fn encode(t: ModbusType, v: Send, clamp: bool, out: &mut [u8]) {
    let code = t.order() as usize;
    let bits = if code >= 14 {
        8
    } else {
        8 * ORDER[code].len() as u32
    };
    let word: u64 = match t.kind() {
        2 => {
            let f = match v {
                Send::U(u) => u as f64,
                Send::S(s) => s as f64,
                Send::F(f) => f,
            };
            match bits {
                16 => u64::from(f64_to_half(f)),
                32 => {
                    let f = if clamp {
                        f.clamp(-f64::from(f32::MAX), f64::from(f32::MAX))
                    } else {
                        f
                    };
                    u64::from((f as f32).to_bits())
                }
                _ => f.to_bits(),
            }
        }
        1 => {
            let s = match v {
                Send::U(u) => u.min(i64::MAX as u64) as i64,
                Send::S(s) => s,
                Send::F(f) => f as i64,
            };
            let (lo, hi) = if bits == 64 {
                (i64::MIN, i64::MAX)
            } else {
                (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
            };
            (if clamp { s.clamp(lo, hi) } else { s }) as u64
        }
        _ => {
            let u = match v {
                Send::U(u) => u,
                Send::S(s) => s.max(0) as u64,
                Send::F(f) => f as u64,
            };
            let max = if bits == 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            };
            if clamp {
                u.min(max)
            } else {
                u
            }
        }
    };
    let be = word.to_be_bytes();
    if code >= 14 {
        let byte = be[7];
        out[0] = if code == 15 { byte } else { 0 };
        out[1] = if code == 14 { byte } else { 0 };
        return;
    }
    let ord = ORDER[code];
    let n = ord.len();
    for (i, &p) in ord.iter().enumerate() {
        out[i] = be[8 - n + p];
    }
}

/// A read register value onto its pin, and the scaled output when the
/// pin has one: `(raw - offset) * scale`.
pub fn to_pin(spec: &PinSpec, raw: Raw, offset: Value, scale: f64) -> (Value, Option<f64>) {
    let clamp = spec.flags & pinf::CLAMP != 0;
    let kind = spec.mtype.kind();
    let as_f = match kind {
        0 => raw.u as f64,
        1 => raw.s as f64,
        _ => raw.f,
    };
    let int = |lo: i128, hi: i128| -> i128 {
        let v: i128 = match kind {
            0 => raw.u.into(),
            1 => raw.s.into(),
            _ if raw.f.is_nan() => 0,
            _ => raw.f as i128,
        };
        if clamp {
            v.clamp(lo, hi)
        } else {
            v
        }
    };
    let value = match spec.htype {
        HalType::Bit => Value::Bit(if kind == 2 { raw.f != 0.0 } else { raw.u != 0 }),
        HalType::Float => Value::Float(as_f),
        HalType::S32 => Value::S32(int(i32::MIN.into(), i32::MAX.into()) as i32),
        HalType::U32 => Value::U32(int(0, u32::MAX.into()) as u32),
        HalType::S64 => Value::S64(int(i64::MIN.into(), i64::MAX.into()) as i64),
        HalType::U64 => Value::U64(int(0, u64::MAX.into()) as u64),
    };
    let scaled = (spec.flags & pinf::SCALE != 0
        && matches!(spec.htype, HalType::Float | HalType::S32 | HalType::S64))
    .then(|| {
        let d = match (kind, offset) {
            (0, Value::U64(o)) => raw.u.wrapping_sub(o) as i64 as f64,
            (1, Value::S64(o)) => raw.s.wrapping_sub(o) as f64,
            (_, Value::Float(o)) => as_f - o,
            _ => as_f,
        };
        d * scale
    });
    (value, scaled)
}

/// The offset pin's type for a pin with scaling: for read pins it
/// follows the Modbus type (u64, s64 or float), for write pins the pin's
/// own type widened (s32 stays s32).
pub fn offset_type(spec: &PinSpec, read: bool) -> HalType {
    if read {
        match spec.mtype.kind() {
            0 => HalType::U64,
            1 => HalType::S64,
            _ => HalType::Float,
        }
    } else {
        spec.htype
    }
}

/// A write pin's value as sent: `(pin - offset) * scale` when scaled.
pub fn from_pin(spec: &PinSpec, pin: Value, offset: Value, scale: f64) -> Send {
    let scaled = spec.flags & pinf::SCALE != 0;
    match pin {
        Value::Bit(b) => Send::U(u64::from(b)),
        Value::U32(u) => Send::U(u.into()),
        Value::U64(u) => Send::U(u),
        Value::S32(s) if scaled => {
            let o = if let Value::S32(o) = offset {
                i64::from(o)
            } else {
                0
            };
            Send::F((i64::from(s) - o) as f64 * scale)
        }
        Value::S64(s) if scaled => {
            let o = if let Value::S64(o) = offset { o } else { 0 };
            Send::F(s.wrapping_sub(o) as f64 * scale)
        }
        Value::Float(f) if scaled => {
            let o = if let Value::Float(o) = offset { o } else { 0.0 };
            Send::F((f - o) * scale)
        }
        Value::S32(s) => Send::S(s.into()),
        Value::S64(s) => Send::S(s),
        Value::Float(f) => Send::F(f),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_orders_round_trip_and_match_their_names() {
        let mut b = [0u8; 8];
        encode(ModbusType(0x02), Send::U(0x11223344), true, &mut b);
        assert_eq!(&b[..4], &[0x11, 0x22, 0x33, 0x44]);
        encode(ModbusType(0x04), Send::U(0x11223344), true, &mut b);
        assert_eq!(&b[..4], &[0x33, 0x44, 0x11, 0x22]);
        encode(ModbusType(0x0D), Send::U(0x0102030405060708), true, &mut b);
        assert_eq!(b, [8, 7, 6, 5, 4, 3, 2, 1]);
        for code in 0..16u8 {
            for kind in [0u8, 0x10] {
                let t = ModbusType(kind | code);
                encode(t, Send::S(-5), false, &mut b);
                let r = decode(t, &b);
                if kind == 0x10 {
                    assert_eq!(r.s, -5, "{t:?}");
                }
            }
        }
    }

    #[test]
    fn floats_of_every_width_read_back() {
        let mut b = [0u8; 8];
        for (t, v) in [
            (0x20u8, 1.5f64),
            (0x22, 0.53),
            (0x26, 99.999),
            (0x25, -2.25),
        ] {
            encode(ModbusType(t), Send::F(v), true, &mut b);
            let r = decode(ModbusType(t), &b);
            assert!(
                (r.f - v).abs() < 1e-3 * v.abs().max(1.0),
                "{t:#x}: {v} -> {}",
                r.f
            );
        }
        // The man page's example: 0.53 as F_ABCD is 0x3f07 0xae14.
        encode(ModbusType(0x22), Send::F(0.53), true, &mut b);
        assert_eq!(&b[..4], &[0x3f, 0x07, 0xae, 0x14]);
    }

    #[test]
    fn clamping_saturates_and_its_absence_truncates() {
        let mut b = [0u8; 2];
        encode(ModbusType(0x00), Send::U(70_000), true, &mut b);
        assert_eq!(b, [0xFF, 0xFF]);
        encode(ModbusType(0x00), Send::U(70_000), false, &mut b);
        assert_eq!(u16::from_be_bytes(b), (70_000u32 & 0xFFFF) as u16);
        encode(ModbusType(0x10), Send::S(-40_000), true, &mut b);
        assert_eq!(i16::from_be_bytes(b), i16::MIN);
    }
}
