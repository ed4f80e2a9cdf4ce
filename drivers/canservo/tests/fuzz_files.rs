//! The text parsers' fuzz bodies ([`hal_canservo::fuzzing::drive_file`],
//! [`hal_canservo::fuzzing::module_params`]) over more than 100 000 inputs
//! each (proptest, on stable). Inputs are built from words that reach
//! deep into each parser (good objects, types, values and parameters,
//! next to near misses and random bytes), so most are not refused at the
//! first word.

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// Inputs per target.
const CASES: u32 = 100_000;

fn runner() -> TestRunner {
    TestRunner::new(Config {
        cases: CASES,
        failure_persistence: None,
        ..Config::default()
    })
}

/// `list[b]` for most bytes `b`; for the top few, the byte itself, so
/// raw bytes (bad UTF-8, controls) still come through.
fn pick(list: &[&str], b: u8, out: &mut Vec<u8>) {
    match list.get(usize::from(b) % 251 % list.len()) {
        Some(w) if b < 251 => out.extend_from_slice(w.as_bytes()),
        _ => out.push(b),
    }
}

/// Drive-file text from `bytes`, four per line: object, type, value,
/// and what ends the line.
fn drive_text(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    for c in bytes.chunks(4) {
        let b = |i: usize| c.get(i).copied().unwrap_or(0);
        pick(OBJECTS, b(0), &mut out);
        out.push(b' ');
        pick(TYPES, b(1), &mut out);
        out.push(b' ');
        pick(VALUES, b(2), &mut out);
        pick(LINE_ENDS, b(3), &mut out);
    }
    out
}

/// A `loadrt` line from `bytes`, one word each.
fn loadrt_text(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    for &b in bytes {
        pick(PARAM_WORDS, b, &mut out);
        out.push(if b % 7 == 0 { b'\t' } else { b' ' });
    }
    out
}

const OBJECTS: &[&str] = &[
    "6098:00",
    "0x6099:01",
    "607C:0",
    "6065:00",
    "2000:FF",
    "ffff:ff",
    "0X1017:0x00",
    "6098:00",
    "6099:02",
    "10000:00",
    "6098",
    "6098:100",
    "+6098:00",
    "# 6098:00",
    "",
];
const TYPES: &[&str] = &[
    "u8", "u16", "u32", "i8", "i16", "i32", "s8", "s16", "s32", "U32", "I16", "u64", "",
];
const VALUES: &[&str] = &[
    "0",
    "1",
    "-1",
    "127",
    "-128",
    "255",
    "256",
    "65535",
    "0x4E20",
    "-0x80",
    "4294967295",
    "4294967296",
    "-2147483648",
    "2147483647",
    "0x",
    "-",
    "--5",
    "+5",
    "19",
    "0x7f",
    "",
];
const LINE_ENDS: &[&str] = &[
    "\n",
    "\n",
    "\n",
    "\r\n",
    " # comment\n",
    "#\n",
    "\n\n",
    " extra\n",
    "\t\n",
    "",
];

const PARAM_WORDS: &[&str] = &[
    "nodes=1",
    "nodes=1,2,3",
    "nodes=127",
    "nodes=0",
    "nodes=3,3",
    "nodes=1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17",
    "backend=sim",
    "backend=socketcan",
    "backend=usb",
    "iface=vcan0",
    "iface=",
    "scale=1000",
    "scale=1,0",
    "scale=nan",
    "scale=-2.5,inf",
    "scale=1e308,1e-308",
    "mode=csp",
    "mode=pv,csv",
    "mode=pp",
    "sync=0",
    "sync=2",
    "period_ns=1000000",
    "period_ns=49999",
    "period_ns=0x7fffffff",
    "heartbeat_ms=0",
    "heartbeat_ms=65535",
    "heartbeat_timeout_ms=600000",
    "master_node=0",
    "master_node=1",
    "master_heartbeat_ms=21845",
    "tpdo_misses=0",
    "tpdo_misses=1000",
    "quick_stop_ms=60000",
    "sdo_timeout_ms=0",
    "boot_timeout_ms=-1",
    "diag_ms=3600000",
    "sim_home=-2147483648",
    "sim_home=1,2,3",
    "drive_file=../../configs/sim/canservo-x.sdo",
    "drive_file=/dev/zero",
    "drive_file=/nonexistent.sdo",
    "drive_file=.",
    "nodes",
    "=",
    "x=1",
    "scale=\"1\"",
];

#[test]
fn drive_files_over_a_hundred_thousand_inputs() {
    let accepted = std::cell::Cell::new(0u32);
    runner()
        .run(&vec(any::<u8>(), 0..4 * 8), |data| {
            if hal_canservo::fuzzing::drive_file(&drive_text(&data)) > 0 {
                accepted.set(accepted.get() + 1);
            }
            Ok(())
        })
        .unwrap();
    // The words reach past the first check often enough to matter.
    assert!(accepted.get() > CASES / 100, "{} accepted", accepted.get());
}

#[test]
fn loadrt_lines_over_a_hundred_thousand_inputs() {
    let accepted = std::cell::Cell::new(0u32);
    runner()
        .run(&vec(any::<u8>(), 0..8), |data| {
            if hal_canservo::fuzzing::module_params(&loadrt_text(&data)) {
                accepted.set(accepted.get() + 1);
            }
            Ok(())
        })
        .unwrap();
    assert!(accepted.get() > CASES / 100, "{} accepted", accepted.get());
}
