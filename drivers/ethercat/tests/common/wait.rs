//! Polling a condition in the simulated-segment tests.

use std::time::{Duration, Instant};

/// Polls `cond` every 2 ms until it holds; fails the test, naming `what`,
/// after 30 s.
pub fn wait(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(30);
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(2));
    }
}
