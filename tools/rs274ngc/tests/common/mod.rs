//! Running an rs274 binary on the programs in tests/programs the way
//! tests/record-expected.sh runs LinuxCNC's: in a fresh copy of the
//! directory, with "-t tool.tbl" unless NAME.args names a tool table,
//! then the words of NAME.args, then "-g NAME.ngc".

#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The directory of test programs.
pub fn programs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs")
}

/// The names of the programs (file names without `.ngc`), sorted.
pub fn program_names() -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(programs_dir())
        .expect("tests/programs")
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().into_string().ok())
        .filter_map(|n| n.strip_suffix(".ngc").map(str::to_string))
        .collect();
    names.sort();
    names
}

/// What a run printed: standard output, and "exit N" then standard error.
pub struct Output {
    pub stdout: Vec<u8>,
    pub status_and_stderr: Vec<u8>,
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).expect("create copy");
    for entry in fs::read_dir(from).expect("read programs") {
        let entry = entry.expect("entry");
        let path = entry.path();
        let name = entry.file_name();
        if name == "expected" {
            continue;
        }
        if path.is_dir() {
            copy_dir(&path, &to.join(&name));
        } else {
            fs::copy(&path, to.join(&name)).expect("copy program file");
        }
    }
}

/// The command line words for program `name`.
pub fn arguments(name: &str) -> Vec<String> {
    let extra = fs::read_to_string(programs_dir().join(format!("{name}.args"))).unwrap_or_default();
    let extra: Vec<String> = extra.split_whitespace().map(str::to_string).collect();
    let mut args = Vec::new();
    if !extra.iter().any(|a| a == "-t") {
        args.extend(["-t".to_string(), "tool.tbl".to_string()]);
    }
    args.extend(extra);
    args.extend(["-g".to_string(), format!("{name}.ngc")]);
    args
}

/// Run `binary` on program `name` with extra environment `env`.
pub fn run(binary: &Path, env: &[(String, String)], name: &str) -> Output {
    let work = tempfile::tempdir().expect("temporary directory");
    copy_dir(&programs_dir(), work.path());
    let out = Command::new(binary)
        .args(arguments(name))
        .envs(env.iter().map(|(k, v)| (k, v)))
        .current_dir(work.path())
        .stdin(Stdio::null())
        .output()
        .expect("run rs274");
    let code = out.status.code().unwrap_or(-1);
    let mut status_and_stderr = format!("exit {code}\n").into_bytes();
    status_and_stderr.extend_from_slice(&out.stderr);
    Output {
        stdout: out.stdout,
        status_and_stderr,
    }
}

/// The first line where two outputs differ, for messages.
pub fn first_difference(expected: &[u8], got: &[u8]) -> String {
    let e = String::from_utf8_lossy(expected);
    let g = String::from_utf8_lossy(got);
    for (n, (a, b)) in e.lines().zip(g.lines()).enumerate() {
        if a != b {
            return format!("line {}: expected {a:?}, got {b:?}", n + 1);
        }
    }
    format!(
        "lengths differ: expected {} lines, got {}",
        e.lines().count(),
        g.lines().count()
    )
}
