//! halstreamer's input: lines of values for a streamer channel, read as
//! bytes and parsed against the channel's column types.
//!
//! The input's first line is the channel's `cfg=` string (`ffb`, `su`,
//! ...; bytes that are no type letter pick a type by their value, so
//! every input has columns); the rest is the stream, cut into lines as
//! halstreamer reads them. Checked besides "no panic": only `#` lines are
//! skipped as comments; a parsed record has a sample word and one word
//! per column, each the canonical bits of a value of the column's type;
//! and what halsampler prints for a record parses back to the same
//! record (floats: to the same printed text).

use hal_components::infra::columns::{parse_cfg, MAX_COLUMNS};
use hal_core::{HalType, Value};
use hal_scope::fifo::{format_record, parse_input_line, parse_line};

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "halstreamer_input",
    run,
    dictionary: &[
        "\n", "# ", " ", "\t", "0", "1", "-", "+", "fb\n", "ffffff\n", "bsuSU\n", "lk\n", "0x10",
        "1e-7", ".", "e",
    ],
    generate: None,
};

fn columns(cfg: &[u8]) -> Vec<HalType> {
    if let Ok(cols) = parse_cfg("streamer", &String::from_utf8_lossy(cfg)) {
        if !cols.is_empty() {
            return cols;
        }
    }
    if cfg.is_empty() {
        return HalType::ALL.to_vec();
    }
    cfg.iter()
        .take(MAX_COLUMNS)
        .map(|b| HalType::ALL[*b as usize % HalType::ALL.len()])
        .collect()
}

fn run(input: &[u8]) {
    let (cfg, stream) = match input.iter().position(|&b| b == b'\n') {
        Some(i) => (&input[..i], &input[i + 1..]),
        None => (input, &[][..]),
    };
    let cols = columns(cfg);
    for line in stream.split_inclusive(|&b| b == b'\n') {
        let Some(parsed) = parse_input_line(line, &cols) else {
            assert!(line.starts_with(b"#"), "{line:?} skipped as a comment");
            continue;
        };
        let Ok(record) = parsed else {
            continue;
        };
        check_record(&record, &cols, line);
        let printed = format_record(&record, &cols, false);
        let again = match parse_line(&printed, &cols) {
            Some(Ok(r)) => r,
            other => panic!("{printed:?} (printed from {line:?}) parses as {other:?}"),
        };
        for ((t, a), b) in cols.iter().zip(&record[1..]).zip(&again[1..]) {
            if *t != HalType::Float {
                assert_eq!(a, b, "{t} column of {line:?} changes through {printed:?}");
            }
        }
        assert_eq!(
            format_record(&again, &cols, false),
            printed,
            "{line:?} prints differently after a round trip"
        );
    }
}

fn check_record(record: &[u64], cols: &[HalType], line: &[u8]) {
    assert_eq!(record.len(), cols.len() + 1, "record of {line:?}");
    assert_eq!(record[0], 0, "sample word of {line:?}");
    for (t, bits) in cols.iter().zip(&record[1..]) {
        let v = Value::from_bits(*t, *bits);
        assert_eq!(v.to_bits(), *bits, "{t} column of {line:?}: {bits:#x}");
    }
}
