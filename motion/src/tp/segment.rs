//! One queued move: its path, limits, how it ends, and what it reports.

use super::budget::{Budget, End, Joins};
use super::geom::Path;
use crate::command::ProbeType;
use crate::kins::{Pose, NUM_AXES};

/// What kind of move a segment is (LinuxCNC's canonical motion types, as
/// `motion.motion-type` reports them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentKind {
    /// A rapid (G0): as fast as the axes allow, times the rapid override.
    Traverse,
    /// A straight feed move (G1).
    Feed,
    /// An arc or helix (G2/G3), or a blend arc made at a corner.
    Arc,
    /// A straight probing move (G38.x).
    Probe,
    /// A pause of a given time (G4).
    Dwell,
}

impl SegmentKind {
    /// LinuxCNC's number for `motion.motion-type`.
    pub fn number(self) -> i32 {
        match self {
            SegmentKind::Traverse => 1,
            SegmentKind::Feed => 2,
            SegmentKind::Arc => 3,
            SegmentKind::Probe => 5,
            SegmentKind::Dwell => 0,
        }
    }
}

/// How a segment may end (the termination condition it was queued with).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Ending {
    /// Exact stop (G61.1): at rest, never blended.
    Stop,
    /// Exact path (G61): no deviation, but a corner the axes can take at
    /// speed is crossed at speed.
    ExactPath,
    /// Blending (G64) within `tolerance` of the corner (0: a quarter of
    /// the shorter move).
    Blend { tolerance: f64 },
}

/// One queued move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    /// The motion id (the program line).
    pub id: i32,
    pub kind: SegmentKind,
    pub path: Path,
    /// The end pose: the programmed one, bit for bit, unless a blend took
    /// the end off.
    pub end: Pose,
    /// Current length (blends shorten lines at their ends).
    pub len: f64,
    /// Length as queued.
    pub nominal_len: f64,
    /// How much of the start a blend took off already.
    pub start_cut: f64,
    /// Programmed speed along the path (infinite for rapids).
    pub req_vel: f64,
    pub budget: Budget,
    /// Hard speed cap where this segment meets the next (0: stop there).
    pub end_cap: f64,
    /// Look-ahead result: the fastest the end may be crossed so that
    /// every later cap and the final stop can still be kept.
    pub ve: f64,
    pub ending: Ending,
    /// Feed-override enable bits captured when queued.
    pub enables: u8,
    /// Seconds to wait (dwells).
    pub dwell: f64,
    pub probe: Option<ProbeType>,
    /// How its start meets the move before it (its budget is made for
    /// [`Segment::joins`], or is lower where a running segment could not
    /// be given more).
    pub start_joins: End,
    /// How its end meets the move after it.
    pub end_joins: End,
    /// A single step ends at the end of this segment.
    pub step_stop: bool,
    /// It starts, from rest, only once the spindle is at speed.
    pub atspeed: bool,
    /// It carries output changes (M62, M63, M67) written when it starts.
    pub sync: bool,
    /// Feed per revolution (G95): its speed follows a spindle's
    /// `speed-in` instead of `req_vel`.
    pub per_rev: Option<FeedPerRev>,
    /// Position synchronisation (G33, G76): its progress follows the
    /// spindle's `revs` times this many units per revolution.
    pub locked: Option<FeedPerRev>,
    /// A rigid tap (G33.1) and where it is.
    pub tap: Option<super::rigid_tap::Tap>,
    /// A locking indexer's rapid: the joint unlocked around it.
    pub indexer: Option<u8>,
}

/// A feed per revolution (LinuxCNC's velocity-mode spindle sync, G95).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeedPerRev {
    /// The spindle whose `speed-in` sets the speed.
    pub spindle: usize,
    /// Path length per revolution, machine units.
    pub per_rev: f64,
}

impl Segment {
    /// The pose at progress `s`.
    pub fn point(&self, s: f64) -> Pose {
        self.path.point(s + self.start_cut, self.nominal_len)
    }

    /// The pose at the end.
    pub fn end(&self) -> Pose {
        self.end
    }

    /// The axes' travel per unit of path at progress `s`.
    pub fn derivative(&self, s: f64) -> [f64; NUM_AXES] {
        self.path.derivative(s + self.start_cut, self.nominal_len)
    }

    /// The curvature part of the axes' acceleration per unit of speed²
    /// at progress `s`.
    pub fn second_derivative(&self, s: f64) -> [f64; NUM_AXES] {
        self.path
            .second_derivative(s + self.start_cut, self.nominal_len)
    }

    /// Whether this segment moves straight in XYZ only (a blend arc may
    /// replace its ends).
    pub fn blendable_line(&self) -> bool {
        matches!(self.kind, SegmentKind::Feed | SegmentKind::Traverse)
            && matches!(self.path, Path::Line { .. })
            && !self.path.moves_other_axes()
            && self.locked.is_none()
    }

    /// How it meets its neighbours.
    pub fn joins(&self) -> Joins {
        Joins::of(self.start_joins, self.end_joins)
    }

    /// Takes `cut` off the end.
    pub fn cut_end(&mut self, cut: f64) {
        self.len -= cut;
        self.end = self.point(self.len);
    }

    /// Takes `cut` off the start.
    pub fn cut_start(&mut self, cut: f64) {
        self.start_cut += cut;
        self.len -= cut;
    }
}
