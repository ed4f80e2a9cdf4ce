//! `canservo-tool` on simulated drives (`--sim`): every command, its
//! messages and exit statuses.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::process::{Command, Output};

fn tool(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_canservo-tool"))
        .args(args)
        .output()
        .unwrap()
}

fn ok(args: &[&str]) -> String {
    let o = tool(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn fails(args: &[&str]) -> (i32, String) {
    let o = tool(args);
    assert!(!o.status.success(), "{args:?} succeeded");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn help_has_examples() {
    let h = ok(&["--help"]);
    for want in [
        "Examples:",
        "canservo-tool --iface can0 scan",
        "power 2 up",
        "watch --nodes 1,2",
    ] {
        assert!(h.contains(want), "{want}: {h}");
    }
    assert!(ok(&["power", "--help"]).contains("Step a drive through the CiA 402 power states"));
}

#[test]
fn scan_finds_every_node_with_its_identity() {
    let out = ok(&["--sim", "2,5", "scan", "--reset"]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "boot-up from: 2, 5");
    assert!(
        lines[1].starts_with("node 2: device type 0x00020192 (CiA 402 drive), vendor 0x0048414c"),
        "{out}"
    );
    assert!(
        lines[2].contains("serial 0x00000005, \"canservo simulated CiA 402 servo drive\""),
        "{out}"
    );
    assert_eq!(lines.len(), 3);
}

#[test]
fn read_and_write_with_types() {
    assert_eq!(
        ok(&["--sim", "1", "read", "1", "1018:04", "u32"]).trim(),
        "0x1018:04 (identity: serial number) = 1 (0x1)"
    );
    assert_eq!(
        ok(&["--sim", "1", "read", "1", "0x1000:0"]).trim(),
        "0x1000:00 (device type) = [92 01 02 00] = 131474"
    );
    assert_eq!(
        ok(&["--sim", "1", "write", "1", "607C:00", "i32", "-500"]).trim(),
        "0x607C:00 (home offset) = -500"
    );
    let (code, e) = fails(&["--sim", "1", "write", "1", "6041:00", "u16", "1"]);
    assert_eq!(code, 1);
    assert!(e.contains("aborted the SDO download to 0x6041:00 (statusword): 0x06010002 (attempt to write a read-only object)"), "{e}");
    let (_, e) = fails(&["--sim", "1", "read", "1", "2000:00"]);
    assert!(
        e.contains("0x06020000 (object does not exist in the object dictionary)"),
        "{e}"
    );
    let (_, e) = fails(&["--sim", "1", "write", "1", "6098:00", "i8", "300"]);
    assert!(e.contains("300 does not fit i8"), "{e}");
    let (_, e) = fails(&["--sim", "1", "read", "3", "1000:00", "--timeout-ms", "50"]);
    assert!(
        e.contains("node 3 did not answer the SDO upload of 0x1000:00 (device type) within 50 ms"),
        "{e}"
    );
}

#[test]
fn status_and_power_steps() {
    let s = ok(&["--sim", "4", "status", "4"]);
    assert!(
        s.starts_with(
            "statusword 0x0250 switch on disabled: voltage-enabled switch-on-disabled remote\n"
        ),
        "{s}"
    );
    assert!(s.contains("error code 0x0000 (no error)"));
    assert_eq!(
        ok(&["--sim", "4", "power", "4", "up"]).trim(),
        "switch on disabled -> ready to switch on -> switched on -> operation enabled"
    );
    assert_eq!(
        ok(&["--sim", "4", "power", "4", "shutdown"]).trim(),
        "switch on disabled -> ready to switch on"
    );
    let (code, e) = fails(&["--sim", "4", "power", "4", "fault-reset"]);
    assert_eq!(code, 1);
    assert!(
        e.contains("node 4 is in switch on disabled: fault-reset is not a transition from there"),
        "{e}"
    );
    let (_, e) = fails(&["--sim", "4", "power", "4", "sideways"]);
    assert!(
        e.contains("'sideways' is not a step (shutdown, switch-on"),
        "{e}"
    );
}

#[test]
fn nmt_and_watch() {
    assert_eq!(
        ok(&["--sim", "1", "nmt", "1", "start"]).trim(),
        "NMT start node 1"
    );
    let (_, e) = fails(&["--sim", "1", "nmt", "1", "go"]);
    assert!(e.contains("'go' is not an NMT command"), "{e}");
    let w = ok(&[
        "--sim",
        "1",
        "watch",
        "--nodes",
        "1",
        "--read-mapping",
        "--start",
        "--sync-ms",
        "5",
        "--seconds",
        "0.2",
    ]);
    assert!(
        w.contains("TPDO1 node 1: 0x6041:00 (statusword) 0x0250 (switch on disabled)"),
        "{w}"
    );
    let (_, e) = fails(&["--sim", "1", "watch"]);
    assert!(e.contains("with --sim, give --count or --seconds"), "{e}");
}

#[test]
fn a_missing_interface_is_named() {
    let (code, e) = fails(&["--iface", "nocan3", "scan"]);
    assert_eq!(code, 1);
    assert!(
        e.contains("canservo-tool: CAN interface 'nocan3': no such network interface"),
        "{e}"
    );
    let (code, _) = fails(&["read", "200", "1000:00"]);
    assert_eq!(code, 2, "usage errors");
}
