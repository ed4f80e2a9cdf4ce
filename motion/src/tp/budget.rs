//! How fast a segment may go: its speed cap, tangential acceleration and
//! tangential jerk, derived from every axis's limits through the
//! segment's `AxisFactors`, and the speed at which a corner between two
//! segments may be crossed.
//!
//! The rules, per axis `i` with limits `V_i`, `A_i`, `J_i`, depend on how
//! the segment meets its neighbours ([`Joins`]):
//! * speed: `v · speed_i ≤ V_i`;
//! * acceleration: the bound of `AxisFactors::accel` at the segment's
//!   speed cap stays within `A_i`; the centripetal part is held to
//!   [`NORMAL_SHARE`] of it (LinuxCNC's 0.866), so a turn at full speed
//!   keeps half the acceleration for speeding up and slowing down along
//!   it;
//! * a segment that may meet another at a kink ([`Joins::Kink`],
//!   [`Joins::Blend`]) keeps [`KINK_RESERVE`] of each axis's acceleration
//!   free: crossing a kink at speed `c` changes axis `i`'s velocity by
//!   `c·|Δt_i|` within one period, which the corner cap keeps within that
//!   reserve;
//! * a segment that may be blended ([`Joins::Blend`]: an end under G64
//!   not met by a blend arc, the last queued move included) may use
//!   [`BLEND_SHARE`] of its tangential acceleration, as LinuxCNC's planner
//!   gives it (it keeps the other half for its parabolic blends): the same
//!   MAX_ACCELERATION gives the same acceleration per move as there. A
//!   lone G0 under G64 speeds up at half the axis limit;
//! * jerk (S-curve planner): the bound of `AxisFactors::jerk` stays
//!   within `J_i`; a segment entered or left at speed keeps
//!   [`JERK_RESERVE`] of it for the corners: the velocity jump and the
//!   jump of the centripetal acceleration (where a straight move meets a
//!   turn), both within one period, stay within that reserve; and, as
//!   LinuxCNC, a turn that may be entered at speed goes no faster than
//!   `√(J·R·T)` (its centripetal acceleration `v²/R` may appear within
//!   one period).
//!
//! A segment's numbers are made when it is queued and again, until it
//! starts, when the next move settles how its end is met: a blend arc
//! (the whole acceleration, as LinuxCNC once its arc blend is made) or a
//! kink crossed at speed under G61 (the kink reserve). Changing a later
//! corner never changes what the executing segment may do.

use super::geom::AxisFactors;
use crate::kins::NUM_AXES;

/// Share of each axis's acceleration a kink may use (LinuxCNC's
/// ARC_BLEND_KINK_RATIO default).
pub const KINK_RESERVE: f64 = 0.1;
/// Share of each axis's jerk kept for the steps at corners and where a
/// turn begins or ends (S-curve planner).
pub const JERK_RESERVE: f64 = 0.5;
/// The largest share of an axis's acceleration a turn's centripetal
/// acceleration may take: `√(1 − 0.5²)`, LinuxCNC's blend-arc ratio, so a
/// turn at full speed keeps half the acceleration along the path.
pub const NORMAL_SHARE: f64 = 0.866_025_403_784_438_6;
/// Share of the tangential acceleration a segment that may be blended
/// uses ([`Joins::Blend`]): LinuxCNC's planner halves it there.
pub const BLEND_SHARE: f64 = 0.5;

/// How one end of a segment meets its neighbour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum End {
    /// At rest: an exact stop, a move that cannot join its neighbour, an
    /// exact-path (G61) end until the next move is found to meet it at
    /// speed.
    Stop,
    /// Tangent to a blend arc.
    Tangent,
    /// Crossed at speed at a kink (G61).
    Kink,
    /// May be blended (G64): not yet met by a next move, or crossed at a
    /// kink (where LinuxCNC falls back to a parabolic blend).
    Open,
}

/// How a segment meets its neighbours, which sets the share of the axes'
/// limits it may use (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Joins {
    /// Both ends at rest (exact stops, G61.1, a lone G61 move): the whole
    /// acceleration and jerk.
    Stop,
    /// Entered or left at speed, but tangentially (a blend arc, a line
    /// blended into arcs at both ends): the whole acceleration, the jerk
    /// reserve (S-curve).
    Tangent,
    /// An end is crossed at speed at a kink (G61): the kink and jerk
    /// reserves.
    Kink,
    /// An end may be blended (G64): the kink and jerk reserves, and
    /// [`BLEND_SHARE`] of the tangential acceleration.
    Blend,
}

impl Joins {
    /// The rule, written once: what a segment whose ends meet their
    /// neighbours as `start` and `end` may use. As LinuxCNC's planner,
    /// half the tangential acceleration wherever an end may be blended
    /// (the last queued G64 move, a move after one), the whole once both
    /// corners are settled as tangent blend arcs or stops.
    pub(crate) fn of(start: End, end: End) -> Joins {
        let either = |e: End| start == e || end == e;
        if either(End::Open) {
            Joins::Blend
        } else if either(End::Kink) {
            Joins::Kink
        } else if either(End::Tangent) {
            Joins::Tangent
        } else {
            Joins::Stop
        }
    }

    /// A kink may be crossed at speed at an end.
    fn kinks(self) -> bool {
        matches!(self, Joins::Kink | Joins::Blend)
    }

    /// An end may be crossed at speed.
    fn at_speed(self) -> bool {
        self != Joins::Stop
    }
}

/// The kinematic limits of the nine world axes, as the planner uses them
/// (the smaller of each axis's own limits and those of the joints it
/// moves). A jerk of 0 means "no jerk limit".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLimits {
    /// Velocity limits.
    pub vel: [f64; NUM_AXES],
    /// Acceleration limits.
    pub acc: [f64; NUM_AXES],
    /// Jerk limits (0: none).
    pub jerk: [f64; NUM_AXES],
    /// The move's own cap on its path speed (SET_LINE's `ini_maxvel`;
    /// infinite: none).
    pub path_vel: f64,
    /// The move's own cap on its path acceleration (SET_LINE's `acc`;
    /// infinite: none).
    pub path_acc: f64,
}

impl Default for AxisLimits {
    fn default() -> Self {
        AxisLimits {
            vel: [1.0; NUM_AXES],
            acc: [1.0; NUM_AXES],
            jerk: [0.0; NUM_AXES],
            path_vel: f64::INFINITY,
            path_acc: f64::INFINITY,
        }
    }
}

/// Machine-wide limits of coordinated motion (`[TRAJ]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrajLimits {
    /// MAX_LINEAR_VELOCITY: tool-tip speed of any move that is not purely
    /// rotary.
    pub max_vel: f64,
    /// MAX_LINEAR_ACCELERATION: tangential acceleration of any move.
    pub max_acc: f64,
    /// MAX_LINEAR_JERK: tangential jerk of any move (S-curve planner).
    pub max_jerk: f64,
}

impl Default for TrajLimits {
    fn default() -> Self {
        TrajLimits {
            max_vel: 1e99,
            max_acc: 1e99,
            max_jerk: 1e9,
        }
    }
}

/// What a segment may do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Budget {
    /// Speed cap along the path (hard: feed override cannot pass it).
    pub vmax: f64,
    /// Tangential acceleration limit.
    pub acc: f64,
    /// Tangential jerk limit (S-curve planner; infinite for trapezoids).
    pub jerk: f64,
}

/// How the planner shapes velocity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlannerType {
    /// Trapezoidal: acceleration jumps (LinuxCNC's PLANNER_TYPE 0).
    Trapezoidal,
    /// Jerk-limited S-curve (PLANNER_TYPE 1).
    SCurve,
}

/// The largest `a ≥ 0` with `bound(a) ≤ limit`, `bound` increasing, by
/// bisection (`hi` must satisfy `bound(hi) ≥ limit`).
fn solve_increasing(bound: impl Fn(f64) -> f64, limit: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, hi);
    if bound(0.0) > limit {
        return 0.0;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if bound(mid) <= limit {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The budget of a segment `len` long with factors `f` that meets its
/// neighbours as `joins` says. `rotary_only`: no XYZ or UVW motion (the traj speed
/// limit does not apply). `None` if the limits leave no speed at all.
#[allow(clippy::too_many_arguments)]
pub(crate) fn budget(
    f: &AxisFactors,
    len: f64,
    lim: &AxisLimits,
    traj: &TrajLimits,
    period: f64,
    joins: Joins,
    planner: PlannerType,
    rotary_only: bool,
) -> Option<Budget> {
    let scurve = planner == PlannerType::SCurve;
    let jerk_reserve = joins.at_speed() && scurve;
    let jerk_share = if jerk_reserve {
        1.0 - JERK_RESERVE
    } else {
        1.0
    };
    let mut vmax = (len / period).min(lim.path_vel);
    if !rotary_only {
        vmax = vmax.min(traj.max_vel);
    }
    for i in 0..NUM_AXES {
        let k = f.speed(i);
        if k <= 0.0 {
            continue;
        }
        vmax = vmax.min(lim.vel[i] / k);
        if f.rot[i] > 0.0 && f.omega > 0.0 {
            let turning = f.rot[i] * f.omega;
            vmax = vmax.min((NORMAL_SHARE * lim.acc[i] / turning).sqrt());
            if jerk_reserve && lim.jerk[i] > 0.0 {
                // The centripetal acceleration changes within one period
                // where the turn meets a straight move, and the discrete
                // jerk of the turn itself: LinuxCNC's √(J·R·T) bound.
                vmax = vmax.min((JERK_RESERVE * lim.jerk[i] * period / turning).sqrt());
            }
        }
    }
    if !(vmax.is_finite() && vmax > 0.0) {
        return None;
    }
    for _ in 0..40 {
        let acc = path_acc(f, lim, traj, vmax, joins);
        if acc <= 0.0 {
            return None;
        }
        if !scurve {
            return Some(Budget {
                vmax,
                acc,
                jerk: f64::INFINITY,
            });
        }
        let mut jerk = traj.max_jerk;
        for i in 0..NUM_AXES {
            let k = f.speed(i);
            if k <= 0.0 || lim.jerk[i] <= 0.0 {
                continue;
            }
            // The jerk bound is linear in the tangential jerk.
            jerk = jerk.min((jerk_share * lim.jerk[i] - f.jerk(i, vmax, acc, 0.0)) / k);
        }
        // Turns fast enough to eat most of the jerk limit go slower.
        if jerk >= 0.25 * traj.max_jerk.min(min_axis_jerk(f, lim)) && jerk > 0.0 {
            return Some(Budget { vmax, acc, jerk });
        }
        vmax *= 0.8;
    }
    None
}

/// The smallest jerk limit among the axes the segment moves (or infinity).
fn min_axis_jerk(f: &AxisFactors, lim: &AxisLimits) -> f64 {
    let mut j = f64::INFINITY;
    for i in 0..NUM_AXES {
        if f.speed(i) > 0.0 && lim.jerk[i] > 0.0 {
            j = j.min(lim.jerk[i] / f.speed(i));
        }
    }
    j
}

/// The tangential acceleration a segment meeting its neighbours as
/// `joins` says may use at speed `vmax`: what every axis allows within
/// its share (less the kink reserve where a kink may be crossed), and
/// for a segment that may be blended no more than [`BLEND_SHARE`] of what
/// the whole limits allow (the `[TRAJ]` limit included).
fn path_acc(f: &AxisFactors, lim: &AxisLimits, traj: &TrajLimits, vmax: f64, joins: Joins) -> f64 {
    let share = if joins.kinks() {
        1.0 - KINK_RESERVE
    } else {
        1.0
    };
    let acc = tangential_acc(f, lim, traj, vmax, share);
    if joins == Joins::Blend {
        acc.min(BLEND_SHARE * tangential_acc(f, lim, traj, vmax, 1.0))
    } else {
        acc
    }
}

/// The tangential acceleration every axis allows at speed `vmax`.
fn tangential_acc(
    f: &AxisFactors,
    lim: &AxisLimits,
    traj: &TrajLimits,
    vmax: f64,
    share: f64,
) -> f64 {
    // The machine's limit and the move's own (its SET_LINE acc), which
    // the blend share then halves as LinuxCNC halves a move's maxaccel.
    let mut acc = traj.max_acc.min(lim.path_acc);
    for i in 0..NUM_AXES {
        let k = f.speed(i);
        if k <= 0.0 {
            continue;
        }
        let limit = share * lim.acc[i];
        let hi = limit / k * 2.0 + 1.0;
        acc = acc.min(solve_increasing(|a| f.accel(i, vmax, a), limit, hi));
    }
    acc
}

/// The two sides of a corner: the axes' travel per unit of path
/// (`d1`, the path's derivative) and its rate of change (`d2`, the
/// curvature part) just before and just after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Corner {
    pub d1_before: [f64; NUM_AXES],
    pub d1_after: [f64; NUM_AXES],
    pub d2_before: [f64; NUM_AXES],
    pub d2_after: [f64; NUM_AXES],
}

/// The speed at which a corner may be crossed. Crossing it at speed `c`
/// changes axis `i`'s velocity by `c·|Δd1_i|` within one period, which
/// must fit the acceleration reserve; for the S-curve planner that and
/// the jump of the centripetal acceleration, `c²·|Δd2_i|`, must fit the
/// jerk reserve within one period.
pub(crate) fn corner_cap(c: &Corner, lim: &AxisLimits, period: f64, planner: PlannerType) -> f64 {
    let mut cap = f64::INFINITY;
    for i in 0..NUM_AXES {
        let j1 = (c.d1_after[i] - c.d1_before[i]).abs();
        let j2 = (c.d2_after[i] - c.d2_before[i]).abs();
        if j1 > 1e-15 {
            cap = cap.min(KINK_RESERVE * lim.acc[i] * period / j1);
        }
        if planner == PlannerType::SCurve && lim.jerk[i] > 0.0 {
            // a·c² + b·c ≤ J with a = j2/T, b = j1/T².
            let budget = JERK_RESERVE * lim.jerk[i];
            let a = j2 / period;
            let b = j1 / (period * period);
            let c_max = if a > 1e-15 {
                (-b + (b * b + 4.0 * a * budget).sqrt()) / (2.0 * a)
            } else if b > 1e-15 {
                budget / b
            } else {
                f64::INFINITY
            };
            cap = cap.min(c_max);
        }
    }
    cap
}

#[cfg(test)]
mod tests {
    use super::super::geom::{arc_move, Path};
    use super::*;
    use crate::kins::Pose;

    fn limits(v: f64, a: f64, j: f64) -> AxisLimits {
        AxisLimits {
            vel: [v; NUM_AXES],
            acc: [a; NUM_AXES],
            jerk: [j; NUM_AXES],
            ..AxisLimits::default()
        }
    }

    fn line_budget(lim: &AxisLimits, traj: &TrajLimits, joins: Joins) -> Budget {
        let mut d = [0.0; NUM_AXES];
        d[0] = 3.0;
        d[1] = 4.0;
        let p = Path::Line {
            start: Pose::ZERO,
            delta: d,
        };
        budget(
            &p.factors(5.0),
            5.0,
            lim,
            traj,
            0.001,
            joins,
            PlannerType::Trapezoidal,
            false,
        )
        .unwrap()
    }

    #[test]
    fn a_diagonal_line_is_held_by_its_slowest_axis() {
        let mut lim = limits(10.0, 100.0, 0.0);
        lim.vel[1] = 4.0;
        let traj = TrajLimits::default();
        let b = line_budget(&lim, &traj, Joins::Stop);
        // Y moves 0.8 per unit of path: 4 / 0.8 = 5.
        assert!((b.vmax - 5.0).abs() < 1e-12);
        // X moves 0.6, Y 0.8: Y's 100 limits the path to 125.
        assert!((b.acc - 125.0).abs() < 1e-9);
        // With kinks possible (G61), 10 % is kept back.
        let k = line_budget(&lim, &traj, Joins::Kink);
        assert!((k.acc - 112.5).abs() < 1e-9);
        // A move that may be blended (G64) gets half, as in LinuxCNC.
        let g64 = line_budget(&lim, &traj, Joins::Blend);
        assert!((g64.acc - 62.5).abs() < 1e-9);
        assert_eq!(g64.vmax, b.vmax);
    }

    #[test]
    fn the_blend_share_halves_the_traj_limit_too() {
        let lim = limits(10.0, 100.0, 0.0);
        let traj = TrajLimits {
            max_acc: 40.0,
            ..TrajLimits::default()
        };
        assert!((line_budget(&lim, &traj, Joins::Stop).acc - 40.0).abs() < 1e-9);
        assert!((line_budget(&lim, &traj, Joins::Kink).acc - 40.0).abs() < 1e-9);
        assert!((line_budget(&lim, &traj, Joins::Blend).acc - 20.0).abs() < 1e-9);
    }

    fn circle_budget(joins: Joins) -> (AxisFactors, Budget) {
        let mut start = Pose::ZERO;
        start.0[0] = 2.0;
        let a = arc_move(&start, &start, [0.0; 3], [0.0, 0.0, 1.0], 0).unwrap();
        let p = Path::Arc(a);
        let len = p.length();
        let lim = limits(100.0, 50.0, 0.0);
        let f = p.factors(len);
        let b = budget(
            &f,
            len,
            &lim,
            &TrajLimits::default(),
            0.001,
            joins,
            PlannerType::Trapezoidal,
            false,
        )
        .unwrap();
        (f, b)
    }

    #[test]
    fn a_circle_keeps_its_centripetal_acceleration_within_the_share() {
        for joins in [Joins::Stop, Joins::Tangent] {
            let (f, b) = circle_budget(joins);
            // LinuxCNC's 0.866 of the limit for the turn.
            assert!((b.vmax * b.vmax / 2.0 - NORMAL_SHARE * 50.0).abs() < 1e-9);
            // At that speed the worst axis acceleration is exactly the limit:
            // half of it is left along the path.
            assert!((f.accel(0, b.vmax, b.acc) - 50.0).abs() < 1e-6);
            assert!((b.acc - 25.0).abs() < 1e-6, "{}", b.acc);
        }
        // The turn is as fast with the kink reserve kept, and what is left
        // of 90 % along the path, no more than half of the 25 under G64.
        let (f, k) = circle_budget(Joins::Kink);
        assert!((k.vmax * k.vmax / 2.0 - NORMAL_SHARE * 50.0).abs() < 1e-9);
        assert!((f.accel(0, k.vmax, k.acc) - 45.0).abs() < 1e-6);
        let (_, g64) = circle_budget(Joins::Blend);
        assert_eq!(g64.vmax, k.vmax);
        assert!((g64.acc - k.acc.min(12.5)).abs() < 1e-9);
        assert!(g64.acc > 12.0, "{}", g64.acc);
    }

    #[test]
    fn corner_caps_shrink_with_the_jumps_and_ignore_untouched_axes() {
        let lim = limits(10.0, 100.0, 1000.0);
        let mut a = [0.0; NUM_AXES];
        let mut b = [0.0; NUM_AXES];
        a[0] = 1.0;
        b[0] = 0.999;
        b[1] = 0.04;
        let z = [0.0; NUM_AXES];
        let kink = Corner {
            d1_before: a,
            d1_after: b,
            d2_before: z,
            d2_after: z,
        };
        let c = corner_cap(&kink, &lim, 0.001, PlannerType::Trapezoidal);
        assert!((c - 0.1 * 100.0 * 0.001 / 0.04).abs() < 1e-12);
        let s = corner_cap(&kink, &lim, 0.001, PlannerType::SCurve);
        assert!((s - 0.5 * 1000.0 * 1e-6 / 0.04).abs() < 1e-12);
        let straight = Corner {
            d1_before: a,
            d1_after: a,
            d2_before: z,
            d2_after: z,
        };
        assert_eq!(
            corner_cap(&straight, &lim, 0.001, PlannerType::SCurve),
            f64::INFINITY
        );
        // Into a circle of radius 2 along X: centripetal 1/2 per speed²
        // on Y; the S-curve planner keeps c²/2 within 500·T.
        let mut d2 = [0.0; NUM_AXES];
        d2[1] = 0.5;
        let into_arc = Corner {
            d1_before: a,
            d1_after: a,
            d2_before: z,
            d2_after: d2,
        };
        assert_eq!(
            corner_cap(&into_arc, &lim, 0.001, PlannerType::Trapezoidal),
            f64::INFINITY
        );
        let c = corner_cap(&into_arc, &lim, 0.001, PlannerType::SCurve);
        assert!((c * c * 0.5 - 0.5).abs() < 1e-9, "{c}");
    }
}
