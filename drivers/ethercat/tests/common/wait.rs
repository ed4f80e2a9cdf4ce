//! Polling a condition in the simulated-segment tests.
#![allow(dead_code, reason = "each test binary uses some of these")]

use std::time::{Duration, Instant};

/// Polls `cond` every millisecond until it holds; fails the test, naming
/// `what`, after 30 s.
pub fn wait(what: &str, cond: impl FnMut() -> bool) {
    wait_within(what, Duration::from_secs(30), cond);
}

/// [`wait`] with the limit `limit`; returns how long it took.
pub fn wait_within(what: &str, limit: Duration, mut cond: impl FnMut() -> bool) -> Duration {
    let start = Instant::now();
    while !cond() {
        assert!(
            start.elapsed() < limit,
            "timed out ({limit:?}) waiting for {what}"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    start.elapsed()
}
