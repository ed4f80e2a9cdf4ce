//! The coordinated trajectory planner: a queue of lines, arcs (circles,
//! helices, spirals) and dwells, each with a motion id, run along the path
//! once per servo period.
//!
//! * `geom`: where a segment is at each arc length, and the factors
//!   that turn path speed into axis speeds.
//! * `budget`: a segment's speed cap and tangential acceleration (and
//!   jerk) from every axis's limits; the speed a corner may be crossed at.
//! * `corners`: what happens where a new segment meets the last one:
//!   exact stop, a kink crossed at its capped speed, or (blending, two
//!   straight XYZ moves) a blend arc within the tolerance.
//! * `lookahead`: how fast each corner may be crossed so that every later
//!   corner and the final stop can still be kept ("rising tide", over the
//!   whole queue after each new segment).
//! * `trapezoid` and `scurve`: the two velocity planners along the path;
//!   `exec` runs them and the queue (pause, step, abort, dwells).
//! * `spindle_sync` and `rigid_tap`: segments locked to a spindle's
//!   position (G33, G76, G33.1).
//!
//! Guarantees, for the trapezoidal planner and, with jerk, the S-curve
//! one: no axis ever moves faster, accelerates or (S-curve) jerks harder
//! than its limit, measured on the positions the planner outputs every
//! period; the path never leaves the programmed one except inside a blend
//! arc, which stays within the blend tolerance; the last move ends
//! exactly on its end point; PAUSE, STEP and ABORT slow down along the
//! path within the same limits.
//!
//! Deliberate differences from LinuxCNC's planner:
//! * limits come from the axes (and joints) themselves rather than from
//!   per-move numbers the sender computes;
//! * velocities are planned in discrete time, so stops land exactly and
//!   the sampled motion keeps the limits (LinuxCNC's acceleration samples
//!   overshoot at corners and segment splits);
//! * no parabolic blending (segments overlapping in time): a corner is a
//!   blend arc, a kink crossed at the speed the axes can take, or a stop;
//!   arc-to-line and arc-to-arc corners that are not tangent are crossed
//!   at their kink speed (often a near stop) rather than blended. The
//!   acceleration budget is still LinuxCNC's (see `budget`): a move that
//!   may be blended (G64, the last queued one included) gets half the
//!   tangential acceleration, one whose corners are settled as blend arcs
//!   or stops the whole, a turn up to 0.866 of it as centripetal
//!   acceleration, so the same MAX_ACCELERATION gives the same
//!   acceleration per move as there. The difference: where a kink is
//!   crossed at speed, 10 % of each axis's acceleration is kept free for
//!   the velocity jump (a G61 move gets this reserve once the next move is
//!   found to meet it at speed, unless it is already running, when that
//!   corner becomes a stop); LinuxCNC lowers the acceleration around the
//!   kink instead. A move already running keeps its budget when the next
//!   move settles its end (LinuxCNC raises it);
//! * no reverse run;
//! * spindle-synchronised segments (`spindle_sync`) are locked to the
//!   spindle's position at its index pulse rather than where the axis
//!   first reaches the spindle's speed, a rigid tap's return keeps the
//!   tapping phase, and both run on the trapezoidal planner whichever
//!   planner is chosen;
//! * a resume requested while the S-curve planner is still braking for a
//!   pause takes effect once it is at rest.

mod budget;
mod corners;
mod exec;
mod geom;
mod indexer;
mod lookahead;
mod rigid_tap;
mod scurve;
mod segment;
mod spindle_sync;
mod sync_io;
mod trapezoid;

use std::collections::VecDeque;

pub use budget::{AxisLimits, PlannerType, TrajLimits};

/// The path length the planner gives an arc from `start` to `end` about
/// the axis through `center` along `normal`, `turns` as SET_CIRCLE has
/// them (a helix or spiral included); `None` for an arc the planner
/// refuses (no radius, no normal). For senders that work out a move's
/// own limits from its length, as LinuxCNC's canon does.
pub fn arc_length(
    start: &Pose,
    end: &Pose,
    center: [f64; 3],
    normal: [f64; 3],
    turns: i32,
) -> Option<f64> {
    geom::arc_move(start, end, center, normal, turns).map(|a| geom::Path::Arc(a).length())
}
pub use indexer::{IndexerFault, IndexerPhase, INDEXER_TIMEOUT};
pub use rigid_tap::TapState;
pub use segment::{FeedPerRev, SegmentKind};

use crate::command::{LineKind, ProbeType, Reject, TermCond};
use crate::kins::Pose;
use crate::sizes::{FH_ENABLED, FS_ENABLED, SS_ENABLED};
use segment::{Ending, Segment};

/// Segments the queue holds (LinuxCNC's `DEFAULT_TC_QUEUE_SIZE`).
pub const QUEUE_SIZE: usize = 2000;

pub use sync_io::{IoOutputs, SyncSet, SYNC_SETS};

/// The overrides and inputs that set the feed scale, read every period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaleInputs {
    /// Feed override (FEED_SCALE).
    pub feed: f64,
    /// Rapid override (RAPID_SCALE).
    pub rapid: f64,
    /// `motion.adaptive-feed`.
    pub adaptive: f64,
    /// `motion.feed-hold`.
    pub feed_hold: bool,
    /// `motion.feed-inhibit`.
    pub feed_inhibit: bool,
    /// The largest feed override and adaptive factor.
    pub max_feed_override: f64,
    /// Every running spindle is at speed (`spindle.N.at-speed`): a
    /// segment queued behind a spindle start waits for it.
    pub spindle_at_speed: bool,
    /// Each spindle's `speed-in`, revolutions per second (feed per
    /// revolution follows it).
    pub spindle_rps: [f64; crate::sizes::MAX_SPINDLES],
    /// Each joint's `is-unlocked` (bit n: joint n), for locking indexers.
    pub unlocked: u32,
    /// Each spindle's `revs`: its position, revolutions.
    pub spindle_revs: [f64; crate::sizes::MAX_SPINDLES],
    /// Each spindle's `index-enable` as read back (bit n: spindle n).
    pub spindle_index_enable: u32,
    /// The spindles commanded to turn in reverse (bit n: spindle n):
    /// their `revs` count down.
    pub spindle_reverse: u32,
}

impl Default for ScaleInputs {
    fn default() -> Self {
        ScaleInputs {
            feed: 1.0,
            rapid: 1.0,
            adaptive: 1.0,
            feed_hold: false,
            feed_inhibit: false,
            max_feed_override: 1.0,
            spindle_at_speed: true,
            spindle_rps: [0.0; crate::sizes::MAX_SPINDLES],
            unlocked: 0,
            spindle_revs: [0.0; crate::sizes::MAX_SPINDLES],
            spindle_index_enable: 0,
            spindle_reverse: 0,
        }
    }
}

impl ScaleInputs {
    /// The net scale for a segment queued with `enables` (LinuxCNC's
    /// `net_feed_scale`, §4.3), clamped to `0..=max_feed_override`.
    pub fn net(&self, enables: u8, traverse: bool) -> f64 {
        use crate::sizes::AF_ENABLED;
        let mut s = 1.0;
        if enables & FS_ENABLED != 0 {
            s *= if traverse { self.rapid } else { self.feed };
        }
        if enables & AF_ENABLED != 0 {
            s *= self.adaptive.clamp(0.0, self.max_feed_override.max(0.0));
        }
        if enables & FH_ENABLED != 0 && self.feed_hold {
            s = 0.0;
        }
        if enables & SS_ENABLED != 0 && self.feed_inhibit {
            s = 0.0;
        }
        if s.is_nan() {
            return 0.0;
        }
        s.clamp(0.0, self.max_feed_override.max(0.0))
    }
}

/// A snapshot of the planner for status and pins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannerStatus {
    /// The motion id of the executing segment, or of the last one run.
    pub exec_id: i32,
    /// Segments queued, the executing one included.
    pub depth: usize,
    /// Whether the queue is (nearly) full.
    pub queue_full: bool,
    /// Queue empty and at rest.
    pub done: bool,
    /// PAUSE in effect (also set while waiting after a single step).
    pub paused: bool,
    /// A single step runs.
    pub stepping: bool,
    /// An abort is stopping the motion.
    pub aborting: bool,
    /// Path speed now.
    pub current_vel: f64,
    /// Path speed asked for now (programmed speed times the scale).
    pub requested_vel: f64,
    /// Distance left in the executing segment.
    pub distance_to_go: f64,
    /// Per axis, the executing segment's end minus where the path is now
    /// (LinuxCNC's `dtg`; zero with nothing moving or in a dwell).
    pub dtg: Pose,
    /// The executing segment's kind, if any.
    pub kind: Option<SegmentKind>,
    /// The net feed scale of the executing segment.
    pub net_scale: f64,
    /// The planner in use.
    pub planner: PlannerType,
    /// The executing segment waits for the spindle to reach its speed.
    pub waiting_for_atspeed: bool,
    /// The override enable bits of the executing segment, if any.
    pub enables: Option<u8>,
    /// A locking indexer's handshake or move runs.
    pub indexer: Option<IndexerPhase>,
}

impl PlannerStatus {
    /// LinuxCNC's `motion.motion-type`: the executing segment's kind, or 6
    /// (rotary unlock for traverse) while a locking indexer unlocks, moves
    /// or relocks.
    pub fn motion_type(&self) -> i32 {
        if self.indexer.is_some() {
            return 6;
        }
        self.kind.map_or(0, |k| k.number())
    }
}

/// `[TRAJ]ARC_BLEND_*` as SETUP_ARC_BLENDS gives them (see
/// [`crate::Command::SetupArcBlends`]); only `enable` changes what this
/// planner does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcBlends {
    /// Corners are rounded with blend arcs (G64).
    pub enable: bool,
    /// ARC_BLEND_FALLBACK_ENABLE.
    pub fallback: bool,
    /// ARC_BLEND_OPTIMIZATION_DEPTH.
    pub depth: i32,
    /// ARC_BLEND_GAP_CYCLES.
    pub gap_cycles: i32,
    /// ARC_BLEND_RAMP_FREQ, Hz.
    pub ramp_freq: f64,
}

impl Default for ArcBlends {
    /// LinuxCNC's defaults: enabled, no fallback, depth 50, 4 gap cycles,
    /// 100 Hz.
    fn default() -> Self {
        ArcBlends {
            enable: true,
            fallback: false,
            depth: 50,
            gap_cycles: 4,
            ramp_freq: 100.0,
        }
    }
}

/// The coordinated planner.
pub struct Planner {
    queue: VecDeque<Segment>,
    period: f64,
    traj: TrajLimits,
    planner: PlannerType,
    /// A planner type switch waiting for the queue to be idle.
    pending_planner: Option<PlannerType>,
    term: TermCond,
    tolerance: f64,
    /// SET_VEL: the trajectory velocity and the INI velocity, kept (as
    /// LinuxCNC's planner keeps them), not used to limit moves.
    traj_vel: (f64, f64),
    /// SETUP_ARC_BLENDS.
    arc_blends: ArcBlends,
    /// The pose new segments start from (end of the last queued one).
    goal: Pose,
    /// The commanded pose.
    pos: Pose,
    /// Progress along the executing segment.
    s: f64,
    /// Path speed and (S-curve) acceleration.
    v: f64,
    a: f64,
    /// One period at rest after an exact stop (see `exec`).
    hold: bool,
    /// The acceleration the period after a corner may use (the smaller
    /// of the two segments'; infinite when no corner was just crossed).
    cross_acc: f64,
    dwell_left: Option<f64>,
    exec_id: i32,
    paused: bool,
    stepping: bool,
    step_id: i32,
    aborting: bool,
    requested_vel: f64,
    net_scale: f64,
    /// The largest feed override seen (`ScaleInputs::max_feed_override`):
    /// a blend arc is sized for the programmed feed times it.
    max_feed_scale: f64,
    scurve: scurve::SCurve,
    /// The next segment pushed waits for the spindle at speed before it
    /// starts (LinuxCNC's at-speed barrier), from rest.
    atspeed_pending: bool,
    /// The executing segment waits for the spindle at speed.
    waiting_for_atspeed: bool,
    /// The executing segment has started (its output changes written).
    head_started: bool,
    /// The feed per revolution of the feed moves queued next (G95).
    feed_per_rev: Option<FeedPerRev>,
    /// The position synchronisation of the feed moves queued next (G33).
    position_sync: Option<FeedPerRev>,
    /// The lock of the executing segment to its spindle.
    track: spindle_sync::Track,
    /// A rigid tap's spindle reversal for the controller: the spindle
    /// and the factor of its speed.
    spindle_reversal: Option<(usize, f64)>,
    /// The next segment pushed is a locking indexer's move of this joint.
    indexer_pending: Option<usize>,
    /// The locking indexer handshake in progress.
    indexer: Option<indexer::IndexerRun>,
    /// A handshake wait that ran out, for the controller to report.
    indexer_fault: Option<IndexerFault>,
    /// Outputs changed in step with the queue (M62, M63, M67) and
    /// their values.
    sync_io: sync_io::SyncIo,
}

impl std::fmt::Debug for Planner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Planner")
            .field("depth", &self.queue.len())
            .field("pos", &self.pos)
            .field("v", &self.v)
            .finish_non_exhaustive()
    }
}

impl Planner {
    /// An empty planner for servo period `period` seconds, at rest at the
    /// origin. All memory is allocated here.
    pub fn new(period: f64) -> Planner {
        Planner {
            queue: VecDeque::with_capacity(QUEUE_SIZE),
            period,
            traj: TrajLimits::default(),
            planner: PlannerType::Trapezoidal,
            pending_planner: None,
            term: TermCond::Blend,
            tolerance: 0.0,
            traj_vel: (0.0, 0.0),
            arc_blends: ArcBlends::default(),
            goal: Pose::ZERO,
            pos: Pose::ZERO,
            s: 0.0,
            v: 0.0,
            a: 0.0,
            hold: false,
            cross_acc: f64::INFINITY,
            dwell_left: None,
            exec_id: 0,
            paused: false,
            stepping: false,
            step_id: 0,
            aborting: false,
            requested_vel: 0.0,
            net_scale: 1.0,
            max_feed_scale: 1.0,
            scurve: scurve::SCurve::new(period),
            atspeed_pending: false,
            waiting_for_atspeed: false,
            head_started: false,
            feed_per_rev: None,
            position_sync: None,
            track: spindle_sync::Track::default(),
            spindle_reversal: None,
            indexer_pending: None,
            indexer: None,
            indexer_fault: None,
            sync_io: sync_io::SyncIo::default(),
        }
    }

    /// The commanded pose.
    pub fn pos(&self) -> Pose {
        self.pos
    }

    /// Whether nothing is queued and the motion is at rest.
    pub fn is_done(&self) -> bool {
        self.queue.is_empty() && self.v == 0.0 && !self.hold && self.indexer.is_none()
    }

    /// The planner in use.
    pub fn planner_type(&self) -> PlannerType {
        self.planner
    }

    /// The machine-wide limits in use.
    pub fn traj_limits(&self) -> TrajLimits {
        self.traj
    }

    /// The status snapshot.
    pub fn status(&self) -> PlannerStatus {
        let head = self.queue.front();
        PlannerStatus {
            exec_id: self.exec_id,
            depth: self.queue.len(),
            queue_full: self.queue.len() >= QUEUE_SIZE,
            done: self.is_done(),
            paused: self.paused,
            stepping: self.stepping,
            aborting: self.aborting,
            current_vel: self.v,
            requested_vel: self.requested_vel,
            distance_to_go: head.map_or(0.0, |h| (h.len - self.s).max(0.0)),
            dtg: head
                .filter(|h| h.kind != SegmentKind::Dwell)
                .map_or(Pose::default(), |h| {
                    let end = h.end();
                    Pose(std::array::from_fn(|a| end.0[a] - self.pos.0[a]))
                }),
            kind: head.map(|h| h.kind),
            net_scale: self.net_scale,
            planner: self.planner,
            waiting_for_atspeed: self.waiting_for_atspeed,
            indexer: self.indexer_phase(),
            enables: head.map(|h| h.enables),
        }
    }

    /// The executing segment's probe type and motion id, if it is a
    /// probing move.
    pub fn probe_segment(&self) -> Option<(ProbeType, i32)> {
        self.queue.front().and_then(|h| h.probe.map(|p| (p, h.id)))
    }

    /// Puts the planner at rest at `pose` with an empty queue (entering
    /// coordinated mode, enabling; LinuxCNC's `tpSetPos` + `tpClear`).
    pub fn set_pos(&mut self, pose: Pose) {
        self.clear();
        self.pos = pose;
        self.goal = pose;
    }

    /// Drops every segment at once, without slowing down (disable, faults:
    /// the drives are off); the goal becomes the commanded pose.
    pub fn clear(&mut self) {
        self.queue.clear();
        // An unlocked indexer's request drops with the queue (its lock is
        // not waited for: nothing moves after a clear).
        self.indexer = None;
        self.indexer_pending = None;
        self.goal = self.pos;
        self.s = 0.0;
        self.v = 0.0;
        self.a = 0.0;
        self.hold = false;
        self.cross_acc = f64::INFINITY;
        self.dwell_left = None;
        self.paused = false;
        self.stepping = false;
        self.aborting = false;
        self.requested_vel = 0.0;
        self.waiting_for_atspeed = false;
        self.head_started = false;
        self.feed_per_rev = None;
        self.position_sync = None;
        self.track = spindle_sync::Track::default();
        self.spindle_reversal = None;
        self.sync_io.clear();
        self.scurve.reset();
        if let Some(p) = self.pending_planner.take() {
            self.planner = p;
        }
    }

    /// Sets the feed per revolution of the feed moves queued next (`None`:
    /// units per minute again).
    pub fn set_feed_per_rev(&mut self, per_rev: Option<FeedPerRev>) {
        self.feed_per_rev = per_rev;
    }

    /// Sets the position synchronisation of the feed moves queued next
    /// (G33: their progress follows the spindle's position; `None`:
    /// off). It takes precedence over a feed per revolution.
    pub fn set_position_sync(&mut self, sync: Option<FeedPerRev>) {
        self.position_sync = sync;
    }

    /// Sets the termination condition of the segments queued next.
    pub fn set_term_cond(&mut self, cond: TermCond, tolerance: f64) {
        self.term = cond;
        self.tolerance = tolerance;
    }

    /// SET_VEL: keeps the trajectory velocity and the INI velocity.
    pub fn set_traj_vel(&mut self, vel: f64, ini_maxvel: f64) {
        self.traj_vel = (vel, ini_maxvel);
    }

    /// The trajectory velocity and the INI velocity SET_VEL gave.
    pub fn traj_vel(&self) -> (f64, f64) {
        self.traj_vel
    }

    /// SETUP_ARC_BLENDS, for the segments queued next.
    pub fn set_arc_blends(&mut self, blends: ArcBlends) {
        self.arc_blends = blends;
    }

    /// The arc blend settings in effect.
    pub fn arc_blends(&self) -> ArcBlends {
        self.arc_blends
    }

    /// Sets the machine-wide limits (for segments queued next).
    pub fn set_traj_limits(&mut self, traj: TrajLimits) {
        self.traj = traj;
    }

    /// Switches the planner type now if idle, else once idle.
    pub fn set_planner_type(&mut self, planner: PlannerType) {
        if self.is_done() {
            self.planner = planner;
            self.pending_planner = None;
        } else if planner == self.planner {
            self.pending_planner = None;
        } else {
            self.pending_planner = Some(planner);
        }
    }

    /// PAUSE: slow down along the path and stop; the queue is kept.
    pub fn pause(&mut self) {
        self.paused = true;
    }

    /// RESUME.
    pub fn resume(&mut self) {
        self.paused = false;
        self.stepping = false;
    }

    /// ABORT: slow down along the path; once at rest the queue is
    /// dropped. Nothing is queued meanwhile.
    pub fn abort(&mut self) {
        if self.queue.is_empty() && self.v == 0.0 {
            self.clear();
        } else {
            self.aborting = true;
        }
    }

    /// Whether an abort is in progress.
    pub fn is_aborting(&self) -> bool {
        self.aborting
    }

    /// The ending of a segment queued now.
    fn ending(&self) -> Ending {
        match self.term {
            TermCond::Stop => Ending::Stop,
            TermCond::ExactPath => Ending::ExactPath,
            // Without arc blends no corner is rounded.
            TermCond::Blend if !self.arc_blends.enable => Ending::ExactPath,
            TermCond::Blend => Ending::Blend {
                tolerance: self.tolerance,
            },
        }
    }

    /// Checks that a segment can be queued now.
    fn can_queue(&self) -> Result<(), Reject> {
        if self.aborting {
            return Err(Reject::Aborting);
        }
        if self.queue.len() >= QUEUE_SIZE || !self.sync_io.has_room() {
            return Err(Reject::QueueFull {
                capacity: QUEUE_SIZE,
            });
        }
        Ok(())
    }

    /// Digital output `index` (below [`MAX_IO`](crate::sizes::MAX_IO))
    /// to `on`: now, or when the next segment queued starts.
    pub fn set_dout(&mut self, index: usize, on: bool, now: bool) {
        if now {
            self.sync_io.outputs.dout[index] = on;
        } else {
            self.sync_io.pending.set_dout(index, on);
        }
    }

    /// Analog output `index` to `value`: now, or when the next segment
    /// queued starts.
    pub fn set_aout(&mut self, index: usize, value: f64, now: bool) {
        if now {
            self.sync_io.outputs.aout[index] = value;
        } else {
            self.sync_io.pending.set_aout(index, value);
        }
    }

    /// The outputs M62 to M68 set.
    pub fn io_outputs(&self) -> &IoOutputs {
        &self.sync_io.outputs
    }

    /// The executing segment starts: the output changes it carries are
    /// written.
    pub(super) fn start_head(&mut self) {
        if self.head_started {
            return;
        }
        self.head_started = true;
        if self.queue.front().is_some_and(|h| h.sync) {
            self.sync_io.fire();
        }
    }

    /// Whether the next segment pushed waits, from rest, for the
    /// spindle at speed (set before queueing a feed move behind a spindle
    /// start; [`Self::take_atspeed_pending`] tells whether it was used).
    pub fn set_atspeed_pending(&mut self, on: bool) {
        self.atspeed_pending = on;
    }

    /// Clears the at-speed request; true if no segment took it (a move
    /// too short to queue, or a refusal).
    pub fn take_atspeed_pending(&mut self) -> bool {
        std::mem::take(&mut self.atspeed_pending)
    }

    /// The pose the next segment starts from.
    pub fn goal(&self) -> Pose {
        self.goal
    }

    /// Queues a straight move to `end` (see [`crate::Command::Line`]).
    /// `enables` are the feed-override enable bits in effect.
    pub fn add_line(
        &mut self,
        end: Pose,
        kind: LineKind,
        vel: f64,
        id: i32,
        enables: u8,
        lim: &AxisLimits,
    ) -> Result<(), Reject> {
        self.can_queue()?;
        let (kind, req) = match kind {
            // A rapid goes as fast as its limits allow, or at the speed
            // task gave it.
            LineKind::Traverse if vel > 0.0 => (SegmentKind::Traverse, vel),
            LineKind::Traverse => (SegmentKind::Traverse, f64::INFINITY),
            LineKind::Feed => (SegmentKind::Feed, vel),
        };
        self.add_straight(end, kind, req, None, id, enables, lim)
    }

    /// Queues a straight probing move to `end`.
    #[allow(clippy::too_many_arguments)]
    pub fn add_probe(
        &mut self,
        end: Pose,
        vel: f64,
        probe: ProbeType,
        id: i32,
        enables: u8,
        lim: &AxisLimits,
    ) -> Result<(), Reject> {
        self.can_queue()?;
        self.add_straight(end, SegmentKind::Probe, vel, Some(probe), id, enables, lim)
    }

    #[allow(clippy::too_many_arguments)]
    fn add_straight(
        &mut self,
        end: Pose,
        kind: SegmentKind,
        req: f64,
        probe: Option<ProbeType>,
        id: i32,
        enables: u8,
        lim: &AxisLimits,
    ) -> Result<(), Reject> {
        let mut delta = [0.0; crate::kins::NUM_AXES];
        for (i, d) in delta.iter_mut().enumerate() {
            *d = end.0[i] - self.goal.0[i];
        }
        let path = geom::Path::Line {
            start: self.goal,
            delta,
        };
        self.push(path, &end, kind, req, probe, id, enables, lim);
        Ok(())
    }

    /// Queues an arc (see [`crate::Command::Circle`]).
    #[allow(clippy::too_many_arguments)]
    pub fn add_arc(
        &mut self,
        end: Pose,
        center: [f64; 3],
        normal: [f64; 3],
        turns: i32,
        vel: f64,
        id: i32,
        enables: u8,
        lim: &AxisLimits,
    ) -> Result<(), Reject> {
        self.can_queue()?;
        let arc = geom::arc_move(&self.goal, &end, center, normal, turns).ok_or(Reject::BadArc)?;
        self.push(
            geom::Path::Arc(arc),
            &end,
            SegmentKind::Arc,
            vel,
            None,
            id,
            enables,
            lim,
        );
        Ok(())
    }

    /// The path a straight or arc move to `end` would take from the goal,
    /// for the caller's limit checks; `None` for an impossible arc.
    pub fn path_extent(
        &self,
        end: &Pose,
        arc: Option<([f64; 3], [f64; 3], i32)>,
    ) -> Option<([f64; 9], [f64; 9])> {
        let path = match arc {
            None => {
                let mut delta = [0.0; crate::kins::NUM_AXES];
                for (i, d) in delta.iter_mut().enumerate() {
                    *d = end.0[i] - self.goal.0[i];
                }
                geom::Path::Line {
                    start: self.goal,
                    delta,
                }
            }
            Some((center, normal, turns)) => {
                geom::Path::Arc(geom::arc_move(&self.goal, end, center, normal, turns)?)
            }
        };
        Some(path.extent(path.length()))
    }

    /// Queues a dwell of `seconds`.
    pub fn add_dwell(&mut self, seconds: f64, id: i32) -> Result<(), Reject> {
        self.can_queue()?;
        let mut seg = Segment {
            id,
            kind: SegmentKind::Dwell,
            path: geom::Path::Line {
                start: self.goal,
                delta: [0.0; crate::kins::NUM_AXES],
            },
            end: self.goal,
            len: 0.0,
            nominal_len: 0.0,
            start_cut: 0.0,
            req_vel: 0.0,
            budget: budget::Budget {
                vmax: 0.0,
                acc: 1.0,
                jerk: 1.0,
            },
            end_cap: 0.0,
            ve: 0.0,
            ending: Ending::Stop,
            enables: 0,
            dwell: seconds,
            probe: None,
            start_joins: budget::End::Stop,
            end_joins: budget::End::Stop,
            step_stop: false,
            atspeed: false,
            sync: false,
            per_rev: None,
            locked: None,
            tap: None,
            indexer: None,
        };
        seg.sync = self.sync_io.attach();
        if let Some(last) = self.queue.back_mut() {
            last.end_cap = 0.0;
        }
        self.queue.push_back(seg);
        self.optimize();
        Ok(())
    }
}

#[cfg(test)]
mod spindle_sync_tests;
#[cfg(test)]
mod tests;
