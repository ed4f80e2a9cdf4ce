//! Typed SDO values as IgH's `ethercat upload`/`download` name them:
//! `bool`, `int8` .. `int64`, `uint8` .. `uint64`, `float`, `double`,
//! `string`, `octet_string`. Values are little-endian on the wire.

use crate::error::{Error, Result};

/// A data type of `--type`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueType {
    /// One byte, 0 or 1.
    Bool,
    /// Signed integer of that many bytes.
    Int(u8),
    /// Unsigned integer of that many bytes.
    Uint(u8),
    /// IEEE single.
    Float,
    /// IEEE double.
    Double,
    /// Text.
    String,
    /// Bytes, written as hexadecimal pairs.
    OctetString,
}

/// The type names `--type` takes.
pub const TYPE_NAMES: &str =
    "bool, int8, int16, int32, int64, uint8, uint16, uint32, uint64, float, double, string, octet_string";

impl ValueType {
    /// The type named `s`.
    pub fn parse(s: &str) -> Result<ValueType> {
        Ok(match s {
            "bool" => ValueType::Bool,
            "int8" => ValueType::Int(1),
            "int16" => ValueType::Int(2),
            "int32" => ValueType::Int(4),
            "int64" => ValueType::Int(8),
            "uint8" => ValueType::Uint(1),
            "uint16" => ValueType::Uint(2),
            "uint32" => ValueType::Uint(4),
            "uint64" => ValueType::Uint(8),
            "float" => ValueType::Float,
            "double" => ValueType::Double,
            "string" => ValueType::String,
            "octet_string" => ValueType::OctetString,
            _ => {
                return Err(Error::malformed(
                    format!("data type '{s}'"),
                    format!("not one of {TYPE_NAMES}"),
                ))
            }
        })
    }

    /// The bytes of `text` as this type; an error says why it does not fit.
    pub fn encode(self, text: &str) -> Result<Vec<u8>> {
        let bad = |why: String| Error::malformed(format!("value '{text}'"), why);
        let int = |t: &str| -> Option<i128> {
            let (neg, t) = match t.strip_prefix('-') {
                Some(r) => (true, r),
                None => (false, t),
            };
            let v = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
                Some(h) => i128::from_str_radix(h, 16).ok()?,
                None => t.parse::<i128>().ok()?,
            };
            Some(if neg { -v } else { v })
        };
        Ok(match self {
            ValueType::Bool => match text {
                "0" | "false" => vec![0],
                "1" | "true" => vec![1],
                _ => return Err(bad("bool is 0, 1, true or false".into())),
            },
            ValueType::Int(n) | ValueType::Uint(n) => {
                let v = int(text).ok_or_else(|| bad("not an integer".into()))?;
                let bits = u32::from(n) * 8;
                let (lo, hi) = if matches!(self, ValueType::Int(_)) {
                    (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
                } else {
                    (0, (1i128 << bits) - 1)
                };
                if v < lo || v > hi {
                    return Err(bad(format!("out of range {lo}..={hi}")));
                }
                v.to_le_bytes()[..usize::from(n)].to_vec()
            }
            ValueType::Float => {
                let v: f32 = text.parse().map_err(|_| bad("not a number".into()))?;
                v.to_le_bytes().to_vec()
            }
            ValueType::Double => {
                let v: f64 = text.parse().map_err(|_| bad("not a number".into()))?;
                v.to_le_bytes().to_vec()
            }
            ValueType::String => text.as_bytes().to_vec(),
            ValueType::OctetString => {
                let hex: String = text.chars().filter(|c| !c.is_whitespace()).collect();
                if hex.len() % 2 != 0 {
                    return Err(bad("an odd number of hexadecimal digits".into()));
                }
                (0..hex.len())
                    .step_by(2)
                    .map(|i| u8::from_str_radix(&hex[i..i + 2], 16))
                    .collect::<std::result::Result<Vec<u8>, _>>()
                    .map_err(|_| bad("not hexadecimal".into()))?
            }
        })
    }

    /// `bytes` as text of this type; an error when the size does not fit.
    pub fn format(self, bytes: &[u8]) -> Result<String> {
        let need = match self {
            ValueType::Bool => Some(1),
            ValueType::Int(n) | ValueType::Uint(n) => Some(usize::from(n)),
            ValueType::Float => Some(4),
            ValueType::Double => Some(8),
            _ => None,
        };
        if let Some(n) = need {
            if bytes.len() != n {
                return Err(Error::malformed(
                    "uploaded data",
                    format!("{} bytes, the type has {n}", bytes.len()),
                ));
            }
        }
        let mut wide = [0u8; 8];
        wide[..bytes.len().min(8)].copy_from_slice(&bytes[..bytes.len().min(8)]);
        let raw = u64::from_le_bytes(wide);
        Ok(match self {
            ValueType::Bool => u8::from(raw != 0).to_string(),
            ValueType::Uint(n) => format!("{raw:#0w$x} {raw}", w = usize::from(n) * 2 + 2),
            ValueType::Int(n) => {
                let shift = 64 - u32::from(n) * 8;
                let v = ((raw << shift) as i64) >> shift;
                format!("{raw:#0w$x} {v}", w = usize::from(n) * 2 + 2)
            }
            ValueType::Float => {
                f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]).to_string()
            }
            ValueType::Double => f64::from_le_bytes(wide).to_string(),
            ValueType::String => String::from_utf8_lossy(bytes)
                .trim_end_matches('\0')
                .to_string(),
            ValueType::OctetString => hex(bytes),
        })
    }

    /// A type to show `bytes` with when none was given: text when there
    /// are at least four printable characters and nothing else but
    /// trailing NULs (names and versions, such as 0x1008), else an
    /// unsigned integer of 1, 2, 4 or 8 bytes, else bytes. Integers whose
    /// four bytes all happen to be printable show as text: give `--type`.
    pub fn guess(bytes: &[u8]) -> ValueType {
        let text_len = bytes
            .iter()
            .take_while(|b| b.is_ascii_graphic() || **b == b' ')
            .count();
        let rest_nul = bytes[text_len..].iter().all(|b| *b == 0);
        if text_len >= 4 && rest_nul {
            return ValueType::String;
        }
        match bytes.len() {
            1 | 2 | 4 | 8 => ValueType::Uint(bytes.len() as u8),
            _ => ValueType::OctetString,
        }
    }
}

/// Bytes as space-separated hexadecimal pairs.
pub fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_and_format_round_trip() {
        let t = ValueType::parse("int16").unwrap();
        assert_eq!(t.encode("-2").unwrap(), vec![0xFE, 0xFF]);
        assert_eq!(t.format(&[0xFE, 0xFF]).unwrap(), "0xfffe -2");
        let u = ValueType::parse("uint32").unwrap();
        assert_eq!(
            u.format(&u.encode("0x539").unwrap()).unwrap(),
            "0x00000539 1337"
        );
        assert_eq!(
            ValueType::Double
                .format(&ValueType::Double.encode("2.5").unwrap())
                .unwrap(),
            "2.5"
        );
        assert_eq!(
            ValueType::OctetString.encode("de ad").unwrap(),
            vec![0xDE, 0xAD]
        );
        assert_eq!(ValueType::guess(b"SimServo"), ValueType::String);
        assert_eq!(ValueType::guess(b"EL1008\0\0"), ValueType::String);
        assert_eq!(ValueType::guess(&[0x39, 5, 0, 0]), ValueType::Uint(4));
        assert_eq!(ValueType::guess(&[1, 2, 3]), ValueType::OctetString);
    }

    #[test]
    fn bad_values_say_why() {
        let e = |t: &str, v: &str| {
            ValueType::parse(t)
                .unwrap()
                .encode(v)
                .unwrap_err()
                .to_string()
        };
        assert!(e("uint8", "256").contains("out of range 0..=255"));
        assert!(e("int8", "-129").contains("out of range -128..=127"));
        assert!(e("bool", "yes").contains("bool is"));
        assert!(e("octet_string", "abc").contains("odd number"));
        assert!(ValueType::parse("u32")
            .unwrap_err()
            .to_string()
            .contains("not one of"));
        assert!(ValueType::Uint(2)
            .format(&[1])
            .unwrap_err()
            .to_string()
            .contains("1 bytes, the type has 2"));
    }
}
