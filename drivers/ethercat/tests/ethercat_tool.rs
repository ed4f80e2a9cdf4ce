//! `ethercat-tool` on a simulated segment (`--sim FILE`): every command,
//! its output as IgH's `ethercat` prints it, its errors and exit status.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::path::PathBuf;
use std::process::{Command, Output};

/// A segment file of its own for each test (tests run in parallel).
fn segment(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("ethercat-tool");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn tool(seg: &PathBuf, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ethercat-tool"))
        .arg("--sim")
        .arg(seg)
        .args(args)
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

const MIXED: &str = "EK1100\nEL1008\nEL2008\nEL7041\nservo\n";

#[test]
fn slaves_master_and_pdos() {
    let seg = segment("mixed", MIXED);
    let out = stdout(&tool(&seg, &["slaves"]));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 5);
    assert_eq!(
        lines[0],
        "0  0:0  PREOP  +  EK1100 EtherCAT-Koppler (2A E-Bus)"
    );
    assert!(lines[3].starts_with("3  0:3  PREOP  +  EL7041"), "{out}");
    assert!(lines[4].ends_with("Simulated CiA 402 servo drive"), "{out}");
    let v = stdout(&tool(&seg, &["slaves", "-v"]));
    assert!(v.contains("=== Master 0, Slave 4 ===") && v.contains("Vendor Id:       0x00000e5c"));
    let m = stdout(&tool(&seg, &["master"]));
    assert!(
        m.contains("Slaves: 5") && m.contains("Lost frames: 0"),
        "{m}"
    );
    let p = stdout(&tool(&seg, &["pdos", "-p", "3"]));
    assert!(p.contains("RxPDO 0x1604 \"STM RxPDO-Map Velocity\""), "{p}");
    assert!(
        p.contains("    PDO entry 0x7010:21, 16 bit, \"Velocity\""),
        "{p}"
    );
    let all = stdout(&tool(&seg, &["pdos"]));
    assert!(all.contains("=== Master 0, Slave 2 ==="), "{all}");
}

#[test]
fn sii_read_raw_and_decoded() {
    let seg = segment("sii", MIXED);
    let raw = tool(&seg, &["sii-read", "-p", "1"]);
    assert!(raw.status.success());
    let sii = hal_ethercat::wire::sii::Sii::decode(&raw.stdout, None).unwrap();
    assert_eq!(
        (sii.identity.vendor, sii.identity.product),
        (2, 0x03F0_3052)
    );
    let v = stdout(&tool(&seg, &["sii-read", "-p", "4", "-v"]));
    assert!(v.contains("Mailbox: out") && v.contains("(CoE)"), "{v}");
}

#[test]
fn upload_and_download_typed_values() {
    let seg = segment("sdo", MIXED);
    assert_eq!(
        stdout(&tool(
            &seg,
            &["upload", "-p", "4", "0x1018", "1", "-t", "uint32"]
        )),
        "0x00000e5c 3676\n"
    );
    // Longer than 4 bytes: a normal (and, past the mailbox, segmented) upload.
    let name = stdout(&tool(&seg, &["upload", "-p", "4", "0x1008", "0"]));
    assert!(name.starts_with("Sim"), "{name}");
    assert!(tool(
        &seg,
        &["download", "-p", "4", "0x6060", "0", "-t", "int8", "9"]
    )
    .status
    .success());
    let e = tool(
        &seg,
        &["download", "-p", "4", "0x6060", "0", "-t", "int8", "300"],
    );
    assert_eq!(e.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&e.stderr).contains("out of range -128..=127"));
    let e = tool(&seg, &["upload", "-p", "4", "0x5555", "0"]);
    let msg = String::from_utf8_lossy(&e.stderr).into_owned();
    assert!(
        msg.contains("slave 4: SDO upload of 0x5555:00 aborted") && msg.contains("0x06020000"),
        "{msg}"
    );
    let e = tool(&seg, &["upload", "-p", "1", "0x1000", "0"]);
    assert!(String::from_utf8_lossy(&e.stderr).contains("no mailbox"));
}

#[test]
fn states_and_bad_input() {
    let seg = segment("states", MIXED);
    assert!(tool(&seg, &["states", "-p", "4", "INIT"]).status.success());
    let e = tool(&seg, &["states", "-p", "1", "SAFEOP"]);
    let msg = String::from_utf8_lossy(&e.stderr).into_owned();
    assert!(
        msg.contains("slave 1: requesting SAFEOP") && msg.contains("AL status code 0x001e"),
        "{msg}"
    );
    let e = tool(&seg, &["states", "FLYING"]);
    assert!(String::from_utf8_lossy(&e.stderr).contains("not one of INIT"));
    let e = tool(&seg, &["upload", "-p", "9", "0x1000", "0"]);
    assert!(String::from_utf8_lossy(&e.stderr).contains("no such slave (the segment has 5)"));
    let bad = segment("bad", "EK1100\nEL9\n");
    let e = tool(&bad, &["slaves"]);
    assert_eq!(e.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&e.stderr).contains("bad:2: <EL9>: unknown slave type"));
    let usage = tool(&seg, &["upload", "-p", "x", "1", "2"]);
    assert_eq!(usage.status.code(), Some(2));
}
