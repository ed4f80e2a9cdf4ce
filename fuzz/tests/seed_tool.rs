//! `hal-fuzz-seed` writes its seeds and ends quietly when nobody reads
//! its summary (a closed standard output), and says what it could not
//! read instead of panicking. Runs on a scratch golden directory and
//! corpus, never the source tree's.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn scratch(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("seed-tool-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the tool with `args`; standard output a pipe whose reader is
/// already gone. (status code, stderr).
fn run_closed_stdout(args: &[&std::ffi::OsStr]) -> (Option<i32>, String) {
    let (reader, writer) = nix::unistd::pipe().unwrap();
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_hal-fuzz-seed"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(Stdio::from(writer))
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_closed_stdout_only_silences_the_summary() {
    let d = scratch("closed");
    let golden = d.join("golden");
    std::fs::create_dir_all(golden.join("and2")).unwrap();
    std::fs::write(golden.join("and2/test.hal"), "loadrt and2\nshow pin\n").unwrap();
    let corpus = d.join("corpus");
    let (code, err) = run_closed_stdout(&[
        "--write".as_ref(),
        golden.as_os_str(),
        "--corpus-dir".as_ref(),
        corpus.as_os_str(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let seed = corpus.join("halcmd_dispatch/golden-and2-test");
    assert_eq!(
        std::fs::read_to_string(&seed).unwrap(),
        "loadrt and2\nshow pin\n"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn what_cannot_be_read_or_written_is_an_error_not_a_panic() {
    let d = scratch("errors");
    let (code, err) = run_closed_stdout(&[
        "--write".as_ref(),
        d.join("no-golden").as_os_str(),
        "--corpus-dir".as_ref(),
        d.join("corpus").as_os_str(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("no golden cases under"), "{err}");
    // A corpus directory that is a file.
    let golden = d.join("golden");
    std::fs::create_dir_all(golden.join("x")).unwrap();
    std::fs::write(golden.join("x/test.hal"), "loadrt and2\n").unwrap();
    std::fs::write(d.join("file"), "").unwrap();
    let (code, err) = run_closed_stdout(&[
        "--write".as_ref(),
        golden.as_os_str(),
        "--corpus-dir".as_ref(),
        d.join("file").as_os_str(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("creating") && !err.contains("panicked"),
        "{err}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}
