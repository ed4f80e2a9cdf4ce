//! The text side of sampler and streamer FIFOs: finding a channel's
//! columns, printing sampled records and parsing lines to stream.

use hal_components::infra::columns::{fifo_name, pin_name};
use hal_core::{HalType, Instance, RingReader, RingWriter, Value};
use hal_lang::fmt_f;
use hal_lang::parse_float;

use crate::error::ScopeError;

/// The column types of channel `chan` of `module` (`sampler` or
/// `streamer`), read from its `pin.M` pins, looked up one by one.
pub fn columns(
    inst: &Instance,
    module: &'static str,
    chan: usize,
) -> Result<Vec<HalType>, ScopeError> {
    let mut cols = Vec::new();
    while let Some(p) = inst.pin(&pin_name(module, chan, cols.len()))? {
        cols.push(p.hal_type);
    }
    if cols.is_empty() {
        return Err(ScopeError::NoChannel { module, chan });
    }
    Ok(cols)
}

/// Opens the FIFO of channel `chan` of `module` with `open` and checks
/// that its records have a word for the sample number and one per column.
fn open_channel<R>(
    inst: &Instance,
    module: &'static str,
    chan: usize,
    open: fn(&Instance, &str) -> hal_core::Result<R>,
    width: fn(&R) -> usize,
) -> Result<(R, Vec<HalType>), ScopeError> {
    let cols = columns(inst, module, chan)?;
    let ring = open(inst, &fifo_name(module, chan))?;
    if width(&ring) != cols.len() + 1 {
        return Err(ScopeError::FifoMismatch { module, chan });
    }
    Ok((ring, cols))
}

/// Opens the FIFO of a sampler channel for reading.
pub fn open_sampler(
    inst: &Instance,
    chan: usize,
) -> Result<(RingReader, Vec<HalType>), ScopeError> {
    open_channel(inst, "sampler", chan, RingReader::open, RingReader::width)
}

/// Opens the FIFO of a streamer channel for writing.
pub fn open_streamer(
    inst: &Instance,
    chan: usize,
) -> Result<(RingWriter, Vec<HalType>), ScopeError> {
    open_channel(inst, "streamer", chan, RingWriter::open, RingWriter::width)
}

/// One sampled record as halsampler prints it: each value followed by a
/// space (floats `%f`, bits 0/1, integers in decimal), then a newline;
/// with `tag`, the sample number minus one first.
pub fn format_record(record: &[u64], cols: &[HalType], tag: bool) -> String {
    let mut line = String::new();
    if tag {
        line.push_str(&format!("{} ", record[0].wrapping_sub(1) as u32));
    }
    for (t, bits) in cols.iter().zip(&record[1..]) {
        line.push_str(&format_value(*t, *bits));
        line.push(' ');
    }
    line.push('\n');
    line
}

/// One sampled value as halsampler prints it: floats `%f`, bits 0/1,
/// integers in decimal.
pub fn format_value(t: HalType, bits: u64) -> String {
    match Value::from_bits(t, bits) {
        Value::Bit(b) => (b as u8).to_string(),
        Value::Float(f) => fmt_f(f),
        Value::S32(x) => x.to_string(),
        Value::U32(x) | Value::Port(x) => x.to_string(),
        Value::S64(x) => x.to_string(),
        Value::U64(x) => x.to_string(),
    }
}

/// Sign and decimal digits of a whole field, as i128 (saturated).
fn decimal(field: &str) -> Option<(bool, u128)> {
    let (neg, digits) = match field.as_bytes().first()? {
        b'-' => (true, &field[1..]),
        b'+' => (false, &field[1..]),
        _ => (false, field),
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let mag = digits.bytes().fold(0u128, |acc, d| {
        acc.saturating_mul(10).saturating_add((d - b'0') as u128)
    });
    Some((neg, mag))
}

/// C's `strtol` on a whole decimal field: saturates at the `long` range
/// (the caller then keeps the low bits, as an assignment in C does).
fn c_strtol(field: &str) -> Option<i64> {
    let (neg, mag) = decimal(field)?;
    let v = if neg {
        -(mag.min(1 << 64) as i128)
    } else {
        mag.min(1 << 64) as i128
    };
    Some(v.clamp(i64::MIN as i128, i64::MAX as i128) as i64)
}

/// C's `strtoul` on a whole decimal field: saturates at the `unsigned
/// long` range, and a minus sign negates in unsigned arithmetic.
fn c_strtoul(field: &str) -> Option<u64> {
    let (neg, mag) = decimal(field)?;
    let m = mag.min(u64::MAX as u128) as u64;
    Some(if neg { m.wrapping_neg() } else { m })
}

/// Parses one line of halstreamer input as read: its bytes, up to and
/// including the newline. As in LinuxCNC, which reads bytes, a byte that
/// is not UTF-8 only spoils the field it is in (a comment may hold any),
/// instead of ending the stream.
pub fn parse_input_line(line: &[u8], cols: &[HalType]) -> Option<Result<Vec<u64>, ScopeError>> {
    parse_line(&String::from_utf8_lossy(line), cols)
}

/// Parses one input line for a streamer. `None` for a comment line. Every
/// field must be followed by whitespace (a last line without a newline is
/// refused); text after the last field is ignored.
pub fn parse_line(line: &str, cols: &[HalType]) -> Option<Result<Vec<u64>, ScopeError>> {
    if line.starts_with('#') {
        return None;
    }
    let mut record = vec![0u64];
    let mut rest = line;
    for (i, t) in cols.iter().enumerate() {
        let trimmed = rest.trim_start();
        let end = trimmed.find(char::is_whitespace);
        let Some(end) = end else {
            return Some(Err(if trimmed.is_empty() {
                ScopeError::MissingValue { column: i }
            } else {
                ScopeError::NoWhitespace {
                    value: trimmed.to_string(),
                    column: i,
                }
            }));
        };
        let field = &trimmed[..end];
        let bad = || ScopeError::BadValue {
            value: field.to_string(),
            column: i,
            hal_type: *t,
        };
        let v = match t {
            HalType::Bit => match field {
                "0" => Value::Bit(false),
                "1" => Value::Bit(true),
                _ => return Some(Err(bad())),
            },
            HalType::Float => match parse_float(field) {
                Some(f) => Value::Float(f),
                None => return Some(Err(bad())),
            },
            HalType::S32 => match c_strtol(field) {
                Some(x) => Value::S32(x as i32),
                None => return Some(Err(bad())),
            },
            HalType::U32 => match c_strtoul(field) {
                Some(x) => Value::U32(x as u32),
                None => return Some(Err(bad())),
            },
            HalType::S64 => match c_strtol(field) {
                Some(x) => Value::S64(x),
                None => return Some(Err(bad())),
            },
            HalType::U64 => match c_strtoul(field) {
                Some(x) => Value::U64(x),
                None => return Some(Err(bad())),
            },
            // A ring column is never a port.
            HalType::Port => return Some(Err(bad())),
        };
        record.push(v.to_bits());
        rest = &trimmed[end..];
    }
    Some(Ok(record))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_print_like_halsampler() {
        let cols = [HalType::Float, HalType::Bit, HalType::S32, HalType::U64];
        let rec = [1, 1.5f64.to_bits(), 1, (-3i32) as i64 as u64, u64::MAX];
        assert_eq!(
            format_record(&rec, &cols, false),
            "1.500000 1 -3 18446744073709551615 \n"
        );
        assert_eq!(
            format_record(&rec, &cols, true),
            "0 1.500000 1 -3 18446744073709551615 \n"
        );
    }

    #[test]
    fn bytes_that_are_not_utf8_spoil_only_their_line() {
        // Found by the halstreamer fuzz target: such a line used to end
        // the whole stream.
        let cols = [HalType::Float];
        assert!(parse_input_line(b"# caf\xe9\n", &cols).is_none());
        assert_eq!(
            parse_input_line(b"2.5 \xff\n", &cols).and_then(Result::ok),
            Some(vec![0, 2.5f64.to_bits()])
        );
        let e = parse_input_line(b"2\xff5\n", &cols)
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("column 0"), "{e}");
    }

    #[test]
    fn lines_parse_like_halstreamer() {
        let cols = [HalType::Float, HalType::Bit];
        assert!(parse_line("# c\n", &cols).is_none());
        assert_eq!(
            parse_line("2.5 1 # trailing\n", &cols).and_then(Result::ok),
            Some(vec![0, 2.5f64.to_bits(), 1])
        );
        assert!(
            matches!(parse_line("2.5 1", &cols), Some(Err(_))),
            "needs the newline"
        );
        assert!(matches!(parse_line("2.5 2\n", &cols), Some(Err(_))));
        assert!(matches!(parse_line("x 1\n", &cols), Some(Err(_))));
        assert!(matches!(parse_line("1\n", &cols), Some(Err(_))));
        assert_eq!(
            parse_line("-1 0\n", &[HalType::S32, HalType::U32]).and_then(Result::ok),
            Some(vec![0, u64::MAX, 0])
        );
        // As C: -1 into an unsigned column wraps, a too large s32 keeps its
        // low bits, a too large s64 saturates.
        assert_eq!(
            parse_line("-1 -1\n", &[HalType::U32, HalType::U64]).and_then(Result::ok),
            Some(vec![0, 0xFFFF_FFFF, u64::MAX])
        );
        assert_eq!(
            parse_line("4294967297\n", &[HalType::S32]).and_then(Result::ok),
            Some(vec![0, 1])
        );
        assert_eq!(
            parse_line("99999999999999999999\n", &[HalType::S64]).and_then(Result::ok),
            Some(vec![0, i64::MAX as u64])
        );
        assert!(matches!(parse_line("12x\n", &[HalType::S32]), Some(Err(_))));
    }
}
