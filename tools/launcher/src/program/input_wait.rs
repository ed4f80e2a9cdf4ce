//! M66 in task: waiting, once the moves before it have ended, for
//! `motion.digital-in-NN` to do what the block's L asks (LinuxCNC's
//! modes: 0 at once, 1 a rising edge, 2 a falling edge, 3 high, 4 low)
//! within its Q seconds; an analog input is read at once. The value is
//! read into #5399 when the interpreter synchronises (−1 after a
//! timeout).

use crate::motion_setup::MotionLink;

/// An M66 wait: LinuxCNC's modes (L) 0 at once, 1 a rising edge, 2 a
/// falling edge, 3 high, 4 low, on a digital input; analog inputs are
/// read at once.
#[derive(Debug, Clone, Copy)]
pub(super) struct InputWait {
    index: usize,
    mode: i32,
    deadline: std::time::Instant,
    /// The input's value when last looked at (for the edges).
    last: Option<bool>,
}

impl InputWait {
    pub(super) fn start(
        index: i32,
        digital: bool,
        mode: i32,
        timeout: f64,
        motion: &MotionLink,
    ) -> Self {
        let timeout = std::time::Duration::try_from_secs_f64(timeout.max(0.0))
            .unwrap_or(std::time::Duration::MAX / 2);
        let mut w = InputWait {
            index: usize::try_from(index).unwrap_or(usize::MAX),
            mode: if digital { mode } else { 0 },
            deadline: std::time::Instant::now() + timeout,
            last: None,
        };
        w.last = w.input(motion);
        w
    }

    /// The digital input now, if motion's status can be read.
    fn input(&self, motion: &MotionLink) -> Option<bool> {
        motion
            .status()
            .and_then(|s| s.io.din.get(self.index).copied())
    }

    /// Whether the wait is over: the input did what `mode` waits for, or
    /// the time ran out (`timed_out` set, as #5399 reads it).
    pub(super) fn done(&mut self, motion: &MotionLink, timed_out: &mut bool) -> bool {
        let now = self.input(motion);
        match self.step(now, std::time::Instant::now()) {
            Some(out_of_time) => {
                *timed_out = out_of_time;
                true
            }
            None => false,
        }
    }

    /// One look at the input (`now`, at time `at`): `None` while the
    /// wait goes on, else whether it ran out of time.
    fn step(&mut self, now: Option<bool>, at: std::time::Instant) -> Option<bool> {
        let before = std::mem::replace(&mut self.last, now);
        let met = match (self.mode, before, now) {
            (1, Some(false), Some(true)) => true,
            (2, Some(true), Some(false)) => true,
            (3, _, Some(true)) => true,
            (4, _, Some(false)) => true,
            (1..=4, _, _) => false,
            _ => true,
        };
        if met {
            Some(false)
        } else if at >= self.deadline {
            Some(true)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    fn wait(mode: i32, last: bool, t0: Instant) -> InputWait {
        InputWait {
            index: 0,
            mode,
            deadline: t0 + Duration::from_secs(1),
            last: Some(last),
        }
    }

    #[test]
    fn m66_modes_wait_for_edges_and_levels_until_the_timeout() {
        let t0 = Instant::now();
        // Rise: high at the start is not a rise.
        let mut w = wait(1, true, t0);
        assert_eq!(w.step(Some(true), t0), None);
        assert_eq!(w.step(Some(false), t0), None);
        assert_eq!(w.step(Some(true), t0), Some(false));
        let mut w = wait(2, false, t0);
        assert_eq!(w.step(Some(true), t0), None);
        assert_eq!(w.step(Some(false), t0), Some(false));
        assert_eq!(wait(3, false, t0).step(Some(true), t0), Some(false));
        assert_eq!(wait(4, false, t0).step(Some(false), t0), Some(false));
        // Immediate, and the timeout.
        assert_eq!(wait(0, false, t0).step(Some(false), t0), Some(false));
        let mut w = wait(3, false, t0);
        assert_eq!(w.step(Some(false), t0), None);
        let late = t0 + Duration::from_secs(2);
        assert_eq!(w.step(Some(false), late), Some(true));
    }
}
