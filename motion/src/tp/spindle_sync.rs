//! Position synchronisation with a spindle (G33, the passes of G76, and
//! G33.1's tapping and retraction): LinuxCNC's SET_SPINDLESYNC in
//! position mode.
//!
//! A synchronised segment starts from rest. It waits for the spindles at
//! speed, sets `spindle.N.index-enable` and waits for the encoder to
//! clear it at the index pulse, where the encoder restarts `spindle.N.revs`
//! at 0: the origin (revolutions, counted positive in the direction the
//! spindle is commanded to turn). From there the progress along the path is made to
//! follow `(revs − origin) × per_rev`: the path speed is the spindle's
//! speed times `per_rev`, corrected by the position error no faster than
//! the braking curve of the segment's tangential acceleration, then held
//! within the segment's speed cap and one period's acceleration step (so
//! the axes' limits hold even while the lag of the start is made up).
//! When a synchronised segment ends, its length in revolutions is added
//! to the origin: the next synchronised segment follows the same spindle
//! position without a new index. An unsynchronised segment, or an empty
//! queue, ends the lock.
//!
//! As LinuxCNC: the feed override, feed hold and pause do not apply to a
//! synchronised segment (the spindle override does, through the spindle);
//! an abort stops it. Unlike LinuxCNC, which accelerates at full rate
//! until the axis reaches the spindle's speed and takes the phase there,
//! the phase is the index's, so every pass of a thread cuts the same
//! helix whatever the acceleration (LinuxCNC's passes agree too, as long
//! as the spindle speed is the same).

use super::segment::Segment;
use super::{Planner, ScaleInputs};

/// The share of the newest speed sample in the smoothed spindle speed,
/// each period.
const SPEED_SMOOTHING: f64 = 0.05;

/// Periods over which a small position error is closed.
const CORRECTION_PERIODS: f64 = 10.0;

/// Where the lock to the spindle is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) enum Phase {
    /// No synchronised segment runs.
    #[default]
    Off,
    /// `index-enable` was set; waiting for the encoder to clear it.
    WaitIndex,
    /// The progress follows the spindle.
    Locked,
}

/// The spindle tracking state of the planner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Track {
    pub phase: Phase,
    /// The spindle position the executing segment's start stands for,
    /// revolutions.
    pub origin: f64,
    /// The spindle position of the last period, revolutions.
    pub prev_revs: f64,
    /// The spindle whose `index-enable` is to be set this period.
    pub arm: Option<usize>,
    /// The spindle's speed, revolutions per second, from its position
    /// differences smoothed over a few periods (an encoder's count
    /// changes by whole counts).
    pub vel_est: f64,
    /// -1 if the spindle turned in reverse when the lock was taken (its
    /// `revs` count down), else 1: kept while locked, through a rigid
    /// tap's reversals.
    pub sign: f64,
}

impl Default for Track {
    fn default() -> Self {
        Track {
            phase: Phase::Off,
            origin: 0.0,
            prev_revs: 0.0,
            arm: None,
            vel_est: 0.0,
            sign: 1.0,
        }
    }
}

impl Planner {
    /// Spindle `n`'s position in revolutions, positive in the direction
    /// it turned when the lock was taken.
    pub(super) fn track_revs(&self, scales: &ScaleInputs, n: usize) -> f64 {
        let revs = scales.spindle_revs.get(n).copied().unwrap_or(0.0);
        let revs = if revs.is_finite() { revs } else { 0.0 };
        revs * self.track.sign
    }

    /// Takes this period's spindle position `revs`: the change since the
    /// last period, and the smoothed speed (revolutions per second).
    pub(super) fn spindle_moved(&mut self, revs: f64) -> (f64, f64) {
        let dr = revs - self.track.prev_revs;
        self.track.prev_revs = revs;
        let raw = dr / self.period;
        self.track.vel_est += SPEED_SMOOTHING * (raw - self.track.vel_est);
        if !self.track.vel_est.is_finite() {
            self.track.vel_est = 0.0;
        }
        (dr, self.track.vel_est)
    }

    /// The path speed that brings the progress towards `desired` while
    /// the spindle moves it at `spindle_vel`: a small error closed over
    /// a few periods (an encoder's counts do not shake the axis), a
    /// large one no faster than the braking curve of acceleration `a`
    /// allows. Never negative.
    pub(super) fn follow_speed(&self, desired: f64, spindle_vel: f64, a: f64) -> f64 {
        let t = self.period;
        let e = desired - self.s - spindle_vel * t;
        let correction = (e.abs() / (CORRECTION_PERIODS * t))
            .min((a * e.abs()).sqrt())
            .copysign(e);
        let v = spindle_vel + correction;
        if v.is_finite() {
            v.max(0.0)
        } else {
            0.0
        }
    }
}

impl Planner {
    /// Before the executing segment moves: the start of a synchronised
    /// segment (at-speed, index). True while it waits, at rest.
    pub(super) fn sync_wait(&mut self, head: &Segment, scales: &ScaleInputs) -> bool {
        self.track.arm = None;
        let Some(lock) = head.locked else {
            self.track.phase = Phase::Off;
            return false;
        };
        match self.track.phase {
            Phase::Locked => false,
            Phase::Off => {
                if self.aborting {
                    return false;
                }
                if !scales.spindle_at_speed {
                    self.waiting_for_atspeed = true;
                    return true;
                }
                self.track.arm = Some(lock.spindle);
                self.track.phase = Phase::WaitIndex;
                true
            }
            Phase::WaitIndex => {
                if self.aborting {
                    return false;
                }
                let armed = scales.spindle_index_enable & (1 << lock.spindle) != 0;
                if armed {
                    return true;
                }
                // The encoder restarted its count at the index: 0 there,
                // whatever it has turned since, is the origin.
                self.track.origin = 0.0;
                let reverse = scales.spindle_reverse & (1 << lock.spindle) != 0;
                self.track.sign = if reverse { -1.0 } else { 1.0 };
                self.track.prev_revs = self.track_revs(scales, lock.spindle);
                self.track.vel_est = 0.0;
                self.track.phase = Phase::Locked;
                false
            }
        }
    }

    /// Whether the executing segment waits for the spindle's index.
    pub fn waiting_for_index(&self) -> bool {
        self.track.phase == Phase::WaitIndex
    }

    /// The spindle whose `index-enable` the controller sets this period
    /// (the start of a synchronised segment).
    pub fn index_arm(&self) -> Option<usize> {
        self.track.arm
    }

    /// The path speed a synchronised executing segment asks for this
    /// period: the spindle's speed times the pitch, corrected by the
    /// position error (0 while aborting).
    pub(super) fn sync_target(&mut self, head: &Segment, scales: &ScaleInputs) -> f64 {
        let Some(lock) = head.locked else {
            return 0.0;
        };
        let revs = self.track_revs(scales, lock.spindle);
        let spindle_vel = self.spindle_moved(revs).1 * lock.per_rev;
        if self.aborting {
            return 0.0;
        }
        let desired = (revs - self.track.origin) * lock.per_rev;
        self.follow_speed(desired, spindle_vel, head.budget.acc)
    }

    /// A synchronised segment is done: the next one keeps the phase.
    pub(super) fn sync_segment_done(&mut self, done: &Segment) {
        if let Some(lock) = done.locked {
            if lock.per_rev > 0.0 {
                self.track.origin += done.len / lock.per_rev;
            }
        }
    }
}
