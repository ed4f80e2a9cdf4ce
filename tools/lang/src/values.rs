//! Parsing values typed by the user (`setp`, `sets`), as halcmd does.

use hal_core::module::{c_radix, parse_c_int};
use hal_core::{HalType, Value};

/// Why a value was refused; the Display text is halcmd's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ValueError {
    /// Not a number (or not a bit word) at all.
    #[error("invalid argument")]
    Invalid,
    /// A number the type cannot hold.
    #[error("value out of range")]
    OutOfRange,
}

/// Parses `text` as a value of type `t`.
pub fn parse_value(t: HalType, text: &str) -> Result<Value, ValueError> {
    match t {
        HalType::Bit => match text.to_ascii_uppercase().as_str() {
            "1" | "TRUE" | "ON" | "YES" => Ok(Value::Bit(true)),
            "0" | "FALSE" | "OFF" | "NO" => Ok(Value::Bit(false)),
            _ => Err(ValueError::Invalid),
        },
        // strtod's ERANGE: a number too large or too small for a double.
        HalType::Float if float_out_of_range(text) => Err(ValueError::OutOfRange),
        HalType::Float => parse_float(text)
            .map(Value::Float)
            .ok_or(ValueError::Invalid),
        HalType::S32 => parse_c_int(text, 32)
            .map(|v| Value::S32(v as i32))
            .map_err(|_| int_error(text)),
        HalType::S64 => parse_c_int(text, 64)
            .map(Value::S64)
            .map_err(|_| int_error(text)),
        HalType::U32 => parse_c_uint(text)
            .filter(|v| *v <= u32::MAX as u64)
            .map(|v| Value::U32(v as u32))
            .ok_or_else(|| int_error(text)),
        HalType::U64 => parse_c_uint(text)
            .map(Value::U64)
            .ok_or_else(|| int_error(text)),
        // A port's value is the size of its buffer, as strtoul reads it.
        HalType::Port => parse_c_uint(text)
            .filter(|v| *v <= u64::from(u32::MAX))
            .map(|v| Value::Port(v as u32))
            .ok_or(ValueError::Invalid),
    }
}

/// Why an integer was refused: a number that does not fit (also a
/// negative one for an unsigned type) or text that is no number.
fn int_error(text: &str) -> ValueError {
    let body = text.trim_start().trim_start_matches(['+', '-']);
    let numeric = match body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        Some(hex) => !hex.is_empty() && hex.chars().all(|c| c.is_ascii_hexdigit()),
        None => !body.is_empty() && body.chars().all(|c| c.is_ascii_digit()),
    };
    if numeric {
        ValueError::OutOfRange
    } else {
        ValueError::Invalid
    }
}

/// Whether `text` is a decimal number that overflows or underflows a double.
fn float_out_of_range(text: &str) -> bool {
    let Ok(v) = text.trim().parse::<f64>() else {
        return false;
    };
    let lower = text.trim().to_ascii_lowercase();
    let named = lower.contains("inf") || lower.contains("nan");
    let nonzero_digits = lower
        .split('e')
        .next()
        .is_some_and(|m| m.chars().any(|c| ('1'..='9').contains(&c)));
    (v.is_infinite() && !named) || (nonzero_digits && v.abs() < f64::MIN_POSITIVE)
}

/// A float as `strtod` reads it, the whole text required.
pub fn parse_float(text: &str) -> Option<f64> {
    let t = text.trim_start();
    if t.is_empty() {
        return None;
    }
    if let Ok(v) = t.parse::<f64>() {
        return Some(v);
    }
    // strtod also reads hexadecimal integers ("0x10").
    let (neg, body) = match t.as_bytes()[0] {
        b'-' => (true, &t[1..]),
        b'+' => (false, &t[1..]),
        _ => (false, t),
    };
    let hex = body
        .strip_prefix("0x")
        .or_else(|| body.strip_prefix("0X"))?;
    let v = u128::from_str_radix(hex, 16).ok()? as f64;
    Some(if neg { -v } else { v })
}

/// An unsigned integer, base 0 like `strtoul`, but refusing a minus sign
/// (LinuxCNC refuses negative values for unsigned pins).
fn parse_c_uint(text: &str) -> Option<u64> {
    let t = text
        .trim_start()
        .strip_prefix('+')
        .unwrap_or(text.trim_start());
    let (radix, digits) = c_radix(t);
    if digits.is_empty() || digits.starts_with(['+', '-']) {
        return None;
    }
    u64::from_str_radix(digits, radix).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_what_halcmd_accepts() {
        assert_eq!(parse_value(HalType::Bit, "TRUE"), Ok(Value::Bit(true)));
        assert_eq!(parse_value(HalType::Bit, "false"), Ok(Value::Bit(false)));
        assert_eq!(parse_value(HalType::Float, "1e-7"), Ok(Value::Float(1e-7)));
        assert_eq!(
            parse_value(HalType::Float, "-0.0").map(|v| v.to_bits()),
            Ok((-0.0f64).to_bits())
        );
        assert_eq!(parse_value(HalType::Float, "0x10"), Ok(Value::Float(16.0)));
        assert_eq!(parse_value(HalType::S32, "0xff"), Ok(Value::S32(255)));
        assert_eq!(
            parse_value(HalType::S32, "-2147483648"),
            Ok(Value::S32(i32::MIN))
        );
        assert_eq!(
            parse_value(HalType::U32, "4294967295"),
            Ok(Value::U32(u32::MAX))
        );
        assert_eq!(
            parse_value(HalType::U64, "18446744073709551615"),
            Ok(Value::U64(u64::MAX))
        );
        assert_eq!(
            parse_value(HalType::S64, "-9223372036854775808"),
            Ok(Value::S64(i64::MIN))
        );
    }

    #[test]
    fn refuses_bad_values() {
        for (t, s) in [
            (HalType::Bit, "2"),
            (HalType::Bit, "maybe"),
            (HalType::Float, "abc"),
            (HalType::Float, "1.0x"),
            (HalType::Float, ""),
            (HalType::S32, "2147483648"),
            (HalType::U32, "-1"),
            (HalType::U32, "4294967296"),
            (HalType::U64, "-0"),
            (HalType::S64, "9223372036854775808"),
        ] {
            assert!(parse_value(t, s).is_err(), "{t} {s:?} accepted");
        }
        assert_eq!(parse_value(HalType::Bit, "2"), Err(ValueError::Invalid));
        assert_eq!(parse_value(HalType::Float, "abc"), Err(ValueError::Invalid));
        assert_eq!(
            parse_value(HalType::S32, "2147483648"),
            Err(ValueError::OutOfRange)
        );
        assert_eq!(parse_value(HalType::U32, "-1"), Err(ValueError::OutOfRange));
        assert_eq!(parse_value(HalType::S32, "12abc"), Err(ValueError::Invalid));
        assert_eq!(
            parse_value(HalType::Float, "1e400"),
            Err(ValueError::OutOfRange)
        );
        assert_eq!(
            parse_value(HalType::Float, "1e-400"),
            Err(ValueError::OutOfRange)
        );
        assert_eq!(
            parse_value(HalType::Float, "-inf"),
            Ok(Value::Float(f64::NEG_INFINITY))
        );
        assert_eq!(parse_value(HalType::Bit, "Yes"), Ok(Value::Bit(true)));
        assert_eq!(parse_value(HalType::Bit, "off"), Ok(Value::Bit(false)));
    }
}
