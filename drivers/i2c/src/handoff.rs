//! The lock-free hand-offs between a chip's realtime functions and the
//! bus's helper thread.
//!
//! Each direction is a triple buffer (the `triple_buffer` crate): the
//! writer always has a buffer of its own to fill and publishes it with
//! one atomic swap; the reader takes the newest published buffer with
//! one atomic swap. Neither side ever waits for the other, allocates or
//! makes a system call, so a realtime function is never held up by a
//! transfer in progress, and the reader always gets a whole, consistent
//! value (all 16 PWM counts of one `write`, all four conversions of one
//! helper cycle), never a mix of two.
//!
//! * [`CmdPort`] → [`CmdFeed`]: the realtime `write` function's command
//!   (outputs) to the helper thread.
//! * [`StatusFeed`] → [`StatusPort`]: the helper thread's [`Status`]
//!   (inputs, fault, error count) to the realtime `read` function.
//! * [`Flags`]: a few atomics for what is not a value: the safe-state
//!   request of the safe-state hook and its acknowledgement, and the
//!   fault-reset requests.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::*};
use std::sync::Arc;
use std::time::{Duration, Instant};

use triple_buffer::{Input, Output, TripleBuffer};

/// What the helper thread tells the realtime side about a chip.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Status<S> {
    /// The chip's latest inputs.
    pub sample: S,
    /// The chip's fault latch: set at the first failure, cleared by a
    /// fault reset once the chip works again.
    pub fault: bool,
    /// Failed transfers (and set-up attempts) so far.
    pub errors: u32,
    /// Helper cycles that completed for this chip.
    pub cycles: u64,
}

/// The realtime `write` function's end of the command hand-off.
pub struct CmdPort<C: Send> {
    input: Input<C>,
    flags: Arc<Flags>,
}

impl<C: Send> CmdPort<C> {
    /// Publishes `cmd`, which the helper thread's next cycle takes; a
    /// newer command replaces one not taken yet. Also ends a safe-state
    /// hold: a `write` that runs means the threads run again.
    #[inline]
    pub fn publish(&mut self, cmd: C) {
        self.input.write(cmd);
        self.flags.hold_safe.store(false, Relaxed);
    }
}

/// The helper thread's end of the command hand-off.
pub struct CmdFeed<C: Send> {
    output: Output<C>,
}

impl<C: Send + Copy> CmdFeed<C> {
    /// The newest command published.
    pub fn latest(&mut self) -> C {
        *self.output.read()
    }
}

/// The helper thread's end of the status hand-off.
pub struct StatusFeed<S: Send> {
    input: Input<Status<S>>,
}

impl<S: Send> StatusFeed<S> {
    /// Publishes `status` for the realtime side.
    pub fn publish(&mut self, status: Status<S>) {
        self.input.write(status);
    }
}

/// The realtime `read` function's end of the status hand-off.
pub struct StatusPort<S: Send> {
    output: Output<Status<S>>,
    flags: Arc<Flags>,
    reset_level: bool,
}

impl<S: Send> StatusPort<S> {
    /// The newest status published.
    #[inline]
    pub fn latest(&mut self) -> &Status<S> {
        self.output.read()
    }

    /// Follows the `fault-reset` pin: its rising edge asks the helper
    /// thread to clear the fault latch.
    #[inline]
    pub fn fault_reset(&mut self, level: bool) {
        if level && !self.reset_level {
            let n = self.flags.reset_requests.load(Relaxed);
            self.flags.reset_requests.store(n + 1, Relaxed);
        }
        self.reset_level = level;
    }
}

/// The flags of one chip.
#[derive(Debug, Default)]
pub struct Flags {
    /// Outputs held in their safe state until the next `write`.
    hold_safe: AtomicBool,
    /// Safe-state requests made.
    safe_requested: AtomicU64,
    /// The newest request the helper thread has carried out.
    safe_done: AtomicU64,
    /// Fault resets asked for by the `fault-reset` pin.
    reset_requests: AtomicU64,
}

impl Flags {
    /// Whether the outputs are held safe.
    pub fn holding_safe(&self) -> bool {
        self.hold_safe.load(Relaxed)
    }

    /// The newest safe-state request (for [`Flags::safe_applied`]).
    pub fn safe_request(&self) -> u64 {
        self.safe_requested.load(Acquire)
    }

    /// The helper thread carried out safe-state request `n`.
    pub fn safe_applied(&self, n: u64) {
        self.safe_done.fetch_max(n, Release);
    }

    /// Fault resets asked for so far.
    pub fn reset_requests(&self) -> u64 {
        self.reset_requests.load(Relaxed)
    }

    /// The safe-state hook: holds the outputs safe and waits (up to
    /// `timeout`) until the helper thread has written them; whether it
    /// did.
    pub fn go_safe(&self, timeout: Duration) -> bool {
        self.hold_safe.store(true, Relaxed);
        let n = self.safe_requested.fetch_add(1, AcqRel) + 1;
        let end = Instant::now() + timeout;
        while self.safe_done.load(Acquire) < n {
            if Instant::now() >= end {
                return false;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        true
    }
}

/// Both hand-offs of one chip and their flags: the realtime ends and
/// the helper thread's ends.
pub struct Handoff<C: Send, S: Send> {
    /// For the realtime `write` function.
    pub cmd_port: CmdPort<C>,
    /// For the helper thread.
    pub cmd_feed: CmdFeed<C>,
    /// For the helper thread.
    pub status_feed: StatusFeed<S>,
    /// For the realtime `read` function.
    pub status_port: StatusPort<S>,
    /// For the safe-state hook and the helper thread.
    pub flags: Arc<Flags>,
}

impl<C: Send + Clone + Default, S: Send + Clone + Default> Handoff<C, S> {
    /// New hand-offs holding `C::default()` and a clear status.
    pub fn new() -> Handoff<C, S> {
        let flags = Arc::new(Flags::default());
        let (cmd_in, cmd_out) = TripleBuffer::new(&C::default()).split();
        let (st_in, st_out) = TripleBuffer::new(&Status::<S>::default()).split();
        Handoff {
            cmd_port: CmdPort {
                input: cmd_in,
                flags: flags.clone(),
            },
            cmd_feed: CmdFeed { output: cmd_out },
            status_feed: StatusFeed { input: st_in },
            status_port: StatusPort {
                output: st_out,
                flags: flags.clone(),
                reset_level: false,
            },
            flags,
        }
    }
}

impl<C: Send + Clone + Default, S: Send + Clone + Default> Default for Handoff<C, S> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latest_values_cross_whole() {
        let mut h = Handoff::<[u16; 16], u32>::new();
        assert_eq!(h.cmd_feed.latest(), [0; 16]);
        h.cmd_port.publish([1; 16]);
        h.cmd_port.publish([2; 16]);
        assert_eq!(h.cmd_feed.latest(), [2; 16], "the newest wins");
        assert_eq!(h.cmd_feed.latest(), [2; 16], "and stays");
        h.status_feed.publish(Status {
            sample: 7,
            fault: true,
            errors: 3,
            cycles: 9,
        });
        let s = *h.status_port.latest();
        assert_eq!((s.sample, s.fault, s.errors, s.cycles), (7, true, 3, 9));
    }

    #[test]
    fn fault_reset_counts_rising_edges() {
        let mut h = Handoff::<(), ()>::new();
        for level in [false, true, true, false, true, false, false] {
            h.status_port.fault_reset(level);
        }
        assert_eq!(h.flags.reset_requests(), 2);
    }

    #[test]
    fn go_safe_waits_for_the_helper_and_write_ends_the_hold() {
        let mut h = Handoff::<u8, ()>::new();
        let flags = h.flags.clone();
        let helper = std::thread::spawn(move || {
            while flags.safe_request() == 0 {
                std::thread::sleep(Duration::from_micros(100));
            }
            assert!(flags.holding_safe());
            flags.safe_applied(flags.safe_request());
        });
        assert!(h.flags.go_safe(Duration::from_secs(30)));
        helper.join().unwrap();
        assert!(h.flags.holding_safe());
        h.cmd_port.publish(1);
        assert!(!h.flags.holding_safe());
        assert!(
            !h.flags.go_safe(Duration::from_millis(1)),
            "nobody answers: timeout"
        );
    }
}
