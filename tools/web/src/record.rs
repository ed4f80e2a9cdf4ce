//! A scope record as the server sends it: JSON for any client, or a
//! binary form for the page, which asks for it with
//! `Accept: application/octet-stream` (four channels of 1000 samples are
//! 4000 numbers: as text they cost the server more than the capture).
//!
//! The binary form, all integers and numbers little-endian:
//!
//! * a `u32`: the length `H` of the header in bytes;
//! * the header: the JSON form without `columns`, plus `samples` (the
//!   number of rows), UTF-8;
//! * zero bytes up to the next multiple of 8 from the start;
//! * the columns one after the other, channel by channel, `samples`
//!   `f64` each (bits as 0 and 1; a float that is not finite stays as
//!   it is, where the JSON form has `null`).

use hal_scope::scope::capture::numeric;
use hal_scope::scope::output::Record;
use serde_json::{json, Map, Value as JsonValue};

/// The media type of the binary form.
pub const BINARY_TYPE: &str = "application/octet-stream";

/// What describes a record beside its columns.
fn header(r: &Record, triggered: bool) -> Map<String, JsonValue> {
    let first = r.rows.first().map(|row| (row[0] as u32).wrapping_sub(1));
    let types: Vec<&str> = r.types.iter().map(|t| t.name()).collect();
    Map::from_iter([
        ("names".to_string(), json!(r.names)),
        ("types".to_string(), json!(types)),
        ("period_ns".to_string(), json!(r.period_ns)),
        ("trigger_index".to_string(), json!(r.trigger_index)),
        ("triggered".to_string(), json!(triggered)),
        ("first_sample".to_string(), json!(first)),
    ])
}

/// Channel `c` of `r` as numbers.
fn column(r: &Record, c: usize) -> impl Iterator<Item = f64> + '_ {
    let t = r.types[c];
    r.rows.iter().map(move |row| numeric(t, row[c + 1]))
}

/// The JSON form: the header and `columns`, a list of numbers per
/// channel.
pub fn json(r: &Record, triggered: bool) -> JsonValue {
    let mut head = header(r, triggered);
    let columns: Vec<Vec<f64>> = (0..r.types.len()).map(|c| column(r, c).collect()).collect();
    head.insert("columns".into(), json!(columns));
    JsonValue::Object(head)
}

/// The binary form (see the module's documentation).
pub fn binary(r: &Record, triggered: bool) -> Vec<u8> {
    let mut head = header(r, triggered);
    head.insert("samples".into(), json!(r.rows.len()));
    let text = JsonValue::Object(head).to_string();
    let start = (4 + text.len()).next_multiple_of(8);
    let mut out = Vec::with_capacity(start + 8 * r.rows.len() * r.types.len());
    // A header past 4 GiB would need more names than a sampler has pins.
    let len = u32::try_from(text.len()).unwrap_or(u32::MAX);
    out.extend_from_slice(&len.to_le_bytes());
    out.extend_from_slice(text.as_bytes());
    out.resize(start, 0);
    for c in 0..r.types.len() {
        for v in column(r, c) {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::HalType;

    fn record() -> Record {
        let rows = (0..5u64)
            .map(|i| {
                vec![
                    i + 10,
                    (i as f64 * 0.5).to_bits(),
                    i % 2,
                    (-(i as i32)) as u32 as u64,
                ]
            })
            .collect();
        Record {
            names: vec!["a.float".into(), "b\"bit".into(), "c.s32".into()],
            types: vec![HalType::Float, HalType::Bit, HalType::S32],
            rows,
            trigger_index: 2,
            period_ns: 100_000,
        }
    }

    /// Reads the binary form back: its header and columns.
    fn decode(bytes: &[u8]) -> (JsonValue, Vec<Vec<f64>>) {
        let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        let head: JsonValue = serde_json::from_slice(&bytes[4..4 + len]).unwrap();
        let start = (4 + len).next_multiple_of(8);
        assert!(bytes[4 + len..start].iter().all(|b| *b == 0));
        let n = head["samples"].as_u64().unwrap() as usize;
        let body = &bytes[start..];
        assert_eq!(body.len() % (8 * n), 0);
        let columns = body
            .chunks(8 * n)
            .map(|col| {
                col.chunks(8)
                    .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
                    .collect()
            })
            .collect();
        (head, columns)
    }

    #[test]
    fn the_binary_form_holds_what_the_json_form_holds() {
        let r = record();
        let j = json(&r, true);
        let (head, columns) = decode(&binary(&r, true));
        for key in [
            "names",
            "types",
            "period_ns",
            "trigger_index",
            "triggered",
            "first_sample",
        ] {
            assert_eq!(head[key], j[key], "{key}");
        }
        assert_eq!(head["samples"], 5);
        assert_eq!(head["first_sample"], 9);
        assert_eq!(json!(columns), j["columns"]);
        assert_eq!(columns[0], [0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(columns[1], [0.0, 1.0, 0.0, 1.0, 0.0]);
        assert_eq!(columns[2], [0.0, -1.0, -2.0, -3.0, -4.0]);
    }

    #[test]
    fn an_empty_record_is_a_header_alone() {
        let r = Record {
            rows: Vec::new(),
            ..record()
        };
        let bytes = binary(&r, false);
        assert_eq!(bytes.len() % 8, 0);
        let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        let head: JsonValue = serde_json::from_slice(&bytes[4..4 + len]).unwrap();
        assert_eq!(head["samples"], 0);
        assert_eq!(head["first_sample"], JsonValue::Null);
        assert_eq!(bytes.len(), (4 + len).next_multiple_of(8));
    }
}
