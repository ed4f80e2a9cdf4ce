//! G10 L1 and L10 on the simulated mill: the change reaches iocontrol's
//! tool table (a following G43 uses it) and the tool table file, in
//! LinuxCNC's format with the tool's comment kept.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{mill_copy, Machine, Scratch};

fn mdi(m: &Machine, line: &str) {
    let words: Vec<&str> = std::iter::once("mdi")
        .chain(line.split_whitespace())
        .collect();
    m.task_ok(&words);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(ok, "{line}: {out}{err}\n--- linuxcnc:\n{}", m.stderr());
}

#[test]
fn g10_l1_and_l10_write_the_tool_table() {
    let s = Scratch::new("g10-table");
    let ini = mill_copy(&s);
    let table = s.0.join("sim.tbl");
    let m = Machine::start(&ini, "g10-table");
    m.on_and_homed();
    m.task_ok(&["mode", "mdi"]);

    mdi(&m, "G21 G10 L1 P2 Z22.25 R3.5");
    let text = std::fs::read_to_string(&table).unwrap();
    assert!(
        text.contains("T2 P2 D7.000000 Z+22.250000 ;6 mm end mill\n"),
        "{text}"
    );
    // The other tools are kept, written the way LinuxCNC writes them.
    assert!(
        text.starts_with("T1 P1 D3.000000 Z+15.000000 ;3 mm end mill\n"),
        "{text}"
    );
    assert!(text.ends_with("T99 P99 Z+0.100000 ;probe\n"), "{text}");
    // A tool change and G43 use the new length.
    mdi(&m, "T2 M6");
    mdi(&m, "G43");
    let status = m.task_ok(&["status"]);
    assert!(status.contains("tool 0.0000 0.0000 22.2500"), "{status}");
    // L10: the length that makes the current Z read 5 in G54.
    mdi(&m, "G49 G0 Z-10");
    mdi(&m, "G10 L10 P2 Z5");
    let text = std::fs::read_to_string(&table).unwrap();
    assert!(
        text.contains("T2 P2 D7.000000 Z-15.000000 ;6 mm end mill\n"),
        "{text}"
    );
    m.stop();
}
