//! LinuxCNC's own outputs for HAL files (../shared/golden): every case
//! whose modules this suite provides must give the same stdout and exit
//! status byte for byte, and the same error lines on stderr.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::collections::BTreeSet;
use std::path::Path;

use common::*;

fn modules_used(hal: &str) -> BTreeSet<String> {
    hal.lines()
        .filter_map(|l| l.trim_start().strip_prefix("loadrt "))
        .filter_map(|rest| rest.split_whitespace().next())
        .map(str::to_string)
        .collect()
}

/// Runs the case in `dir` and lists how its outcome differs from
/// LinuxCNC's recorded one (stdout, exit status, error lines): empty when
/// it matches.
fn differences(dir: &Path, name: &str) -> Vec<String> {
    let out = halrun(dir, &["-f", "test.hal"], name);
    let expected = std::fs::read(dir.join("expected")).unwrap_or_default();
    let status: i32 = std::fs::read_to_string(dir.join("expected-status"))
        .map(|s| s.trim().parse().unwrap_or(0))
        .unwrap_or(0);
    let mut problems = Vec::new();
    if out.stdout != expected {
        problems.push(format!(
            "stdout differs:\n--- expected\n{}\n--- got\n{}",
            String::from_utf8_lossy(&expected),
            String::from_utf8_lossy(&out.stdout)
        ));
    }
    if out.status.code() != Some(status) {
        problems.push(format!(
            "exit status {:?}, expected {status}",
            out.status.code()
        ));
    }
    let want_err = meaningful_stderr(
        &std::fs::read_to_string(dir.join("expected-stderr")).unwrap_or_default(),
    );
    let got_err = meaningful_stderr(&String::from_utf8_lossy(&out.stderr));
    let missing: Vec<_> = want_err.iter().filter(|l| !got_err.contains(l)).collect();
    if !missing.is_empty() {
        problems.push(format!(
            "stderr lacks {missing:?}\n--- got stderr\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    problems
}

#[test]
fn golden_cases_with_provided_modules_match_linuxcnc() {
    let golden = root().join("../shared/golden");
    let Ok(entries) = std::fs::read_dir(&golden) else {
        eprintln!("no golden corpus at {}; skipped", golden.display());
        return;
    };
    let provided: BTreeSet<String> = hal_host::registry()
        .names()
        .into_iter()
        .map(str::to_string)
        .collect();
    let mut dirs: Vec<_> = entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let (mut ran, mut skipped, mut failures) = (Vec::new(), Vec::new(), Vec::new());
    for dir in dirs {
        let hal = std::fs::read_to_string(dir.join("test.hal")).unwrap_or_default();
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        let missing: Vec<_> = modules_used(&hal)
            .into_iter()
            .filter(|m| !provided.contains(m))
            .collect();
        // The unknown module of err-unknown-component is the point of it;
        // every other module it loads must exist.
        let missing: Vec<_> = missing
            .into_iter()
            .filter(|m| m != "no_such_component_xyz")
            .collect();
        if !missing.is_empty() {
            skipped.push(format!("{name} (needs {})", missing.join(", ")));
            continue;
        }
        let problems = differences(&dir, &name);
        if problems.is_empty() {
            ran.push(name);
        } else {
            failures.push(format!("{name}: {}", problems.join("\n")));
        }
    }
    eprintln!("golden: {} passed: {}", ran.len(), ran.join(" "));
    eprintln!(
        "golden: {} not yet runnable: {}",
        skipped.len(),
        skipped.join("; ")
    );
    assert!(
        failures.is_empty(),
        "{} golden case(s) differ:\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    assert!(!ran.is_empty(), "no golden case could run");
}
