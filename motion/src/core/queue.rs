//! The queueing commands (SET_LINE, SET_CIRCLE, PROBE, dwells) with the
//! checks every queued move passes, and the commands that steer the
//! coordinated planner: termination condition, pause, resume, step,
//! overrides, limits and the planner type.
//!
//! A move is queued only in coordinated mode with motion enabled, with no
//! active joint on a hard limit, with finite coordinates, and if every
//! point of its path stays within the axis limits (arcs are checked at
//! their bulges, not only at their ends as LinuxCNC does) and the
//! kinematics put every active joint of its end point within its soft
//! limits. Its speed limits are each axis's own, lowered to what the
//! joints it moves allow (through the kinematics at its end point: exact
//! for identity kinematics, where each axis drives its joints one to one).

use super::*;
use crate::command::{CommandResult, LineKind, Quantity, Reject, TermCond};
use crate::sizes::{AF_ENABLED, FH_ENABLED, FS_ENABLED, SS_ENABLED};
use crate::tp::{AxisLimits, PlannerType};

/// A finite coordinate, or a rejection naming it.
fn coordinate(v: f64) -> Result<f64, Reject> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Reject::BadValue {
            what: Quantity::Coordinate,
            value: v,
        })
    }
}

/// A queued move's own caps on its path speed and acceleration
/// (SET_LINE's and SET_CIRCLE's `ini_maxvel` and `acc`; infinite where
/// the command gave 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct MoveCaps {
    vel: f64,
    acc: f64,
}

impl MoveCaps {
    /// The caps of `ini_maxvel` and `acc`: each finite and at least 0,
    /// 0 for none.
    pub(super) fn new(ini_maxvel: f64, acc: f64) -> Result<MoveCaps, Reject> {
        let cap = |what, v: f64| {
            if !(v.is_finite() && v >= 0.0) {
                Err(Reject::BadValue { what, value: v })
            } else if v == 0.0 {
                Ok(f64::INFINITY)
            } else {
                Ok(v)
            }
        };
        Ok(MoveCaps {
            vel: cap(Quantity::MoveSpeedCap, ini_maxvel)?,
            acc: cap(Quantity::MoveAccelerationCap, acc)?,
        })
    }

    /// `lim` with these caps.
    fn apply(self, mut lim: AxisLimits) -> AxisLimits {
        lim.path_vel = self.vel;
        lim.path_acc = self.acc;
        lim
    }
}

/// A usable programmed speed.
fn feed(vel: f64) -> Result<f64, Reject> {
    if vel.is_finite() && vel > 0.0 {
        Ok(vel)
    } else {
        Err(Reject::BadVelocity { vel })
    }
}

impl MotionCore {
    /// What every queued move needs from the machine.
    fn queue_allowed(&self) -> CommandResult {
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        if self.state != MotionState::Coord {
            return Err(Reject::NotCoordMode);
        }
        if let Some(joint) = (0..self.joints.len())
            .find(|&j| self.joints[j].active && (self.joints[j].phl || self.joints[j].nhl))
        {
            return Err(Reject::HardLimitTripped { joint });
        }
        Ok(())
    }

    /// Checks a move to `end` (an arc if `arc` is given): coordinates,
    /// axis limits along the path, joint limits at the end.
    fn check_move(&mut self, end: &Pose, arc: Option<([f64; 3], [f64; 3], i32)>) -> CommandResult {
        for &v in &end.0 {
            coordinate(v)?;
        }
        if let Some((c, n, _)) = arc {
            for v in c.into_iter().chain(n) {
                coordinate(v)?;
            }
        }
        let (lo, hi) = self.tp.path_extent(end, arc).ok_or(Reject::BadArc)?;
        for a in 0..NUM_AXES {
            if !self.axis_in_kinematics(a) {
                continue;
            }
            let cfg = self.world.axes[a].cfg;
            if hi[a] > cfg.max_pos_limit {
                return Err(Reject::OutsideAxisLimits {
                    axis: a,
                    value: hi[a],
                    min: cfg.min_pos_limit,
                    max: cfg.max_pos_limit,
                });
            }
            if lo[a] < cfg.min_pos_limit {
                return Err(Reject::OutsideAxisLimits {
                    axis: a,
                    value: lo[a],
                    min: cfg.min_pos_limit,
                    max: cfg.max_pos_limit,
                });
            }
        }
        let n = self.load_positions(|jt| jt.coarse_pos);
        let mut flags = self.kins_flags;
        self.kins
            .inverse(end, &mut self.positions[..n], &mut flags)
            .map_err(|_| Reject::EndUnreachable)?;
        for (j, jt) in self.joints[..n].iter().enumerate() {
            if !jt.active {
                continue;
            }
            let q = self.positions[j];
            if !q.is_finite() {
                return Err(Reject::EndUnreachable);
            }
            if q > jt.cfg.max_pos_limit || q < jt.cfg.min_pos_limit {
                return Err(Reject::OutsideJointLimits {
                    joint: j,
                    value: q,
                    min: jt.cfg.min_pos_limit,
                    max: jt.cfg.max_pos_limit,
                });
            }
        }
        Ok(())
    }

    /// The limits the planner uses for a move ending at `at`: each axis's,
    /// lowered by those of the joints it moves (how much each joint moves
    /// per unit of the axis, through the inverse kinematics there).
    fn planning_limits(&mut self, at: &Pose) -> AxisLimits {
        let mut lim = AxisLimits::default();
        for a in 0..NUM_AXES {
            let cfg = self.world.axes[a].cfg;
            lim.vel[a] = cfg.plan_vel();
            lim.acc[a] = cfg.plan_acc();
            lim.jerk[a] = cfg.jerk_limit;
        }
        let n = self.load_positions(|jt| jt.coarse_pos);
        let mut q0 = [0.0; MAX_JOINTS];
        let mut flags = self.kins_flags;
        if self
            .kins
            .inverse(at, &mut self.positions[..n], &mut flags)
            .is_err()
        {
            return lim;
        }
        q0[..n].copy_from_slice(&self.positions[..n]);
        for a in 0..NUM_AXES {
            if !self.axis_in_kinematics(a) {
                continue;
            }
            let delta = 1e-6 * at.0[a].abs().max(1.0);
            let mut p = *at;
            p.0[a] += delta;
            let mut q1 = q0;
            let mut flags = self.kins_flags;
            if self.kins.inverse(&p, &mut q1[..n], &mut flags).is_err() {
                continue;
            }
            for (j, jt) in self.joints[..n].iter().enumerate() {
                if !jt.active {
                    continue;
                }
                let ratio = (q1[j] - q0[j]).abs() / delta;
                if !(ratio > 1e-9 && ratio.is_finite()) {
                    continue;
                }
                // The axis's external offset takes its share of the
                // joint's limits too.
                let keep = 1.0 - self.world.axes[a].cfg.eoffset_ratio;
                lim.vel[a] = lim.vel[a].min(jt.cfg.vel_limit / ratio * keep);
                lim.acc[a] = lim.acc[a].min(jt.cfg.acc_limit / ratio * keep);
                if jt.cfg.jerk_limit > 0.0 {
                    let j_axis = jt.cfg.jerk_limit / ratio;
                    lim.jerk[a] = if lim.jerk[a] > 0.0 {
                        lim.jerk[a].min(j_axis)
                    } else {
                        j_axis
                    };
                }
            }
        }
        lim
    }

    /// SET_LINE.
    pub(super) fn queue_line(
        &mut self,
        end: Pose,
        vel: f64,
        caps: MoveCaps,
        kind: LineKind,
        id: i32,
    ) -> CommandResult {
        self.queue_allowed()?;
        // A rapid's speed is optional (0: as fast as the limits allow).
        if kind == LineKind::Feed || vel != 0.0 {
            feed(vel)?;
        }
        self.check_move(&end, None)?;
        let indexer = self.indexer_move(&end, kind == LineKind::Traverse)?;
        let lim = caps.apply(self.planning_limits(&end));
        let enables = self.enables_new;
        let feed_move = kind == LineKind::Feed;
        self.tp.set_indexer_pending(indexer);
        let r = self.with_atspeed_barrier(feed_move, |tp| {
            tp.add_line(end, kind, vel, id, enables, &lim)
        });
        // A move too short to queue leaves no request for the next one.
        self.tp.set_indexer_pending(None);
        r?;
        self.queued();
        Ok(())
    }

    /// SET_CIRCLE: `arc` is its center, normal and turns.
    pub(super) fn queue_circle(
        &mut self,
        end: Pose,
        arc: ([f64; 3], [f64; 3], i32),
        vel: f64,
        caps: MoveCaps,
        id: i32,
    ) -> CommandResult {
        let (center, normal, turns) = arc;
        self.queue_allowed()?;
        feed(vel)?;
        self.check_move(&end, Some(arc))?;
        self.no_indexer_move(&end)?;
        let lim = caps.apply(self.planning_limits(&end));
        let enables = self.enables_new;
        self.with_atspeed_barrier(true, |tp| {
            tp.add_arc(end, center, normal, turns, vel, id, enables, &lim)
        })?;
        self.queued();
        Ok(())
    }

    /// RIGID_TAP (G33.1): the tap to `end` and back.
    pub(super) fn queue_rigid_tap(
        &mut self,
        end: Pose,
        vel: f64,
        scale: f64,
        id: i32,
    ) -> CommandResult {
        self.queue_allowed()?;
        feed(vel)?;
        // It moves in X, Y and Z only, to the end and back.
        let mut end3 = self.tp.goal();
        end3.0[..3].copy_from_slice(&end.0[..3]);
        self.check_move(&end3, None)?;
        self.no_indexer_move(&end3)?;
        let lim = self.planning_limits(&end3);
        let enables = self.enables_new;
        self.with_atspeed_barrier(true, |tp| {
            tp.add_rigid_tap(end3, vel, scale, id, enables, &lim)
        })?;
        self.queued();
        Ok(())
    }

    /// PROBE: clears the last result; refused if the input already shows
    /// what the move looks for (unless errors are suppressed).
    pub(super) fn queue_probe(
        &mut self,
        end: Pose,
        vel: f64,
        probe: ProbeType,
        id: i32,
    ) -> CommandResult {
        self.queue_allowed()?;
        feed(vel)?;
        if !probe.no_error && self.inputs.probe_input != probe.trip_on_clear {
            return Err(Reject::ProbeAlreadyThere {
                trip_on_clear: probe.trip_on_clear,
            });
        }
        self.check_move(&end, None)?;
        self.no_indexer_move(&end)?;
        let lim = self.planning_limits(&end);
        let enables = self.enables_new;
        self.with_atspeed_barrier(true, |tp| tp.add_probe(end, vel, probe, id, enables, &lim))?;
        self.probe.tripped = false;
        self.queued();
        Ok(())
    }

    /// A dwell of `seconds`.
    pub(super) fn queue_dwell(&mut self, seconds: f64, id: i32) -> CommandResult {
        self.queue_allowed()?;
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(Reject::BadValue {
                what: Quantity::DwellTime,
                value: seconds,
            });
        }
        self.tp.add_dwell(seconds, id)?;
        self.queued();
        Ok(())
    }

    /// Queues a move with `add`; a feed move (`feed_move`) takes the
    /// at-speed barrier a spindle start left (it starts from rest once
    /// the spindles are at speed). The barrier stays for the next feed
    /// move when this one was refused or too short to queue.
    fn with_atspeed_barrier(
        &mut self,
        feed_move: bool,
        add: impl FnOnce(&mut crate::tp::Planner) -> CommandResult,
    ) -> CommandResult {
        self.tp
            .set_atspeed_pending(feed_move && self.atspeed_next_feed);
        let r = add(&mut self.tp);
        let unused = self.tp.take_atspeed_pending();
        if r.is_ok() && feed_move {
            self.atspeed_next_feed = unused;
        }
        r
    }

    /// What every queued move does (as LinuxCNC's SET_LINE on success).
    fn queued(&mut self) {
        self.error = false;
        self.rehome_all = true;
    }

    /// SET_DOUT (M62 to M65).
    pub(super) fn set_dout(&mut self, index: i32, on: bool, now: bool) -> CommandResult {
        let i = Self::io_index(index, self.cfg.num_dio)?;
        self.tp.set_dout(i, on, now);
        Ok(())
    }

    /// SET_AOUT (M67, M68).
    pub(super) fn set_aout(&mut self, index: i32, value: f64, now: bool) -> CommandResult {
        let i = Self::io_index(index, self.cfg.num_aio)?;
        let value = Self::finite(Quantity::AnalogValue, value)?;
        self.tp.set_aout(i, value, now);
        Ok(())
    }

    fn io_index(index: i32, count: usize) -> Result<usize, Reject> {
        usize::try_from(index)
            .ok()
            .filter(|&i| i < count)
            .ok_or(Reject::NoSuchOutput { index, count })
    }

    /// SET_TERM_COND.
    pub(super) fn set_term_cond(&mut self, cond: TermCond, tolerance: f64) -> CommandResult {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(Reject::BadValue {
                what: Quantity::BlendTolerance,
                value: tolerance,
            });
        }
        self.tp.set_term_cond(cond, tolerance);
        Ok(())
    }

    /// CLEAR_PROBE_FLAGS.
    pub(super) fn clear_probe_flags(&mut self) -> CommandResult {
        self.probe.tripped = false;
        Ok(())
    }

    /// PAUSE.
    pub(super) fn pause(&mut self) -> CommandResult {
        self.tp.pause();
        Ok(())
    }

    /// RESUME.
    pub(super) fn resume(&mut self) -> CommandResult {
        self.tp.resume();
        Ok(())
    }

    /// STEP.
    pub(super) fn step(&mut self) -> CommandResult {
        self.tp.step()
    }

    /// FEED_SCALE, RAPID_SCALE and SET_MAX_FEED_OVERRIDE.
    pub(super) fn set_override(&mut self, which: Override, scale: f64) -> CommandResult {
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(Reject::BadValue {
                what: Quantity::Scale,
                value: scale,
            });
        }
        match which {
            Override::Feed => self.feed_scale = scale,
            Override::Rapid => self.rapid_scale = scale.min(1.0),
            Override::Max => self.max_feed_override = scale,
        }
        Ok(())
    }

    /// FS/FH/AF/SS_ENABLE: sets or clears `bit` for the moves queued next.
    pub(super) fn set_enable(&mut self, bit: u8, on: bool) -> CommandResult {
        debug_assert!([FS_ENABLED, FH_ENABLED, AF_ENABLED, SS_ENABLED].contains(&bit));
        if on {
            self.enables_new |= bit;
        } else {
            self.enables_new &= !bit;
        }
        Ok(())
    }

    /// SET_VEL_LIMIT, SET_ACC and SET_JERK: the `[TRAJ]` limits.
    pub(super) fn set_traj_limit(&mut self, what: Quantity, value: f64) -> CommandResult {
        if !(value.is_finite() && value > 0.0) {
            return Err(Reject::BadValue { what, value });
        }
        let mut t = self.tp.traj_limits();
        match what {
            Quantity::VelocityLimit => t.max_vel = value,
            Quantity::AccelerationLimit => t.max_acc = value,
            _ => t.max_jerk = value.min(1e9),
        }
        if what == Quantity::JerkLimit
            && t.max_jerk < 1.0
            && self.tp.planner_type() == PlannerType::SCurve
        {
            return Err(Reject::NeedsJerkLimit { jerk: value });
        }
        self.tp.set_traj_limits(t);
        Ok(())
    }

    /// SET_VEL: the trajectory velocity and INI velocity, both finite
    /// and at least 0, kept by the planner.
    pub(super) fn set_traj_vel(&mut self, vel: f64, ini_maxvel: f64) -> CommandResult {
        let vel = Self::non_negative(Quantity::TrajVelocity, vel)?;
        let ini_maxvel = Self::non_negative(Quantity::TrajVelocity, ini_maxvel)?;
        self.tp.set_traj_vel(vel, ini_maxvel);
        Ok(())
    }

    /// SETUP_ARC_BLENDS, for the moves queued next.
    pub(super) fn set_arc_blends(&mut self, blends: crate::tp::ArcBlends) -> CommandResult {
        let whole = |v: i32| {
            if v >= 0 {
                Ok(())
            } else {
                Err(Reject::BadValue {
                    what: Quantity::ArcBlendSetting,
                    value: f64::from(v),
                })
            }
        };
        whole(blends.depth)?;
        whole(blends.gap_cycles)?;
        Self::non_negative(Quantity::ArcBlendSetting, blends.ramp_freq)?;
        self.tp.set_arc_blends(blends);
        Ok(())
    }

    /// SET_PLANNER_TYPE: 0 trapezoidal, 1 S-curve.
    pub(super) fn set_planner_type(&mut self, planner: i32) -> CommandResult {
        let p = match planner {
            0 => PlannerType::Trapezoidal,
            1 => {
                let jerk = self.tp.traj_limits().max_jerk;
                if jerk < 1.0 {
                    return Err(Reject::NeedsJerkLimit { jerk });
                }
                PlannerType::SCurve
            }
            _ => {
                return Err(Reject::BadValue {
                    what: Quantity::PlannerType,
                    value: f64::from(planner),
                })
            }
        };
        self.tp.set_planner_type(p);
        Ok(())
    }
}

/// Which override a scale command sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Override {
    Feed,
    Rapid,
    Max,
}
