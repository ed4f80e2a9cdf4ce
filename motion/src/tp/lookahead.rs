//! The look-ahead ("rising tide"): after each new segment, how fast each
//! corner may be crossed so that every later corner's cap and the final
//! stop can still be kept, walking back from the tail.
//!
//! The tail always ends at rest. Going back, a corner's speed is the
//! smallest of its own cap, the speed caps of the two segments meeting
//! there, and the fastest speed from which the next segment can still
//! reach its own end speed (in the executing planner's discrete motion).
//! Values only rise as segments are added, so the walk stops where
//! nothing changes, or after [`MAX_DEPTH`] corners: corners further back
//! keep their lower values, which is safe.

use super::scurve;
use super::segment::{Segment, SegmentKind};
use super::trapezoid::{v_cross, v_stop};
use super::{Planner, PlannerType};

/// How far back one update walks.
pub(super) const MAX_DEPTH: usize = super::corners::MAX_TOUCHED - 1;

impl Planner {
    /// The fastest a segment may be entered so that it can still end at
    /// `ve` (the speed it ends at; 0: at rest), braking at `brake`.
    pub(super) fn entry_speed_max(&self, seg: &Segment, ve: f64, brake: f64) -> f64 {
        if seg.kind == SegmentKind::Dwell {
            return 0.0;
        }
        let b = &seg.budget;
        match self.planner {
            PlannerType::Trapezoidal => {
                if ve <= 0.0 {
                    v_stop(seg.len, brake, self.period)
                } else {
                    v_cross(seg.len, ve, brake, self.period)
                }
            }
            PlannerType::SCurve => scurve::entry_speed_max(seg.len, ve, b.vmax, b.acc, b.jerk),
        }
    }

    /// The fastest the corner after segment `k` may be crossed so that the
    /// segment after it can still keep its own end speed: that segment
    /// brakes with its [`Planner::brake_acc`], and its first period only
    /// with the smaller of the two corners' accelerations, which the
    /// trapezoidal planner pays for with one period's speed change.
    pub(super) fn corner_entry_limit(&self, k: usize) -> f64 {
        let seg = &self.queue[k];
        let next = &self.queue[k + 1];
        let brake = match self.queue.get(k + 2) {
            Some(after) if next.ve > 0.0 => next.budget.acc.min(after.budget.acc),
            _ => next.budget.acc,
        };
        let entry = self.entry_speed_max(next, next.ve, brake);
        match self.planner {
            PlannerType::Trapezoidal => {
                let first = seg.budget.acc.min(next.budget.acc);
                (entry - (brake - first).max(0.0) * self.period).max(0.0)
            }
            PlannerType::SCurve => entry,
        }
    }

    /// Recomputes the corner speeds from the tail back.
    pub(super) fn optimize(&mut self) {
        let n = self.queue.len();
        if n == 0 {
            return;
        }
        self.queue[n - 1].ve = 0.0;
        for k in (0..n - 1).rev().take(MAX_DEPTH) {
            let entry = self.corner_entry_limit(k);
            let next = self.queue[k + 1];
            let seg = &self.queue[k];
            let mut ve = seg
                .end_cap
                .min(seg.budget.vmax)
                .min(next.budget.vmax)
                .min(entry);
            if seg.step_stop || next.kind == SegmentKind::Dwell || seg.kind == SegmentKind::Dwell {
                ve = 0.0;
            }
            let ve = ve.max(0.0);
            let same = ve == seg.ve;
            self.queue[k].ve = ve;
            // Nothing further back depends on anything but this value and
            // unchanged segments (the last few may have changed shape).
            if same && k + 3 < n {
                break;
            }
        }
    }
}
