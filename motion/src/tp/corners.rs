//! Queueing a move: its budget, and what happens at the corner where it
//! meets the last queued move.
//!
//! A corner is an exact stop when the last move asked for one (G61.1),
//! when a rapid meets a feed move or the other way round, and around
//! probing moves and dwells. Otherwise, under blending (G64) two straight
//! XYZ moves get a blend arc tangent to both, as large as the tolerance,
//! half of each move and the acceleration budget allow but no larger than
//! the programmed feed (at the largest feed override) needs; every other
//! corner is a kink crossed no faster than its [`kink_cap`], which is
//! full speed for a tangent corner and next to nothing for a sharp one.
//!
//! A change may only lower how fast the executing segment may end if the
//! executor can still keep it: otherwise the corner is left as a kink.

use super::budget::{budget, corner_cap, Budget, Corner, End, Joins};
use super::geom::{self, Path, MIN_LENGTH};
use super::segment::{Ending, Segment, SegmentKind};
use super::{AxisLimits, Planner, PlannerType};
use crate::command::ProbeType;
use crate::kins::Pose;

/// How many segments' look-ahead values a corner change may touch (the
/// look-ahead's depth).
pub(super) const MAX_TOUCHED: usize = 128;

impl Planner {
    /// Builds a segment for `path` and queues it after the last one.
    /// A zero-length move is dropped (it would not move anything).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn push(
        &mut self,
        path: Path,
        end: &Pose,
        kind: SegmentKind,
        req_vel: f64,
        probe: Option<ProbeType>,
        id: i32,
        enables: u8,
        lim: &AxisLimits,
    ) {
        let len = path.length();
        if len < MIN_LENGTH {
            return;
        }
        let atspeed = std::mem::take(&mut self.atspeed_pending);
        let indexer = self.indexer_pending.take().map(|j| j as u8);
        let locked = match kind {
            SegmentKind::Feed | SegmentKind::Arc => self.position_sync,
            _ => None,
        };
        // Entering position synchronisation waits for the spindle's index
        // at rest (LinuxCNC's early-stop rule).
        let enters_sync = locked.is_some() && self.queue.back().is_none_or(|p| p.locked.is_none());
        if atspeed || indexer.is_some() || enters_sync {
            // It starts from rest: the segment before it stops.
            if let Some(last) = self.queue.back_mut() {
                last.ending = Ending::Stop;
                last.end_cap = 0.0;
            }
        }
        // A locking indexer's move ends at rest too.
        let ending = if indexer.is_some() {
            Ending::Stop
        } else {
            self.ending()
        };
        let prev_ending = self
            .queue
            .back()
            .filter(|p| joinable(p.kind, kind))
            .map_or(Ending::Stop, |p| p.ending);
        let own_ending = if probe.is_some() {
            Ending::Stop
        } else {
            ending
        };
        let (start_joins, end_joins) = ends_of(prev_ending, own_ending);
        let Some(b) = self.budget_for(&path, len, lim, Joins::of(start_joins, end_joins)) else {
            return;
        };
        let mut seg = Segment {
            id,
            kind,
            path,
            end: *end,
            len,
            nominal_len: len,
            start_cut: 0.0,
            req_vel,
            budget: b,
            end_cap: 0.0,
            ve: 0.0,
            ending: if probe.is_some() {
                Ending::Stop
            } else {
                ending
            },
            enables,
            dwell: 0.0,
            probe,
            start_joins,
            end_joins,
            step_stop: false,
            atspeed,
            indexer,
            sync: false,
            per_rev: match kind {
                SegmentKind::Feed | SegmentKind::Arc if locked.is_none() => self.feed_per_rev,
                _ => None,
            },
            locked,
            tap: None,
        };
        seg.sync = self.sync_io.attach();
        self.goal = *end;
        self.join(&mut seg, lim);
        self.queue.push_back(seg);
        self.optimize();
        if !self.head_can_follow() {
            // The executing segment cannot take the new corner at speed
            // (it had planned to stop there): it stops there.
            let n = self.queue.len();
            self.queue[n - 2].end_cap = 0.0;
            self.optimize();
        }
    }

    /// The budget of `path`, `len` long (see [`budget`]); the `[TRAJ]` speed
    /// limit does not apply to purely rotary moves.
    fn budget_for(&self, path: &Path, len: f64, lim: &AxisLimits, joins: Joins) -> Option<Budget> {
        let f = path.factors(len);
        let rotary_only = [0, 1, 2, 6, 7, 8].iter().all(|&i| f.speed(i) == 0.0);
        budget(
            &f,
            len,
            lim,
            &self.traj,
            self.period,
            joins,
            self.planner,
            rotary_only,
        )
    }

    /// Sets up the corner between the last queued segment and `seg`.
    fn join(&mut self, seg: &mut Segment, lim: &AxisLimits) {
        let Some(prev) = self.queue.back() else {
            return;
        };
        let prev = *prev;
        let stop = prev.ending == Ending::Stop
            || seg.probe.is_some()
            || prev.probe.is_some()
            || !joinable(prev.kind, seg.kind);
        if stop {
            return;
        }
        if let Ending::Blend { tolerance } = prev.ending {
            // A segment carrying output changes keeps its start.
            if !seg.sync
                && prev.blendable_line()
                && seg.blendable_line()
                && self.try_blend(seg, tolerance, lim)
            {
                return;
            }
        }
        let kink = corner_cap(&corner(&prev, seg), lim, self.period, self.planner);
        // A corner that cannot be crossed faster than one period's speed
        // change is a stop (a reversal, a sharp corner).
        let crossable = |p: &Budget| {
            let cap = kink.min(p.vmax).min(seg.budget.vmax);
            (cap > p.acc.min(seg.budget.acc) * self.period).then_some(cap)
        };
        let Some(mut cap) = crossable(&prev.budget) else {
            return;
        };
        if prev.end_joins == End::Stop && kink.is_finite() {
            // A G61 move queued as if it stopped is crossed at a kink
            // after all: it keeps the kink reserve from now on.
            let mut kinked = prev;
            kinked.end_joins = End::Kink;
            if !self.rebudget(&mut kinked, 1, lim) {
                return;
            }
            let Some(c) = crossable(&kinked.budget) else {
                return;
            };
            cap = c;
            if let Some(last) = self.queue.back_mut() {
                *last = kinked;
            }
        }
        if let Some(last) = self.queue.back_mut() {
            last.end_cap = cap;
        }
    }

    /// Makes `seg`'s budget again for how its ends now meet their
    /// neighbours (`from_tail`: its place counted from the tail, 0 for a
    /// segment not queued yet). The executing segment, once started, may
    /// only gain (trapezoidal planner: the next period simply may change
    /// speed faster; the S-curve planner keeps what it planned with). False
    /// if it could not: `seg`'s budget is then unchanged, never more than
    /// its ends allow.
    fn rebudget(&self, seg: &mut Segment, from_tail: usize, lim: &AxisLimits) -> bool {
        let n = self.queue.len();
        let running =
            from_tail > 0 && n == from_tail && (self.head_started || self.s > 0.0 || self.v > 0.0);
        if running && self.planner != PlannerType::Trapezoidal {
            return false;
        }
        let Some(b) = self.budget_for(&seg.path, seg.nominal_len, lim, seg.joins()) else {
            return false;
        };
        let b = cap_by_length(b, seg.len, self.period);
        let was = cap_by_length(seg.budget, seg.len, self.period);
        if running && (b.acc < was.acc || b.vmax < was.vmax) {
            return false;
        }
        seg.budget = b;
        true
    }

    /// The smallest cut, at most `cut`, whose blend arc at `corner` can
    /// still be run at `goal` (the programmed feed at the largest feed
    /// override), as LinuxCNC sizes its blend arcs: no larger than the
    /// speed needs, so the path keeps as close to the corner as it can
    /// without slowing down. `cut` itself when even its arc is slower.
    fn cut_for_speed(
        &self,
        corner: &Pose,
        u1: geom::V3,
        u2: geom::V3,
        cut: f64,
        goal: f64,
        lim: &AxisLimits,
    ) -> f64 {
        let vmax_at = |c: f64| -> Option<f64> {
            let blend = geom::blend_arc(corner, u1, u2, c)?;
            let path = Path::Arc(blend.arc);
            let len = path.length();
            self.budget_for(&path, len, lim, Joins::Tangent)
                .map(|b| b.vmax)
        };
        if !(goal > 0.0 && cut > MIN_LENGTH) {
            return cut;
        }
        let Some(full) = vmax_at(cut) else {
            return cut;
        };
        if full <= goal {
            return cut;
        }
        // A turn's speed grows with the square root of its radius, and the
        // radius with the cut: start there and correct for the other caps.
        let mut c = cut * (goal / full).powi(2);
        for _ in 0..4 {
            match vmax_at(c) {
                Some(v) if v >= goal => return c,
                Some(v) if v > 0.0 => c = (c * (goal / v).powi(2) * 1.01).min(cut),
                _ => return cut,
            }
        }
        cut
    }

    /// Puts a blend arc between the last queued line and the line `seg`,
    /// if one fits and the executor can keep the changed speeds. True if
    /// it did.
    fn try_blend(&mut self, seg: &mut Segment, tolerance: f64, lim: &AxisLimits) -> bool {
        let n = self.queue.len();
        let prev = self.queue[n - 1];
        let (Some(u1), Some(u2)) = (
            prev.path.xyz_direction(prev.len, prev.nominal_len),
            seg.path.xyz_direction(0.0, seg.nominal_len),
        ) else {
            return false;
        };
        let quarter = 0.25 * prev.nominal_len.min(seg.nominal_len);
        let tol = if tolerance > 0.0 {
            tolerance.min(quarter)
        } else {
            quarter
        };
        // Each line gives at most half of itself to each of its corners.
        let mut cut = geom::cut_for_tolerance(u1, u2, tol)
            .min(0.5 * prev.nominal_len)
            .min(prev.len)
            .min(0.5 * seg.nominal_len);
        if n == 1 {
            // The executing line cannot lose what it has already run.
            cut = cut.min(prev.len - self.s);
        }
        let corner = prev.end();
        let goal = prev.req_vel.max(seg.req_vel)
            * if prev.kind == SegmentKind::Traverse && seg.kind == SegmentKind::Traverse {
                1.0
            } else {
                self.max_feed_scale
            };
        cut = self.cut_for_speed(&corner, u1, u2, cut, goal, lim);
        if cut.is_nan() || cut <= MIN_LENGTH {
            return false;
        }
        let Some(blend) = geom::blend_arc(&corner, u1, u2, cut) else {
            return false;
        };
        let path = Path::Arc(blend.arc);
        let len = path.length();
        if len < 1e-6 {
            return false;
        }
        let Some(b) = self.budget_for(&path, len, lim, Joins::Tangent) else {
            return false;
        };
        let arc_end = path.point(len, len);
        let arc = Segment {
            id: prev.id,
            end: arc_end,
            // A blend between rapids is a rapid (rapid override, no feed).
            kind: if prev.kind == SegmentKind::Traverse {
                SegmentKind::Traverse
            } else {
                SegmentKind::Arc
            },
            path,
            len,
            nominal_len: len,
            start_cut: 0.0,
            req_vel: prev.req_vel.max(seg.req_vel),
            budget: b,
            end_cap: b.vmax.min(seg.budget.vmax),
            ve: 0.0,
            ending: prev.ending,
            enables: prev.enables,
            dwell: 0.0,
            probe: None,
            start_joins: End::Tangent,
            end_joins: End::Tangent,
            step_stop: false,
            atspeed: false,
            indexer: None,
            sync: false,
            per_rev: prev.per_rev.or(seg.per_rev),
            locked: None,
            tap: None,
        };
        // Remember what may change, to put it back if the executor could
        // not follow.
        let touched = n.min(MAX_TOUCHED);
        let mut saved_ve = [0.0; MAX_TOUCHED];
        for (k, v) in saved_ve.iter_mut().enumerate().take(touched) {
            *v = self.queue[n - touched + k].ve;
        }
        let saved_seg = *seg;

        // Both lines now meet the arc tangentially: as in LinuxCNC, a
        // line settled that way at both ends gets the whole acceleration.
        let mut trimmed = prev;
        trimmed.cut_end(cut);
        trimmed.end_joins = End::Tangent;
        if !self.rebudget(&mut trimmed, 1, lim) {
            trimmed.budget = cap_by_length(trimmed.budget, trimmed.len, self.period);
        }
        trimmed.end_cap = trimmed.budget.vmax.min(b.vmax);
        let consumed = trimmed.len < MIN_LENGTH && (n > 1 || (self.s == 0.0 && self.v == 0.0));
        seg.cut_start(cut);
        seg.start_joins = End::Tangent;
        if !self.rebudget(seg, 0, lim) {
            seg.budget = cap_by_length(seg.budget, seg.len, self.period);
        }
        if consumed {
            self.queue.pop_back();
        } else {
            self.queue[n - 1] = trimmed;
        }
        self.queue.push_back(arc);
        // The new segment is not queued yet: the arc is the tail for now.
        self.optimize();
        if self.head_can_follow() {
            return true;
        }
        // Undo.
        self.queue.pop_back();
        if consumed {
            self.queue.push_back(prev);
        } else {
            self.queue[n - 1] = prev;
        }
        for (k, v) in saved_ve.iter().enumerate().take(touched) {
            self.queue[n - touched + k].ve = *v;
        }
        *seg = saved_seg;
        false
    }

    /// Whether the executing segment can still keep its (possibly
    /// lowered) end speed and speed cap from the state the executor is in.
    pub(super) fn head_can_follow(&self) -> bool {
        let Some(head) = self.queue.front() else {
            return true;
        };
        if self.v == 0.0 && self.a == 0.0 {
            return true;
        }
        match self.planner {
            PlannerType::Trapezoidal => {
                let t = self.period;
                let slowest = (self.v - head.budget.acc * t).max(0.0);
                slowest <= head.budget.vmax + 1e-12 && slowest <= self.hard_brake_speed(head) + 1e-9
            }
            PlannerType::SCurve => self.scurve.keeps(head.ve, head.len),
        }
    }
}

/// Whether two kinds of move may meet without stopping: rapids only with
/// rapids, feed moves and arcs with each other (LinuxCNC stops between
/// traverse and feed moves).
fn joinable(a: SegmentKind, b: SegmentKind) -> bool {
    use SegmentKind::*;
    matches!((a, b), (Traverse, Traverse) | (Feed | Arc, Feed | Arc))
}

/// How a new move's ends meet its neighbours, from how the move before
/// it ends (`Stop` if they cannot meet at speed) and how it ends itself,
/// until the corners are settled (see `join`): under G64 an end is
/// `Open` (it may be blended); after a G61 move the start is a `Kink`;
/// a G61 move's own end counts as a stop until the next move is found to
/// meet it at speed (alone, it runs at the whole acceleration, as in
/// LinuxCNC).
fn ends_of(prev: Ending, own: Ending) -> (End, End) {
    let start = match prev {
        Ending::Blend { .. } => End::Open,
        Ending::ExactPath => End::Kink,
        Ending::Stop => End::Stop,
    };
    let end = match own {
        Ending::Blend { .. } => End::Open,
        Ending::ExactPath | Ending::Stop => End::Stop,
    };
    (start, end)
}

/// The corner where `a` ends and `b` starts.
fn corner(a: &Segment, b: &Segment) -> Corner {
    Corner {
        d1_before: a.derivative(a.len),
        d1_after: b.derivative(0.0),
        d2_before: a.second_derivative(a.len),
        d2_after: b.second_derivative(0.0),
    }
}

/// A segment shortened to `len` must still take at least one period.
fn cap_by_length(b: Budget, len: f64, period: f64) -> Budget {
    Budget {
        vmax: b.vmax.min(len / period),
        ..b
    }
}
