//! Shared helpers for hal-core's integration tests.
#![allow(dead_code)]
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};

use hal_core::{Host, HostConfig, RealtimeMode};

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// An instance name no other test (or test process) uses.
pub fn unique_instance(tag: &str) -> String {
    format!(
        "t-{tag}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    )
}

/// A host on a fresh instance, small segment, given realtime mode.
pub fn host_with(tag: &str, realtime: RealtimeMode) -> Host {
    let mut cfg = HostConfig::new(&unique_instance(tag));
    cfg.shm_size = 8 << 20;
    cfg.realtime = realtime;
    Host::create(cfg).expect("host starts")
}

/// A host without realtime scheduling (tests run side by side).
pub fn host(tag: &str) -> Host {
    host_with(tag, RealtimeMode::Off)
}

/// The role this process plays, if it was started by [`spawn_child`].
pub fn child_role() -> Option<(String, String)> {
    let role = std::env::var("HAL_TEST_CHILD_ROLE").ok()?;
    let inst = std::env::var("HAL_TEST_CHILD_INSTANCE").ok()?;
    Some((role, inst))
}

/// Re-runs this test binary, running only `test`, as a child with `role`.
pub fn spawn_child(test: &str, role: &str, instance: &str) -> Child {
    Command::new(std::env::current_exe().unwrap())
        .args([test, "--exact", "--nocapture", "--test-threads=1"])
        .env("HAL_TEST_CHILD_ROLE", role)
        .env("HAL_TEST_CHILD_INSTANCE", instance)
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("child starts")
}

/// Polls `cond` for up to `secs` seconds.
pub fn wait_until(secs: f64, mut cond: impl FnMut() -> bool) -> bool {
    let end = std::time::Instant::now() + std::time::Duration::from_secs_f64(secs);
    while std::time::Instant::now() < end {
        if cond() {
            return true;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    cond()
}
