//! The time source of the driver's write/reset timing and of the
//! simulator's write log.
//!
//! The driver remembers when it last wrote each register and `reset`
//! busy-waits until that time plus `reset-time`. On hardware the clock is
//! CLOCK_MONOTONIC; tests substitute a [`SimClock`] that advances a fixed
//! step on every reading, so a busy-wait ends after a known number of
//! polls and the logged times are exact.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// A nanosecond clock.
pub trait Clock: Send + Sync {
    /// The current time in nanoseconds.
    fn now_ns(&self) -> u64;
}

/// CLOCK_MONOTONIC.
#[derive(Debug, Default, Clone, Copy)]
pub struct MonotonicClock;

impl Clock for MonotonicClock {
    #[inline]
    fn now_ns(&self) -> u64 {
        hal_core::clock::monotonic_ns()
    }
}

/// A simulated clock: every reading returns the current time and then
/// advances it by `step` ns (so a busy-wait terminates); tests move it on
/// with [`advance`](Self::advance).
#[derive(Debug)]
pub struct SimClock {
    now: AtomicU64,
    step: u64,
}

impl SimClock {
    /// A clock at `start` ns that advances `step` ns per reading.
    pub fn new(start: u64, step: u64) -> SimClock {
        SimClock {
            now: AtomicU64::new(start),
            step,
        }
    }

    /// Moves the clock forward by `ns`.
    pub fn advance(&self, ns: u64) {
        self.now.fetch_add(ns, Relaxed);
    }

    /// The current time, without advancing.
    pub fn peek(&self) -> u64 {
        self.now.load(Relaxed)
    }
}

impl Clock for SimClock {
    fn now_ns(&self) -> u64 {
        self.now.fetch_add(self.step, Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sim_clock_steps_per_reading() {
        let c = SimClock::new(1000, 10);
        assert_eq!(c.now_ns(), 1000);
        assert_eq!(c.now_ns(), 1010);
        c.advance(500);
        assert_eq!(c.peek(), 1520);
    }

    #[test]
    fn monotonic_clock_does_not_go_back() {
        let c = MonotonicClock;
        let a = c.now_ns();
        assert!(c.now_ns() >= a);
    }
}
