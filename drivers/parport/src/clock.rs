//! The time source of the driver's write/reset timing and of the
//! simulator's write log: the driver layer's clocks.
//!
//! The driver remembers when it last wrote each register and `reset`
//! busy-waits until that time plus `reset-time`. On hardware the clock is
//! CLOCK_MONOTONIC ([`MonotonicClock`]); tests substitute a [`SimClock`]
//! made with [`SimClock::new`]`(start, step)`, which advances `step` ns on
//! every reading, so a busy-wait ends after a known number of polls and
//! the logged times are exact.

pub use hal_driver::sim::{Clock, MonotonicClock, SimClock};
