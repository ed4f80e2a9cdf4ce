//! Running the queue, once per servo period: the speed along the path,
//! the pose, segments finishing, dwells, pause, single steps and abort.
//!
//! The trapezoidal executor chooses each period's path speed as the
//! largest one that is at most one acceleration step from the last, not
//! above the segment's speed cap, not above the programmed speed times
//! the feed scale (a soft target: a drop is followed at the acceleration
//! limit), and from which the end of the segment can still be reached at
//! its look-ahead speed ([`v_stop`] for a stop, [`v_cross`] for a corner
//! crossed at speed). A step that passes a corner carries on into the next
//! segment. A stop lands exactly on its point, and the period after it
//! stands still, so the velocity never turns a corner at once.

use super::scurve::Mode;
use super::segment::{Segment, SegmentKind};
use super::trapezoid::{v_cross, v_stop};
use super::{Planner, PlannerType, ScaleInputs};
use crate::kins::Pose;

/// The speed for the coming period from which distance `d` can still be
/// covered ending at `c` (0: at rest) braking at `a`.
fn brake_speed(d: f64, c: f64, a: f64, t: f64) -> f64 {
    if c <= 0.0 {
        v_stop(d, a, t)
    } else {
        v_cross(d, c, a, t)
    }
}

impl Planner {
    /// The speed a segment asks for at scale `scale` (soft; 0 while
    /// paused or aborting).
    fn target_speed(&self, seg: &Segment, scales: &ScaleInputs, scale: f64) -> f64 {
        let vmax = seg.budget.vmax;
        if let Some(lock) = seg.locked {
            // A synchronised segment after the executing one: the
            // spindle's speed, neither paused nor scaled.
            let rps = scales.spindle_rps.get(lock.spindle).copied().unwrap_or(0.0);
            let v = lock.per_rev * rps.abs();
            return if v.is_finite() && !self.aborting {
                v.min(vmax)
            } else {
                0.0
            };
        }
        if self.paused || self.aborting {
            return 0.0;
        }
        if seg.kind == SegmentKind::Traverse {
            return vmax * scale.min(1.0);
        }
        let req = match seg.per_rev {
            // G95: the path speed follows the spindle's measured speed,
            // whichever way it turns.
            Some(f) => {
                let rps = scales.spindle_rps.get(f.spindle).copied().unwrap_or(0.0);
                if rps.is_finite() {
                    f.per_rev * rps.abs()
                } else {
                    0.0
                }
            }
            None => seg.req_vel,
        };
        (req * scale).min(vmax)
    }

    /// The acceleration the executing segment brakes with: its own, or
    /// the next segment's if smaller when the corner is crossed at speed
    /// (the period crossing it must stay within both budgets).
    pub(super) fn brake_acc(&self, head: &Segment) -> f64 {
        match self.queue.get(1) {
            Some(next) if head.ve > 0.0 => head.budget.acc.min(next.budget.acc),
            _ => head.budget.acc,
        }
    }

    /// The fastest speed for the coming period that still keeps the
    /// executing segment's end speed.
    pub(super) fn hard_brake_speed(&self, head: &Segment) -> f64 {
        brake_speed(
            head.len - self.s,
            head.ve,
            self.brake_acc(head),
            self.period,
        )
    }

    /// One servo period; returns the commanded pose.
    pub fn run(&mut self, scales: &ScaleInputs) -> Pose {
        self.requested_vel = 0.0;
        self.track.arm = None;
        self.max_feed_scale = scales.max_feed_override.max(0.0);
        if self.hold {
            // The period at rest after an exact stop.
            self.hold = false;
            self.v = 0.0;
            self.a = 0.0;
            return self.pos;
        }
        if self.aborting && self.v == 0.0 && self.a == 0.0 {
            self.clear();
            return self.pos;
        }
        if self.indexer_step(scales.unlocked) {
            // A locking indexer is unlocking or relocking, at rest.
            self.exec_id = self.queue.front().map_or(self.exec_id, |h| h.id);
            return self.pos;
        }
        let Some(head) = self.queue.front().copied() else {
            self.v = 0.0;
            self.a = 0.0;
            // An empty queue ends the lock to the spindle.
            self.track = Default::default();
            if let Some(p) = self.pending_planner.take() {
                self.planner = p;
            }
            return self.pos;
        };
        self.exec_id = head.id;
        self.waiting_for_atspeed =
            head.atspeed && self.s == 0.0 && self.v == 0.0 && !scales.spindle_at_speed;
        if self.waiting_for_atspeed {
            // LinuxCNC's at-speed barrier: the move after a spindle start
            // waits, at rest, for `spindle.N.at-speed`.
            return self.pos;
        }
        if self.sync_wait(&head, scales) {
            // At rest until the spindle is at speed and its index passes.
            return self.pos;
        }
        self.start_head();
        if head.kind == SegmentKind::Dwell {
            self.run_dwell(&head);
            return self.pos;
        }
        if let Some(tap) = head.tap {
            self.scurve.reset();
            self.a = 0.0;
            if tap.state == super::TapState::FinalPlacement {
                self.step_tap_placement(&head);
            } else {
                self.step_tap(scales);
            }
            return self.pos;
        }
        if head.locked.is_some() {
            self.net_scale = 1.0;
            let vt = self.sync_target(&head, scales);
            self.requested_vel = vt;
            let next_vt = self.next_target(scales);
            // The trapezoidal steps, whatever the planner type.
            self.scurve.reset();
            self.a = 0.0;
            self.step_trapezoid(&head, vt, next_vt);
            return self.pos;
        }
        let scale = scales.net(head.enables, head.kind == SegmentKind::Traverse);
        self.net_scale = scale;
        let vt = self.target_speed(&head, scales, scale);
        self.requested_vel = vt;
        let next_vt = self.next_target(scales);
        match self.planner {
            PlannerType::Trapezoidal => self.step_trapezoid(&head, vt, next_vt),
            PlannerType::SCurve => self.step_scurve(vt, next_vt, scales),
        }
        self.pos
    }

    /// The speed the segment after the executing one asks for (0: none,
    /// or a dwell).
    fn next_target(&self, scales: &ScaleInputs) -> f64 {
        match self.queue.get(1) {
            Some(next) if next.kind != SegmentKind::Dwell => {
                let s = scales.net(next.enables, next.kind == SegmentKind::Traverse);
                self.target_speed(next, scales, s)
            }
            _ => 0.0,
        }
    }

    fn run_dwell(&mut self, head: &Segment) {
        self.v = 0.0;
        self.a = 0.0;
        self.pos = head.point(0.0);
        if self.paused {
            return;
        }
        let left = self.dwell_left.get_or_insert(head.dwell);
        *left -= self.period;
        if *left <= 1e-12 {
            self.finish_head();
        }
    }

    pub(super) fn step_trapezoid(&mut self, head: &Segment, vt: f64, next_vt: f64) {
        let t = self.period;
        let d = head.len - self.s;
        let a_brake = self.brake_acc(head);
        let hard = self.hard_brake_speed(head);
        let soft_end = head.ve.min(next_vt);
        let soft = if soft_end < head.ve {
            brake_speed(d, soft_end, a_brake, t)
        } else {
            hard
        };
        // The period after a corner keeps within both segments' budgets.
        let mut a = head.budget.acc.min(self.cross_acc);
        self.cross_acc = f64::INFINITY;
        let mut v = self.trapezoid_speed(a, vt.min(soft), hard, head.budget.vmax);
        if head.ve > 0.0 && self.s + v * t >= head.len && a > a_brake {
            // This period crosses the corner: both budgets again.
            a = a_brake;
            v = self.trapezoid_speed(a, vt.min(soft), hard, head.budget.vmax);
        }
        self.v = v;
        self.advance(v * t);
    }

    /// The speed for the coming period: `target` clamped to one step of
    /// acceleration `a` from the current speed and below `hard` and
    /// `vmax` (which win should they conflict).
    pub(super) fn trapezoid_speed(&self, a: f64, target: f64, hard: f64, vmax: f64) -> f64 {
        let t = self.period;
        let lo = (self.v - a * t).max(0.0);
        let hi = (self.v + a * t).min(hard).min(vmax);
        if hi <= lo {
            hi.max(0.0)
        } else {
            target.clamp(lo, hi)
        }
    }

    /// Moves `step` along the queue, through corners, landing on stops.
    fn advance(&mut self, mut step: f64) {
        loop {
            let Some(head) = self.queue.front().copied() else {
                self.hold = true;
                return;
            };
            let left = head.len - self.s;
            if head.ve <= 0.0 && step >= left - 1e-12 {
                self.land(&head);
                return;
            }
            if step < left {
                self.s += step;
                self.pos = head.point(self.s);
                return;
            }
            step -= left;
            let a_before = head.budget.acc;
            self.finish_head();
            if let Some(next) = self.queue.front() {
                self.cross_acc = a_before.min(next.budget.acc);
                // Crossed at speed: the next segment starts here.
                self.start_head();
            }
        }
    }

    /// Ends exactly at the end of `head`, at rest from the next period.
    fn land(&mut self, head: &Segment) {
        self.s = head.len;
        self.pos = head.end();
        self.finish_head();
        self.hold = true;
    }

    /// The executing segment is done: the next one starts.
    pub(super) fn finish_head(&mut self) {
        if let Some(done) = self.queue.pop_front() {
            self.exec_id = done.id;
            self.sync_segment_done(&done);
            self.indexer_segment_done(done.indexer);
        }
        self.s = 0.0;
        self.dwell_left = None;
        self.head_started = false;
        if self.stepping {
            let same = self.queue.front().is_some_and(|h| h.id == self.step_id);
            if !same {
                self.stepping = false;
                self.paused = true;
            }
        }
    }

    /// STEP: run to the end of the executing motion id and pause there.
    /// Only from a pause at rest.
    pub fn step(&mut self) -> Result<(), crate::command::Reject> {
        use crate::command::Reject;
        if !self.paused || self.stepping {
            return Err(Reject::NotPaused);
        }
        if self.v != 0.0 || self.a != 0.0 || self.hold {
            return Err(Reject::StillMoving);
        }
        let Some(head) = self.queue.front() else {
            return Ok(());
        };
        let id = head.id;
        let last = self.queue.iter().take_while(|s| s.id == id).count() - 1;
        self.queue[last].step_stop = true;
        self.queue[last].ve = 0.0;
        // The segments of this id must now stop at its end: recompute
        // their corner speeds back from there (lowering them is safe: the
        // motion is at rest).
        for k in (0..last).rev() {
            let entry = self.corner_entry_limit(k);
            let seg = &mut self.queue[k];
            seg.ve = seg.ve.min(entry);
        }
        self.scurve.reset();
        self.step_id = id;
        self.stepping = true;
        self.paused = false;
        Ok(())
    }

    // ------------------------------------------------------------------
    // S-curve

    fn step_scurve(&mut self, vt: f64, next_vt: f64, scales: &ScaleInputs) {
        let head = self.queue[0];
        let brake = vt <= 0.0;
        match self.scurve.mode {
            Mode::Idle => {
                if !brake {
                    self.start_position(vt, next_vt);
                } else if (self.v != 0.0 || self.a != 0.0) && !self.start_brake(&head) {
                    // No stop fits here: run this segment as planned.
                    self.start_position(self.v.max(1e-9), next_vt);
                }
            }
            Mode::Position => {
                let want = head.ve.min(vt).min(next_vt.max(0.0));
                if brake {
                    // Stop as soon as a stop fits in this segment.
                    self.start_brake(&head);
                } else if (vt - self.scurve.vt).abs() > 1e-9 * vt.max(1.0)
                    || want > self.scurve.vf + 1e-9
                {
                    // An override change, or a faster end now possible
                    // (more queued): keep the old profile if the new one
                    // would not keep the end speed.
                    self.replan_position(vt, next_vt);
                }
            }
            Mode::Brake => {
                if !brake && self.v == 0.0 && self.a == 0.0 {
                    self.start_position(vt, next_vt);
                }
            }
        }
        self.sample_scurve(scales);
    }

    /// A position profile from the current state to the executing
    /// segment's end.
    fn start_position(&mut self, vt: f64, next_vt: f64) {
        let head = self.queue[0];
        let b = head.budget;
        let want = head.ve.min(vt).min(next_vt.max(0.0));
        let d = head.len - self.s;
        let vf = if self.a == 0.0 {
            super::scurve::reachable_end_speed(self.v, want, d, b.acc, b.jerk)
        } else {
            want
        };
        let vf = vf.min(head.ve);
        if !self
            .scurve
            .plan_position(self.s, self.v, self.a, head.len, vf, vt, b.acc, b.jerk)
            && !self.start_brake(&head)
        {
            self.scurve.mode = Mode::Idle;
        }
    }

    fn replan_position(&mut self, vt: f64, next_vt: f64) {
        let head = self.queue[0];
        let b = head.budget;
        let old_vf = self.scurve.vf;
        let want = head.ve.min(vt).min(next_vt.max(0.0));
        // Try the new end speed, then the old one; else keep the profile.
        for vf in [want, old_vf.min(vt)] {
            let saved_t = self.scurve.t;
            if self
                .scurve
                .plan_position(self.s, self.v, self.a, head.len, vf, vt, b.acc, b.jerk)
            {
                return;
            }
            self.scurve.t = saved_t;
        }
    }

    /// A stop, if it fits in the executing segment; false if not (the
    /// profile in use is kept).
    fn start_brake(&mut self, head: &Segment) -> bool {
        let b = head.budget;
        self.scurve
            .plan_brake_within(self.s, self.v, self.a, b.acc, b.jerk, head.len)
    }

    /// The state and pose of the profile in use at its time `t`.
    fn take_sample(&mut self, head: &Segment, t: f64) {
        let smp = self.scurve.sample(t);
        self.scurve.t = t;
        self.s = smp.pos.min(head.len);
        self.v = smp.vel.max(0.0);
        self.a = smp.acc;
        self.pos = head.point(self.s);
    }

    /// Advances the profile by one period and takes the pose from it.
    fn sample_scurve(&mut self, scales: &ScaleInputs) {
        let mut t = self.scurve.t + self.period;
        loop {
            let Some(head) = self.queue.front().copied() else {
                self.scurve.reset();
                self.hold = true;
                return;
            };
            match self.scurve.mode {
                Mode::Idle => return,
                Mode::Position => {
                    let dur = self.scurve.duration();
                    if t < dur {
                        self.take_sample(&head, t);
                        return;
                    }
                    let vf = self.scurve.vf;
                    self.v = vf;
                    self.a = 0.0;
                    if vf <= 0.0 || head.ve <= 0.0 {
                        self.scurve.reset();
                        self.v = 0.0;
                        self.land(&head);
                        return;
                    }
                    t -= dur;
                    self.finish_head();
                    let Some(next) = self.queue.front().copied() else {
                        self.scurve.reset();
                        self.hold = true;
                        return;
                    };
                    // The next segment's profile, sampled for the rest of
                    // the period.
                    self.start_head();
                    self.exec_id = next.id;
                    let s = scales.net(next.enables, next.kind == SegmentKind::Traverse);
                    let vt = self.target_speed(&next, scales, s).max(vf);
                    let after = match self.queue.get(1) {
                        Some(n2) if n2.kind != SegmentKind::Dwell => {
                            let s2 = scales.net(n2.enables, n2.kind == SegmentKind::Traverse);
                            self.target_speed(n2, scales, s2)
                        }
                        _ => 0.0,
                    };
                    self.scurve.reset();
                    self.start_position(vt, after);
                }
                Mode::Brake => {
                    // A stop stays within its segment.
                    let dur = self.scurve.duration();
                    self.take_sample(&head, t);
                    if t >= dur {
                        self.v = 0.0;
                        self.a = 0.0;
                        self.scurve.mode = Mode::Idle;
                    }
                    return;
                }
            }
        }
    }
}
