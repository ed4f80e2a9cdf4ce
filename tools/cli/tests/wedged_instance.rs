//! An instance survives a damaged lock word, and `realtime stop` always
//! ends the host: one byte written over the lock (offset 64 of the
//! segment, which the group may write) names an owner that does not
//! exist; tools recover the lock with a message instead of waiting
//! forever. A host that does not answer at all is killed by `realtime
//! stop`, which says so.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::os::unix::fs::FileExt;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs tool `bin` with `args` on `instance`, killed after `limit` (a
/// failure: the tool hung). Returns its output and how long it took.
fn run_within(bin: &str, args: &[&str], instance: &str, limit: Duration) -> (Output, Duration) {
    let mut child = Command::new(bin)
        .args(args)
        .env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let began = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if began.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!(
                "{bin} {args:?} still waiting after {limit:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    (child.wait_with_output().unwrap(), began.elapsed())
}

/// The pid of the hal-host serving `instance`, from /proc.
fn host_pid(instance: &str) -> i32 {
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<i32>() else {
            continue;
        };
        let Ok(cmd) = std::fs::read(format!("/proc/{pid}/cmdline")) else {
            continue;
        };
        let words: Vec<&[u8]> = cmd.split(|&b| b == 0).collect();
        let is_host = words.first().is_some_and(|w| w.ends_with(b"hal-host"));
        if is_host
            && words
                .windows(2)
                .any(|w| w[0] == b"--instance" && w[1] == instance.as_bytes())
        {
            return pid;
        }
    }
    panic!("no hal-host for {instance}");
}

#[test]
fn a_damaged_lock_word_is_recovered_and_realtime_stop_ends_the_host() {
    let inst = common::instance("lockword");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    let halcmd = env!("CARGO_BIN_EXE_halcmd");
    let limit = Duration::from_secs(30);
    let (out, _) = run_within(realtime, &["start"], &inst, limit);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (out, _) = run_within(halcmd, &["loadrt", "and2"], &inst, limit);
    assert!(out.status.success());

    // The report's byte: 0x55 over the lock word (thread 85).
    let seg = std::fs::OpenOptions::new()
        .write(true)
        .open(hal_core::paths::segment(&inst))
        .unwrap();
    seg.write_all_at(&[0x55], 64).unwrap();

    let (out, took) = run_within(halcmd, &["show", "pin"], &inst, limit);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("and2.0.out"));
    assert!(
        err.contains("named thread 85 as its holder") && err.contains("lock recovered"),
        "{err}"
    );
    assert!(took < Duration::from_secs(15), "took {took:?}");

    // The host's own work goes on, and stop ends it.
    let (out, _) = run_within(halcmd, &["loadrt", "or2"], &inst, limit);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (out, took) = run_within(realtime, &["stop"], &inst, limit);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(took < Duration::from_secs(20), "took {took:?}");
    assert!(hal_core::Instance::attach(&inst).is_err());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}

#[test]
fn realtime_stop_ends_a_host_that_does_not_answer() {
    let inst = common::instance("frozen");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    let limit = Duration::from_secs(60);
    let (out, _) = run_within(realtime, &["start"], &inst, limit);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let pid = host_pid(&inst);
    nix::sys::signal::kill(
        nix::unistd::Pid::from_raw(pid),
        nix::sys::signal::Signal::SIGSTOP,
    )
    .unwrap();

    let (out, _) = run_within(realtime, &["stop"], &inst, limit);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("did not exit within 20 s")
            && err.contains(&format!("ended it (process {pid}) with SIGKILL")),
        "{err}"
    );
    let alive = std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|s| {
        s.rsplit_once(')')
            .is_some_and(|(_, r)| !r.trim_start().starts_with('Z'))
    });
    assert!(!alive, "host {pid} still runs");

    // What it left is reclaimed by the next host.
    let (out, _) = run_within(realtime, &["start"], &inst, limit);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (out, _) = run_within(realtime, &["stop"], &inst, limit);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}
