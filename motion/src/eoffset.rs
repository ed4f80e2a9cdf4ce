//! External axis offsets: one world axis's offset planner, driven by the
//! `axis.L.eoffset-*` pins, whose output is added to the planned position
//! of that axis in teleop and coordinated mode.
//!
//! `[AXIS_L]OFFSET_AV_RATIO` (r, 0..=0.9) splits the axis's velocity and
//! acceleration limits: planned moves (teleop jogs, the coordinated
//! planner) get `(1 - r)` of them, the offset `r`, so that their sum stays
//! within the axis's limits. With r = 0 the offset pins do nothing.
//!
//! Each servo period (see [`ExtOffset::take_inputs`]) the change of
//! `eoffset-counts` since the last period, times `eoffset-scale`, is added
//! to a register, the requested offset (`eoffset-request`), while the
//! axis's `eoffset-enable` is true, motion is enabled and every joint is
//! homed; `eoffset-clear` sets the request to zero. The applied offset
//! (`axis.L.eoffset`) follows the request with a trapezoidal profile
//! ([`SimpleTp`]) at the offset's share of the limits
//! ([`ExtOffset::update`]).
//!
//! What LinuxCNC's documentation ("External Axis Offsets") asks for, and
//! how it is done here:
//! * `eoffset-enable` false: the offset planner brakes to a stop at its
//!   acceleration limit and holds the offset there; the request follows
//!   the held value, so counting back from there returns the offset to
//!   zero. Counts turned meanwhile are dropped, as are counts turned while
//!   motion is disabled or a joint is not homed.
//! * Soft limits: the planned position plus the offset stays within the
//!   axis's `[MIN_LIMIT, MAX_LIMIT]`. An offset that would carry the axis
//!   past a limit is cut to reach the limit exactly and its velocity
//!   zeroed (no deceleration: the documentation warns of it);
//!   `motion.eoffset-limited` is true while an axis with a non-zero offset
//!   sits on a limit. The request is not changed, so the offset resumes
//!   towards it when the planned position moves back inside. An offset
//!   never pushes an axis that is already beyond a limit further out.
//! * Machine off keeps the position, offset included (nothing moves); at
//!   machine on the offset and its register are zeroed and the planned
//!   position starts where the axis is, so nothing moves then either (see
//!   `core::eoffset`).

use crate::simple_tp::SimpleTp;

/// The largest `OFFSET_AV_RATIO`.
pub const MAX_RATIO: f64 = 0.9;

/// The value LinuxCNC uses in place of an `OFFSET_AV_RATIO` outside
/// `0..=0.9`.
pub const FALLBACK_RATIO: f64 = 0.1;

/// Closer than this to a soft limit counts as on it.
const AT_LIMIT: f64 = 1e-9;

/// An axis's external-offset inputs (`axis.L.eoffset-*`), read every
/// servo cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EoffsetInputs {
    /// `axis.L.eoffset-enable`.
    pub enable: bool,
    /// `axis.L.eoffset-clear`: the request becomes zero.
    pub clear: bool,
    /// `axis.L.eoffset-counts`: its change is added to the request.
    pub counts: i32,
    /// `axis.L.eoffset-scale`: distance per count.
    pub scale: f64,
}

/// What may change the request this period.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Intake {
    /// The axis has no share of the limits (ratio 0): nothing changes.
    Off,
    /// Motion is disabled or a joint is not homed: counts are dropped,
    /// the enable and clear inputs still act.
    Hold,
    /// Counts add to the request.
    Accept,
}

/// One axis's external offset: the request register and the planner
/// that applies it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ExtOffset {
    /// Position: the applied offset; target: the request (or, while
    /// `eoffset-enable` is false, the held offset).
    tp: SimpleTp,
    /// The requested offset (`axis.L.eoffset-request`).
    request: f64,
    /// `eoffset-counts` as last seen.
    old_counts: i32,
    /// The counts have been seen once (the first period only records them).
    counts_seen: bool,
    /// On a soft limit with a non-zero offset this period.
    limited: bool,
}

impl ExtOffset {
    /// The applied offset (`axis.L.eoffset`).
    pub fn applied(&self) -> f64 {
        self.tp.curr_pos
    }

    /// The requested offset (`axis.L.eoffset-request`).
    pub fn request(&self) -> f64 {
        self.request
    }

    /// The velocity at which the offset changes.
    pub fn velocity(&self) -> f64 {
        self.tp.curr_vel
    }

    /// Whether `eoffset-enable` was true when the inputs were last taken.
    pub fn enabled(&self) -> bool {
        self.tp.enable
    }

    /// Whether the offset planner moves.
    pub fn moving(&self) -> bool {
        self.tp.active
    }

    /// Whether the axis sat on a soft limit with a non-zero offset in the
    /// last update.
    pub fn limited(&self) -> bool {
        self.limited
    }

    /// Whether the applied offset counts as non-zero: beyond the planner's
    /// dead band for `max_acc` and `period` (exactly zero when there is no
    /// acceleration to judge by).
    pub fn is_active(&self, max_acc: f64, period: f64) -> bool {
        self.tp.curr_pos.abs() > SimpleTp::tiny_dp(max_acc, period)
    }

    /// Zero offset, zero request, at rest (machine on). The counts keep
    /// their last value: only later changes count.
    pub fn reset(&mut self) {
        self.tp.set_at_rest(0.0);
        self.request = 0.0;
        self.limited = false;
    }

    /// Takes this period's inputs: the change of the counts, the enable
    /// and clear inputs (see the module documentation).
    pub fn take_inputs(&mut self, inp: &EoffsetInputs, intake: Intake) {
        let delta = inp.counts.wrapping_sub(self.old_counts);
        self.old_counts = inp.counts;
        let first = !self.counts_seen;
        self.counts_seen = true;
        if intake == Intake::Off {
            return;
        }
        if !inp.enable {
            // The planner brakes and forgets its target; the request
            // follows what it holds.
            self.tp.enable = false;
            self.request = self.tp.curr_pos;
            return;
        }
        self.tp.enable = true;
        if inp.clear {
            self.request = 0.0;
        } else if intake == Intake::Accept && !first && delta != 0 {
            let next = self.request + f64::from(delta) * inp.scale;
            if next.is_finite() {
                self.request = next;
            }
        }
        self.tp.pos_cmd = self.request;
    }

    /// One period of `period` seconds in a world mode: the offset moves
    /// towards its target within `max_vel` and `max_acc`, then is bounded
    /// so that `planned` plus the offset stays within `[min, max]`.
    /// Returns the applied offset. With no velocity or acceleration share
    /// the offset stands still.
    pub fn update(
        &mut self,
        period: f64,
        (max_vel, max_acc): (f64, f64),
        planned: f64,
        (min, max): (f64, f64),
    ) -> f64 {
        if max_vel > 0.0 && max_acc > 0.0 {
            self.tp.max_vel = max_vel;
            self.tp.max_acc = max_acc;
            self.tp.update(period, 1.0);
        }
        self.limited = self.bound(planned, min, max);
        self.tp.curr_pos
    }

    /// Cuts the offset so that `planned + offset` stays within
    /// `[min, max]`, never pushing further out than `planned` alone is;
    /// true if the axis is on a limit with a non-zero offset.
    fn bound(&mut self, planned: f64, min: f64, max: f64) -> bool {
        let o = self.tp.curr_pos;
        if o == 0.0 {
            return false;
        }
        let highest = (max - planned).max(0.0);
        let lowest = (min - planned).min(0.0);
        let cut = if o > highest {
            Some(highest)
        } else if o < lowest {
            Some(lowest)
        } else {
            None
        };
        if let Some(v) = cut {
            self.tp.curr_pos = v;
            self.tp.curr_vel = 0.0;
            return true;
        }
        let sum = planned + o;
        sum >= max - AT_LIMIT || sum <= min + AT_LIMIT
    }
}

/// `OFFSET_AV_RATIO` as motion takes it: finite and within `0..=0.9`.
pub fn ratio_ok(ratio: f64) -> bool {
    ratio.is_finite() && (0.0..=MAX_RATIO).contains(&ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: f64 = 0.001;
    const LIM: (f64, f64) = (2.0, 20.0);
    const WIDE: (f64, f64) = (-1e99, 1e99);

    fn inputs(counts: i32, scale: f64) -> EoffsetInputs {
        EoffsetInputs {
            enable: true,
            clear: false,
            counts,
            scale,
        }
    }

    /// An offset whose counts were seen once at 0.
    fn fresh() -> ExtOffset {
        let mut e = ExtOffset::default();
        e.take_inputs(&inputs(0, 0.0), Intake::Accept);
        e
    }

    /// Runs `n` periods with the planned position 0 and wide limits,
    /// checking the velocity and acceleration shares every period.
    fn run(e: &mut ExtOffset, inp: &EoffsetInputs, n: usize) {
        for _ in 0..n {
            let v0 = e.velocity();
            e.take_inputs(inp, Intake::Accept);
            e.update(T, LIM, 0.0, WIDE);
            assert!(e.velocity().abs() <= LIM.0 + 1e-12, "{}", e.velocity());
            let acc = (e.velocity() - v0).abs() / T;
            assert!(acc <= LIM.1 * (1.0 + 1e-9), "acceleration {acc}");
        }
    }

    #[test]
    fn the_offset_reaches_the_request_within_its_limits() {
        let mut e = fresh();
        let inp = inputs(4, 0.25);
        run(&mut e, &inp, 1);
        assert_eq!(e.request(), 1.0);
        // 1.0 at 2/s, 20/s²: about 0.6 s.
        run(&mut e, &inp, 800);
        assert!((e.applied() - 1.0).abs() < 1e-6, "{}", e.applied());
        assert!(!e.moving());
        assert!(e.is_active(LIM.1, T));
    }

    #[test]
    fn counts_accumulate_as_changes_times_the_scale_of_the_moment() {
        let mut e = fresh();
        e.take_inputs(&inputs(10, 0.1), Intake::Accept);
        e.take_inputs(&inputs(20, 0.5), Intake::Accept);
        assert!((e.request() - 6.0).abs() < 1e-12);
        // Wrapping counters count on.
        let mut w = ExtOffset::default();
        w.take_inputs(&inputs(i32::MAX, 1.0), Intake::Accept);
        w.take_inputs(&inputs(i32::MIN, 1.0), Intake::Accept);
        assert_eq!(w.request(), 1.0);
    }

    #[test]
    fn the_first_period_only_records_the_counts() {
        let mut e = ExtOffset::default();
        e.take_inputs(&inputs(500, 1.0), Intake::Accept);
        assert_eq!(e.request(), 0.0);
    }

    #[test]
    fn counts_while_held_or_off_are_dropped() {
        let mut e = fresh();
        e.take_inputs(&inputs(5, 1.0), Intake::Hold);
        assert_eq!(e.request(), 0.0);
        e.take_inputs(&inputs(7, 1.0), Intake::Accept);
        assert_eq!(e.request(), 2.0, "only the change since the last period");
        let mut off = fresh();
        off.take_inputs(&inputs(9, 1.0), Intake::Off);
        off.update(T, (0.0, 0.0), 0.0, WIDE);
        assert_eq!((off.request(), off.applied()), (0.0, 0.0));
    }

    #[test]
    fn clear_drives_the_offset_back_to_zero() {
        let mut e = fresh();
        run(&mut e, &inputs(100, 0.01), 1000);
        assert!((e.applied() - 1.0).abs() < 1e-6);
        let clear = EoffsetInputs {
            clear: true,
            ..inputs(100, 0.01)
        };
        run(&mut e, &clear, 1);
        assert_eq!(e.request(), 0.0);
        run(&mut e, &clear, 1000);
        assert!(e.applied().abs() < 1e-6 && !e.is_active(LIM.1, T));
    }

    #[test]
    fn enable_off_holds_the_offset_and_counting_back_returns_it() {
        let mut e = fresh();
        run(&mut e, &inputs(100, 0.01), 1000);
        let held = e.applied();
        let off = EoffsetInputs {
            enable: false,
            ..inputs(300, 0.01)
        };
        run(&mut e, &off, 500);
        assert_eq!(e.applied(), held, "held");
        assert_eq!(e.request(), held, "the request follows the held offset");
        // Re-enabled at 300 counts: counting back by the 100 counts that
        // made the offset returns it to zero.
        run(&mut e, &inputs(300, 0.01), 1);
        run(&mut e, &inputs(200, 0.01), 1000);
        assert!(e.applied().abs() < 1e-6, "{}", e.applied());
    }

    #[test]
    fn enable_off_while_moving_brakes_within_the_acceleration_share() {
        let mut e = fresh();
        run(&mut e, &inputs(100, 0.1), 300);
        assert!(e.velocity() > 1.0);
        let off = EoffsetInputs {
            enable: false,
            ..inputs(100, 0.1)
        };
        run(&mut e, &off, 300);
        assert_eq!(e.velocity(), 0.0);
        let held = e.applied();
        assert!(held > 0.0 && held < 10.0);
        run(&mut e, &off, 10);
        assert_eq!(e.applied(), held);
    }

    #[test]
    fn the_soft_limit_cuts_the_offset_and_says_so() {
        let mut e = fresh();
        let inp = inputs(100, 0.1);
        let limits = (-10.0, 5.0);
        let mut planned = 3.0;
        for _ in 0..3000 {
            e.take_inputs(&inp, Intake::Accept);
            let o = e.update(T, LIM, planned, limits);
            assert!(planned + o <= 5.0 + 1e-12, "{}", planned + o);
        }
        assert!((e.applied() - 2.0).abs() < 1e-12 && e.limited());
        assert_eq!(e.request(), 10.0, "the request is kept");
        // The planned position moves on towards the limit: the sum stays
        // on it, the offset shrinks.
        for _ in 0..1000 {
            planned += 0.001;
            let o = e.update(T, LIM, planned, limits);
            assert!(planned + o <= 5.0 + 1e-12);
        }
        assert!((e.applied() - 1.0).abs() < 1e-9 && e.limited());
        // Moved back inside, the offset resumes towards the request and
        // the flag clears once the axis leaves the limit.
        planned = -9.0;
        e.update(T, LIM, planned, limits);
        assert!(!e.limited());
    }

    #[test]
    fn an_offset_never_pushes_further_past_a_limit() {
        let mut e = fresh();
        run(&mut e, &inputs(-100, 0.01), 1000);
        assert!((e.applied() + 1.0).abs() < 1e-6);
        // Planned below the lower limit: the negative offset goes.
        e.update(T, LIM, -11.0, (-10.0, 10.0));
        assert_eq!(e.applied(), 0.0);
        assert_eq!(e.velocity(), 0.0);
        // A positive offset may stay: it pulls the axis back in.
        let mut p = fresh();
        run(&mut p, &inputs(100, 0.01), 1000);
        let before = p.applied();
        p.update(T, LIM, -11.0, (-10.0, 10.0));
        assert_eq!(p.applied(), before);
    }

    #[test]
    fn a_zero_offset_is_never_limited() {
        let mut e = fresh();
        e.update(T, LIM, 10.0, (-10.0, 10.0));
        assert!(!e.limited());
    }

    #[test]
    fn reset_zeroes_offset_and_request() {
        let mut e = fresh();
        run(&mut e, &inputs(100, 0.01), 100);
        e.reset();
        assert_eq!((e.applied(), e.request(), e.velocity()), (0.0, 0.0, 0.0));
        assert!(!e.moving());
        // Only later changes count.
        e.take_inputs(&inputs(101, 0.01), Intake::Accept);
        assert!((e.request() - 0.01).abs() < 1e-15);
    }

    #[test]
    fn bad_scales_leave_the_request() {
        let mut e = fresh();
        e.take_inputs(&inputs(1, f64::NAN), Intake::Accept);
        e.take_inputs(&inputs(2, f64::INFINITY), Intake::Accept);
        assert_eq!(e.request(), 0.0);
    }

    #[test]
    fn ratios() {
        assert!(ratio_ok(0.0) && ratio_ok(0.9) && ratio_ok(0.25));
        assert!(!ratio_ok(-0.1) && !ratio_ok(0.95) && !ratio_ok(f64::NAN));
    }
}
