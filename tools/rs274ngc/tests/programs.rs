//! Our rs274 on every program in tests/programs, compared byte for byte
//! with what LinuxCNC's rs274 printed for it (recorded by
//! tests/record-expected.sh into tests/programs/expected). The live test
//! runs LinuxCNC's rs274 as well when LINUXCNC_RS274 names it.

mod common;

use std::path::{Path, PathBuf};

use common::{first_difference, program_names, programs_dir, run};

fn ours() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_rs274"))
}

#[test]
fn recorded_outputs_match() {
    let expected_dir = programs_dir().join("expected");
    let mut failures = Vec::new();
    let names = program_names();
    assert!(names.len() >= 40, "the test programs are missing");
    for name in &names {
        let out = run(&ours(), &[], name);
        let want_out =
            std::fs::read(expected_dir.join(format!("{name}.out"))).expect("expected .out");
        let want_err =
            std::fs::read(expected_dir.join(format!("{name}.err"))).expect("expected .err");
        if out.stdout != want_out {
            failures.push(format!(
                "{name} (stdout): {}",
                first_difference(&want_out, &out.stdout)
            ));
        }
        if out.status_and_stderr != want_err {
            let diff = first_difference(&want_err, &out.status_and_stderr);
            failures.push(format!("{name} (exit/stderr): {diff}"));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} differ:\n{}",
        failures.len(),
        names.len(),
        failures.join("\n")
    );
}

/// LinuxCNC's rs274 and the environment it needs, from LINUXCNC_RS274
/// (the binary) and LINUXCNC_LD_LIBRARY_PATH (default: ../lib and
/// ../lib/x86_64-linux-gnu next to the binary).
fn linuxcnc() -> Option<(PathBuf, Vec<(String, String)>)> {
    let binary = PathBuf::from(std::env::var_os("LINUXCNC_RS274")?);
    let bin_dir = binary.parent().unwrap_or(Path::new(".")).to_path_buf();
    let libs = std::env::var("LINUXCNC_LD_LIBRARY_PATH").unwrap_or_else(|_| {
        let lib = bin_dir.join("../lib");
        format!(
            "{}:{}",
            lib.display(),
            lib.join("x86_64-linux-gnu").display()
        )
    });
    Some((binary, vec![("LD_LIBRARY_PATH".to_string(), libs)]))
}

#[test]
#[ignore = "needs LinuxCNC's rs274: LINUXCNC_RS274=/path/to/rs274 cargo test -p rs274ngc --test programs -- --ignored"]
fn live_differential_against_linuxcnc() {
    let (binary, env) =
        linuxcnc().expect("LINUXCNC_RS274 is not set: this test needs LinuxCNC's rs274");
    let mut failures = Vec::new();
    let mut differing = 0;
    let names = program_names();
    for name in &names {
        let theirs = run(&binary, &env, name);
        let ours = run(&ours(), &[], name);
        let before = failures.len();
        if theirs.stdout != ours.stdout {
            failures.push(format!(
                "{name} (stdout): {}",
                first_difference(&theirs.stdout, &ours.stdout)
            ));
        }
        if theirs.status_and_stderr != ours.status_and_stderr {
            let diff = first_difference(&theirs.status_and_stderr, &ours.status_and_stderr);
            failures.push(format!("{name} (exit/stderr): {diff}"));
        }
        differing += usize::from(failures.len() > before);
    }
    println!(
        "{} of {} programs identical to LinuxCNC's rs274",
        names.len() - differing,
        names.len()
    );
    assert!(
        failures.is_empty(),
        "{differing} programs differ:\n{}",
        failures.join("\n")
    );
}
