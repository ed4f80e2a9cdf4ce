//! A program started by a one-shot `halcmd loadusr` outlives halcmd, as in
//! LinuxCNC, and ends with the instance: `realtime stop` and halrun's exit
//! stop it before they return.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A private scratch directory for this test.
fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hal-loadusr-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir(&d).unwrap();
    d
}

/// Whether `pid` runs (a zombie waiting for its reaper does not).
fn running(pid: i32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| s.rsplit_once(')').map(|(_, r)| r.trim_start().to_string()))
        .is_some_and(|r| !r.starts_with('Z') && !r.starts_with('X'))
}

/// Waits for the program to write its PID into `file`.
fn pid_from(file: &Path) -> i32 {
    let end = Instant::now() + Duration::from_secs(20);
    loop {
        if let Some(pid) = std::fs::read_to_string(file)
            .ok()
            .and_then(|t| t.trim().parse().ok())
        {
            return pid;
        }
        assert!(
            Instant::now() < end,
            "the program never wrote {}",
            file.display()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A `loadusr` line whose program writes its PID to `file` and sleeps.
fn sleeper(file: &Path) -> Vec<String> {
    vec![
        "loadusr".into(),
        "sh".into(),
        "-c".into(),
        format!("echo $$ > {}; exec sleep 600", file.display()),
    ]
}

fn tool(bin: &str, instance: &str) -> Command {
    let mut c = Command::new(bin);
    c.env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (4u64 << 20).to_string())
        // The program inherits these; a captured pipe would stay open.
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    c
}

#[test]
fn loadusr_programs_outlive_halcmd_and_end_with_realtime_stop() {
    let inst = common::instance("outlive");
    let dir = scratch("outlive");
    let pidfile = dir.join("pid");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(tool(realtime, &inst)
        .arg("start")
        .status()
        .unwrap()
        .success());
    let status = tool(env!("CARGO_BIN_EXE_halcmd"), &inst)
        .args(sleeper(&pidfile))
        .status()
        .unwrap();
    assert!(status.success());
    let pid = pid_from(&pidfile);
    // halcmd has exited; the program has not.
    std::thread::sleep(Duration::from_millis(100));
    assert!(running(pid), "the program ended with halcmd");
    assert!(tool(realtime, &inst)
        .arg("stop")
        .status()
        .unwrap()
        .success());
    assert!(!running(pid), "realtime stop left the program running");
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn loadusr_programs_end_when_halrun_ends() {
    let inst = common::instance("halrun-usr");
    let dir = scratch("halrun");
    let pidfile = dir.join("pid");
    let hal = dir.join("u.hal");
    let line = sleeper(&pidfile)
        .into_iter()
        .map(|w| {
            if w.contains(' ') {
                format!("\"{w}\"")
            } else {
                w
            }
        })
        .collect::<Vec<_>>()
        .join(" ");
    // The file waits until the program has written its PID, so that the
    // teardown cannot come first.
    let wait = format!(
        "loadusr -w sh -c \"while [ ! -s {0} ]; do sleep 0.01; done\"",
        pidfile.display()
    );
    std::fs::write(&hal, format!("{line}\n{wait}\n")).unwrap();
    let status = tool(env!("CARGO_BIN_EXE_halrun"), &inst)
        .arg("-f")
        .arg(&hal)
        .status()
        .unwrap();
    assert!(status.success());
    let pid = pid_from(&pidfile);
    assert!(!running(pid), "halrun left the program running");
    std::fs::remove_dir_all(&dir).unwrap();
}
