//! `realtime stop` returns only once the host has released everything, so
//! `realtime start` may follow at once: three instances cycle side by side.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::process::{Command, Output};
use std::time::Instant;

fn realtime(args: &[&str], instance: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_realtime"))
        .args(args)
        .env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (2u64 << 20).to_string())
        .output()
        .expect("realtime runs")
}

fn check(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Cycles per instance: 300, or `HAL_TEST_CYCLES`.
fn cycles() -> usize {
    std::env::var("HAL_TEST_CYCLES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(300)
}

#[test]
fn three_instances_start_and_stop_side_by_side() {
    let cycles = cycles();
    let began = Instant::now();
    let workers: Vec<_> = (0..3)
        .map(|i| {
            std::thread::spawn(move || {
                let inst = common::instance(&format!("cycle{i}"));
                for n in 0..cycles {
                    check(&realtime(&["start"], &inst), &format!("{inst} start #{n}"));
                    check(&realtime(&["stop"], &inst), &format!("{inst} stop #{n}"));
                }
                // Nothing of the instance is left behind.
                assert!(!hal_core::paths::segment(&inst).exists());
                assert!(!hal_core::paths::socket(&inst).unwrap().exists());
                assert!(!hal_core::paths::lock(&inst).unwrap().exists());
                let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
            })
        })
        .collect();
    for w in workers {
        w.join().expect("a worker failed");
    }
    eprintln!(
        "3 instances x {cycles} start/stop cycles side by side: {:.1} s",
        began.elapsed().as_secs_f64()
    );
}

#[test]
fn restart_starts_a_stopped_instance_and_replaces_a_running_one() {
    let inst = common::instance("restart");
    check(
        &realtime(&["restart"], &inst),
        "restart of a stopped instance",
    );
    check(&realtime(&["status"], &inst), "status");
    check(
        &realtime(&["restart"], &inst),
        "restart of a running instance",
    );
    check(&realtime(&["status"], &inst), "status after restart");
    check(&realtime(&["stop"], &inst), "stop");
    let stopped = realtime(&["status"], &inst);
    assert!(!stopped.status.success());
    assert!(String::from_utf8_lossy(&stopped.stdout).contains("not running"));
    let again = realtime(&["stop"], &inst);
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("realtime not running"));
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}
