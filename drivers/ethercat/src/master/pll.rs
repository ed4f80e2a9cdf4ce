//! `syncToRefClock`: the master's application time follows the
//! reference clock, with linuxcnc-ethercat's bang-bang controller and
//! its pins (`pll-err`, `pll-out`, `pll-reset-count`, parameters
//! `pll-step`, `pll-max-err`).
//!
//! Each cycle the application time is the time of the cycle's first
//! deadline plus the whole periods since, plus the corrections so far,
//! plus how late the thread runs in its period. The error is last
//! cycle's application time minus the reference clock's time in that
//! cycle's frame (the low 32 bits of each, as lcec compares them). An
//! error within `pll-max-err` gives a correction of `pll-step` ns
//! against it (`pll-out`: positive means "the period is long by
//! this"); a larger one is taken out at once, counted in
//! `pll-reset-count`, and the next cycle is not compared.
//!
//! LinuxCNC's RTAPI moves the servo thread's next wake-up by
//! `pll-out`. Our host's threads keep their own period, so here the
//! correction is taken out of the application time instead: a period
//! `pll-out` longer on the reference clock is the same as an
//! application time `pll-out` shorter per period. The application time
//! (`app-time-*`) follows the reference clock either way; the servo
//! thread's wake-ups stay on the host's clock.

/// The default `pll-step`: 0.1 % of the period, as lcec.
pub fn default_step(period_ns: u64) -> u32 {
    (period_ns / 1000).min(u64::from(u32::MAX)) as u32
}

/// The default `pll-max-err`: one period, as lcec.
pub fn default_max_err(period_ns: u64) -> u32 {
    period_ns.min(u64::from(u32::MAX)) as u32
}

/// The largest `pll-step` taken: 1 % of the period (lcec's limit).
pub fn step_limit(period_ns: u64) -> u32 {
    (period_ns / 100).min(u64::from(u32::MAX)) as u32
}

/// What one cycle of the controller gives, for the pins.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PllCycle {
    /// The cycle's application time (EtherCAT ns).
    pub app_time: u64,
    /// `pll-err`: last cycle's application time minus the reference
    /// clock's time of that cycle's frame (0 when not compared).
    pub err: i32,
    /// `pll-out`: the correction, ±`pll-step` or 0.
    pub out: i32,
}

/// The controller's state across cycles. No allocation; every method is
/// a few integer operations.
#[derive(Debug, Clone, Default)]
pub struct Pll {
    /// The application time of the first cycle's deadline.
    origin: Option<u64>,
    /// Whole periods since then, plus the corrections (ns).
    elapsed: i64,
    last_deadline: u64,
    /// Low 32 bits of last cycle's application time.
    app_time_last: u32,
    /// Last cycle's reference time was usable.
    valid_last: bool,
    /// `pll-reset-count`.
    resets: u32,
}

impl Pll {
    /// A controller that has not run.
    pub fn new() -> Pll {
        Pll::default()
    }

    /// Resets so far (`pll-reset-count`).
    pub fn resets(&self) -> u32 {
        self.resets
    }

    /// One cycle.
    ///
    /// * `app_of_deadline`: the application time of this cycle's
    ///   deadline on the host's clock (used once, for the origin);
    /// * `now`, `deadline`: CLOCK_MONOTONIC ns when the thread woke and
    ///   the deadline it serves; `period` the thread's period (ns);
    /// * `reference`: the reference clock's time in last cycle's frame,
    ///   None when that frame did not come back or no slave has DC;
    /// * `step`, `max_err`: the parameters (`step` limited to
    ///   [`step_limit`]).
    #[allow(
        clippy::too_many_arguments,
        reason = "one cycle's inputs, each a plain number"
    )]
    pub fn cycle(
        &mut self,
        app_of_deadline: u64,
        now: u64,
        deadline: u64,
        period: u64,
        reference: Option<u64>,
        step: u32,
        max_err: u32,
    ) -> PllCycle {
        let period = period.max(1);
        let origin = *self.origin.get_or_insert(app_of_deadline);
        if self.last_deadline != 0 {
            // Whole periods (a skipped deadline counts), at least one.
            let since = deadline.saturating_sub(self.last_deadline);
            let periods = ((since + period / 2) / period).max(1);
            self.elapsed = self
                .elapsed
                .wrapping_add(periods.saturating_mul(period) as i64);
        }
        self.last_deadline = deadline;
        let late = now.saturating_sub(deadline) as i64;
        let app_time = origin
            .wrapping_add_signed(self.elapsed)
            .wrapping_add_signed(late);
        let step = step.min(step_limit(period)) as i32;
        let mut valid = reference.is_some();
        let mut c = PllCycle {
            app_time,
            err: 0,
            out: 0,
        };
        if let (Some(r), true) = (reference, self.valid_last) {
            c.err = self.app_time_last.wrapping_sub(r as u32) as i32;
            if c.err.unsigned_abs() > max_err {
                // Too far to pull: take it out at once, skip a cycle.
                self.elapsed = self.elapsed.wrapping_sub(i64::from(c.err));
                valid = false;
                self.resets = self.resets.wrapping_add(1);
            } else {
                c.out = if c.err < 0 { -step } else { step };
            }
        }
        // A period longer by `out` on the reference clock: the
        // application time `out` shorter per period.
        self.elapsed = self.elapsed.wrapping_sub(i64::from(c.out));
        self.app_time_last = app_time as u32;
        self.valid_last = valid;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: u64 = 1_000_000;

    /// The application time starting at `start`, a reference clock
    /// running `ppm` fast starting at `start + ahead`; each frame passes
    /// it `latency` ns after the thread's deadline, which the thread
    /// misses by 3 µs.
    fn run(pll: &mut Pll, cycles: u64, ppm: i64, ahead: u64, latency: u64) -> Vec<PllCycle> {
        let start = 5_000_000_000;
        let mut out = Vec::new();
        let mut last_ref = None;
        for n in 1..=cycles {
            let deadline = n * P;
            let c = pll.cycle(
                start + deadline,
                deadline + 3_000,
                deadline,
                P,
                last_ref,
                default_step(P),
                default_max_err(P),
            );
            let at = (deadline + latency) as i64;
            last_ref = Some((start as i64 + ahead as i64 + at + at * ppm / 1_000_000) as u64);
            out.push(c);
        }
        out
    }

    #[test]
    fn a_drifting_reference_is_followed_within_a_few_steps() {
        let mut pll = Pll::new();
        let cycles = run(&mut pll, 20_000, 300, 0, 20_000);
        // Without the controller the error would reach 300 ppm × 20 s = 6 ms.
        for c in &cycles[2_000..] {
            assert!(c.err.abs() <= 3 * default_step(P) as i32, "{c:?}");
            assert_eq!(c.out.abs(), default_step(P) as i32);
        }
        assert_eq!(pll.resets(), 0);
    }

    #[test]
    fn an_error_past_the_limit_is_taken_out_and_counted() {
        let mut pll = Pll::new();
        // The reference is 5 periods ahead of the application time.
        let cycles = run(&mut pll, 50, 0, 5 * P, 0);
        assert_eq!(pll.resets(), 1);
        assert!(cycles[2].err.unsigned_abs() > default_max_err(P));
        assert_eq!(cycles[2].out, 0);
        // Then it is compared again and small.
        assert!(
            cycles[49].err.unsigned_abs() <= 2 * default_step(P),
            "{:?}",
            cycles[49]
        );
    }

    #[test]
    fn nothing_is_compared_without_a_reference_and_steps_are_limited() {
        let mut pll = Pll::new();
        let c = pll.cycle(100, 10, 10, P, None, 1, 1);
        assert_eq!((c.err, c.out, c.app_time), (0, 0, 100));
        let c = pll.cycle(0, P + 10, P + 10, P, Some(50), u32::MAX, u32::MAX);
        assert_eq!((c.err, c.out), (0, 0), "one valid cycle is not enough");
        let c = pll.cycle(0, 2 * P + 10, 2 * P + 10, P, Some(50), u32::MAX, u32::MAX);
        assert_eq!(c.out, step_limit(P) as i32);
        // A skipped deadline still advances the time by whole periods.
        let before = c.app_time;
        let c = pll.cycle(0, 5 * P + 10, 5 * P + 10, P, None, 0, u32::MAX);
        assert_eq!(c.app_time - before, 3 * P - step_limit(P) as u64);
    }
}
