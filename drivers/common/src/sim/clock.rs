//! Time for drivers and simulated boards.
//!
//! * [`Clock`]: a nanosecond time source a driver reads for its own
//!   timing (hal_parport's `reset` busy-waits on one).
//!   [`MonotonicClock`] on hardware.
//! * [`SimClock`]: simulated time. A board's time moves only when told:
//!   by [`advance`](SimClock::advance) in tests, or, for a clock made by
//!   [`SimClock::following_thread`] (what a simulated board under `loadrt`
//!   uses), also by the HAL thread's elapsed time, which the driver's
//!   `read` function passes through
//!   [`RegWindow::tick`](crate::bus::RegWindow::tick). A clock may also step a fixed amount
//!   on every reading, so a driver busy-waiting on it in a test ends
//!   after a known number of polls.

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

/// "No thread time seen yet".
const NEVER: u64 = u64::MAX;

/// Simulated time.
#[derive(Debug)]
pub struct SimClock {
    now: AtomicU64,
    step: u64,
    follows_thread: bool,
    /// The thread time of the previous [`follow`](Self::follow).
    last_thread: AtomicU64,
}

impl SimClock {
    /// A clock at `start` ns that moves only by [`advance`](Self::advance)
    /// and by `step` ns after every reading through [`Clock::now_ns`].
    pub fn new(start: u64, step: u64) -> SimClock {
        SimClock {
            now: AtomicU64::new(start),
            step,
            follows_thread: false,
            last_thread: AtomicU64::new(NEVER),
        }
    }

    /// A clock at 0 that also moves by the HAL thread's elapsed time
    /// passed to [`follow`](Self::follow).
    pub fn following_thread() -> SimClock {
        SimClock {
            follows_thread: true,
            ..SimClock::new(0, 0)
        }
    }

    /// Whether [`follow`](Self::follow) moves this clock.
    pub fn follows_thread(&self) -> bool {
        self.follows_thread
    }

    /// Moves the clock forward by `ns`.
    pub fn advance(&self, ns: u64) {
        self.now.fetch_add(ns, Relaxed);
    }

    /// The current time, without stepping.
    pub fn peek(&self) -> u64 {
        self.now.load(Relaxed)
    }

    /// Takes the HAL thread's time `thread_now_ns` (`FunctCtx::now_ns`):
    /// a clock following the thread moves by the time elapsed since the
    /// previous call and returns it. The first call, a clock not following
    /// the thread, and time that did not move forward return 0.
    /// Realtime-safe (atomics only); callers in several threads each
    /// account for their own interval, so no time is counted twice.
    #[inline]
    pub fn follow(&self, thread_now_ns: u64) -> u64 {
        if !self.follows_thread {
            return 0;
        }
        let prev = self.last_thread.swap(thread_now_ns, Relaxed);
        if prev == NEVER || thread_now_ns <= prev {
            return 0;
        }
        let dt = thread_now_ns - prev;
        self.advance(dt);
        dt
    }
}

impl Clock for SimClock {
    #[inline]
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
        assert_eq!(c.follow(5_000_000), 0, "explicit clocks ignore thread time");
        assert_eq!(c.peek(), 1520);
    }

    #[test]
    fn a_following_clock_moves_by_thread_time() {
        let c = SimClock::following_thread();
        assert_eq!(c.follow(1_000_000), 0, "first sight only sets the origin");
        assert_eq!(c.follow(2_000_000), 1_000_000);
        assert_eq!(c.follow(2_000_000), 0);
        assert_eq!(c.follow(1_500_000), 0, "time going back is ignored");
        assert_eq!(c.follow(2_500_000), 1_000_000);
        c.advance(7);
        assert_eq!(c.peek(), 2_000_007);
    }

    #[test]
    fn monotonic_clock_does_not_go_back() {
        let c = MonotonicClock;
        let a = c.now_ns();
        assert!(c.now_ns() >= a);
    }
}
