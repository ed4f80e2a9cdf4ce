//! Rigid tapping (G33.1; LinuxCNC's RIGID_TAP): one segment that feeds
//! to the tap's depth locked to the spindle, has the spindle reversed,
//! comes back to its start locked to the reversed spindle, has the
//! spindle restored and finally moves back onto the start, as
//! LinuxCNC's rigid-tap states:
//!
//! * `Tapping`: the progress follows the spindle (as G33) until it
//!   reaches the depth; the spindle's speed is then multiplied by
//!   −scale (the reversal);
//! * `Reversing`: still following the spindle, which slows down and
//!   turns back; once its position decreases the axis stops, and the
//!   path becomes the line back to the start;
//! * `Retraction`: the progress back follows the reversed spindle from
//!   the point of the helix where the axis turned, until the start is
//!   reached; the spindle's speed is restored (divided by −scale);
//! * `FinalReversal`: following the spindle again until its position
//!   increases, then at rest;
//! * `FinalPlacement`: an ordinary move onto the start, ending at rest.
//!
//! Each path runs 10 revolutions past its end (LinuxCNC's overrun) for
//! the spindle's coasting; the axis never leaves that line. The
//! reversals of the axis happen at rest, so the axes' limits hold.
//! Unlike LinuxCNC, the return keeps the tapping phase: its origin is
//! the spindle position of the point where the axis turned rather than
//! the spindle's position then.

use super::geom::{Path, MIN_LENGTH};
use super::segment::{Ending, Segment, SegmentKind};
use super::trapezoid::v_stop;
use super::{AxisLimits, Planner, ScaleInputs};
use crate::command::{Quantity, Reject};
use crate::kins::{Pose, NUM_AXES};

/// Revolutions each path of a rigid tap runs past its end.
const OVERRUN_REVS: f64 = 10.0;

/// Where a rigid tap is (LinuxCNC's names).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TapState {
    /// Feeding to the depth.
    Tapping,
    /// The spindle was told to reverse; waiting for it to turn back.
    Reversing,
    /// Coming back to the start with the reversed spindle.
    Retraction,
    /// The spindle was told to turn forward again.
    FinalReversal,
    /// An ordinary move back onto the start.
    FinalPlacement,
}

/// The state of a rigid tap segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tap {
    pub state: TapState,
    /// The length of the path to the depth (or back to the start).
    pub depth: f64,
    /// Where the tap started and ends.
    pub start: Pose,
    /// The reversal's speed factor (G33.1 I).
    pub scale: f64,
    /// The spindle position (revolutions) the return's origin stands
    /// for.
    pub revs_at_reversal: f64,
}

/// A straight path from `from` to `to` in XYZ (other axes fixed),
/// extended by `overrun`; its length to `to`.
fn tap_line(from: &Pose, to: &Pose, overrun: f64) -> (Path, f64) {
    let mut delta = [0.0; NUM_AXES];
    for (i, d) in delta.iter_mut().enumerate().take(3) {
        *d = to.0[i] - from.0[i];
    }
    let len = (delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2]).sqrt();
    if len > 0.0 {
        let k = (len + overrun) / len;
        for d in &mut delta[..3] {
            *d *= k;
        }
    }
    (
        Path::Line {
            start: *from,
            delta,
        },
        len,
    )
}

impl Planner {
    /// Queues a rigid tap from the goal to `end` (X, Y and Z; the other
    /// axes stay) and back, at the position synchronisation in effect;
    /// `scale` is the reversal's speed factor.
    #[allow(clippy::too_many_arguments)]
    pub fn add_rigid_tap(
        &mut self,
        end: Pose,
        vel: f64,
        scale: f64,
        id: i32,
        enables: u8,
        lim: &AxisLimits,
    ) -> Result<(), Reject> {
        self.can_queue()?;
        let lock = self.position_sync.ok_or(Reject::RigidTapNotSynchronised)?;
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Reject::BadValue {
                what: Quantity::Scale,
                value: scale,
            });
        }
        let start = self.goal;
        let (path, depth) = tap_line(&start, &end, OVERRUN_REVS * lock.per_rev);
        if depth < MIN_LENGTH {
            return Ok(());
        }
        let len = path.length();
        let Some(budget) = self.tap_budget(&path, len, lim) else {
            return Ok(());
        };
        self.atspeed_pending = false;
        if let Some(last) = self.queue.back_mut() {
            // It starts from rest.
            last.ending = Ending::Stop;
            last.end_cap = 0.0;
        }
        let mut seg = Segment {
            id,
            kind: SegmentKind::Feed,
            path,
            // It comes back.
            end: start,
            len,
            nominal_len: len,
            start_cut: 0.0,
            req_vel: vel,
            budget,
            end_cap: 0.0,
            ve: 0.0,
            ending: Ending::Stop,
            enables,
            dwell: 0.0,
            probe: None,
            start_joins: super::budget::End::Stop,
            end_joins: super::budget::End::Stop,
            step_stop: false,
            // The at-speed wait is the synchronisation's, at its start
            // only (not when the return starts from rest).
            atspeed: false,
            sync: false,
            per_rev: None,
            locked: Some(lock),
            tap: Some(Tap {
                state: TapState::Tapping,
                depth,
                start,
                scale,
                revs_at_reversal: 0.0,
            }),
            indexer: None,
        };
        seg.sync = self.sync_io.attach();
        self.queue.push_back(seg);
        self.optimize();
        Ok(())
    }

    /// The spindle whose commanded speed the controller multiplies by the
    /// factor this period (a rigid tap's reversals); taken once.
    pub fn take_spindle_reversal(&mut self) -> Option<(usize, f64)> {
        self.spindle_reversal.take()
    }

    /// The executing rigid tap's state, if one runs.
    pub fn tap_state(&self) -> Option<TapState> {
        self.queue.front().and_then(|h| h.tap).map(|t| t.state)
    }

    /// One period of the executing rigid tap.
    pub(super) fn step_tap(&mut self, scales: &ScaleInputs) {
        let head = self.queue[0];
        let (Some(mut tap), Some(lock)) = (head.tap, head.locked) else {
            return;
        };
        let revs = self.track_revs(scales, lock.spindle);
        let (dr, rps) = self.spindle_moved(revs);
        let p = lock.per_rev;
        let a = head.budget.acc;
        let (desired, spindle_vel) = match tap.state {
            TapState::Tapping | TapState::Reversing => ((revs - self.track.origin) * p, rps * p),
            _ => ((tap.revs_at_reversal - revs) * p, -rps * p),
        };
        // Once the spindle has turned back, the axis stops to turn too.
        let turned = match tap.state {
            TapState::Reversing => dr < 0.0,
            TapState::FinalReversal => dr > 0.0,
            _ => false,
        };
        let vt = if self.aborting || turned {
            0.0
        } else {
            self.follow_speed(desired, spindle_vel, a)
        };
        self.requested_vel = vt;
        self.net_scale = 1.0;
        let hard = v_stop(head.len - self.s, a, self.period);
        self.v = self.trapezoid_speed(a, vt, hard, head.budget.vmax);
        self.s = (self.s + self.v * self.period).min(head.len);
        self.pos = head.point(self.s);
        match tap.state {
            TapState::Tapping if self.s >= tap.depth => {
                self.spindle_reversal = Some((lock.spindle, -tap.scale));
                tap.state = TapState::Reversing;
            }
            TapState::Reversing if turned && self.v == 0.0 => {
                // Back along the same helix: the spindle position of the
                // point where the axis turned is the return's origin.
                tap.revs_at_reversal = self.track.origin + self.s / p;
                self.new_tap_path(&mut tap, OVERRUN_REVS * p);
                tap.state = TapState::Retraction;
            }
            TapState::Retraction if self.s >= tap.depth => {
                self.spindle_reversal = Some((lock.spindle, -1.0 / tap.scale));
                tap.state = TapState::FinalReversal;
            }
            TapState::FinalReversal if turned && self.v == 0.0 => {
                self.new_tap_path(&mut tap, 0.0);
                tap.state = TapState::FinalPlacement;
                let head = &mut self.queue[0];
                head.locked = None;
                head.end = tap.start;
            }
            _ => {}
        }
        if let Some(h) = self.queue.front_mut() {
            h.tap = Some(tap);
        }
    }

    /// The executing tap's path becomes the line from here to its start
    /// (extended by `overrun`), from rest.
    fn new_tap_path(&mut self, tap: &mut Tap, overrun: f64) {
        let from = self.pos;
        let (path, len_to) = tap_line(&from, &tap.start, overrun);
        let head = &mut self.queue[0];
        head.path = path;
        head.len = path.length();
        head.nominal_len = head.len;
        head.start_cut = 0.0;
        tap.depth = len_to;
        self.s = 0.0;
        self.v = 0.0;
    }

    /// The final placement: an ordinary move onto the start, landing
    /// there at rest (at once if it is there already).
    pub(super) fn step_tap_placement(&mut self, head: &Segment) {
        if head.len < MIN_LENGTH {
            self.v = 0.0;
            self.pos = head.end;
            self.s = head.len;
            self.finish_head();
            self.hold = true;
            return;
        }
        let vt = if self.aborting { 0.0 } else { head.budget.vmax };
        self.requested_vel = vt;
        self.step_trapezoid(head, vt, 0.0);
    }

    /// The budget of a tap's path (no corner reserves: it starts and ends
    /// at rest).
    fn tap_budget(&self, path: &Path, len: f64, lim: &AxisLimits) -> Option<super::budget::Budget> {
        let f = path.factors(len);
        super::budget::budget(
            &f,
            len,
            lim,
            &self.traj,
            self.period,
            super::budget::Joins::Stop,
            self.planner,
            false,
        )
    }
}
