//! Property tests of the coordinated planner: random paths (lines, arcs
//! and helices, tiny segments, reversals), random axis limits, random
//! termination conditions and feeds, both planners; PAUSE, RESUME, STEP,
//! feed override changes and ABORT at random times.
//!
//! Every period's output pose is differenced into per-axis velocity,
//! acceleration and (S-curve) jerk, which must stay within the axis
//! limits; every pose must lie on the programmed path or, inside a blend,
//! within the blend tolerance of it; an uninterrupted run ends exactly on
//! the last programmed point, an aborted one at rest on the path with an
//! empty queue.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use motion::command::{LineKind, TermCond};
use motion::kins::{Pose, NUM_AXES};
use motion::tp::{AxisLimits, Planner, PlannerType, ScaleInputs};
use proptest::prelude::*;

const T: f64 = 0.001;
const ENABLES: u8 = motion::sizes::FS_ENABLED | motion::sizes::FH_ENABLED;

/// One programmed move.
#[derive(Debug, Clone)]
enum Move {
    Line {
        to: [f64; 3],
        feed: Option<f64>,
    },
    /// An arc about a centre offset from the start, in the XY plane, with a
    /// climb in Z; `turns` as SET_CIRCLE encodes it.
    Arc {
        to: [f64; 3],
        center: [f64; 3],
        turns: i32,
        feed: f64,
    },
}

#[derive(Debug, Clone)]
struct Program {
    start: [f64; 3],
    moves: Vec<(Move, TermCond, f64)>,
    limits: AxisLimits,
    scurve: bool,
}

fn pose(p: [f64; 3]) -> Pose {
    let mut q = Pose::ZERO;
    q.0[..3].copy_from_slice(&p);
    q
}

fn arb_limits() -> impl Strategy<Value = AxisLimits> {
    (
        prop::array::uniform3(5.0f64..60.0),
        prop::array::uniform3(50.0f64..2000.0),
        prop::array::uniform3(2_000.0f64..200_000.0),
    )
        .prop_map(|(v, a, j)| {
            let mut l = AxisLimits {
                vel: [10.0; NUM_AXES],
                acc: [100.0; NUM_AXES],
                jerk: [0.0; NUM_AXES],
                ..AxisLimits::default()
            };
            l.vel[..3].copy_from_slice(&v);
            l.acc[..3].copy_from_slice(&a);
            l.jerk[..3].copy_from_slice(&j);
            l
        })
}

fn arb_term() -> impl Strategy<Value = (TermCond, f64)> {
    prop_oneof![
        Just((TermCond::Stop, 0.0)),
        Just((TermCond::ExactPath, 0.0)),
        (0.0f64..0.5).prop_map(|t| (TermCond::Blend, t)),
    ]
}

/// A move relative to `from`, chosen among long lines, tiny lines,
/// reversals and arcs.
fn arb_move() -> impl Strategy<Value = (u8, [f64; 3], f64, f64, bool)> {
    (
        0u8..5,
        prop::array::uniform3(-20.0f64..20.0),
        2.0f64..80.0,
        0.0001f64..0.05,
        any::<bool>(),
    )
}

/// A raw random move and its termination condition.
type RawMove = ((u8, [f64; 3], f64, f64, bool), (TermCond, f64));

fn build(start: [f64; 3], raw: Vec<RawMove>) -> Vec<(Move, TermCond, f64)> {
    let mut here = start;
    let mut prev_dir = [1.0, 0.0, 0.0];
    let mut out = Vec::new();
    for ((kind, d, feed, tiny, flag), (term, tol)) in raw {
        let mv = match kind {
            // A long line.
            0 => Move::Line {
                to: [here[0] + d[0], here[1] + d[1], here[2] + d[2] * 0.2],
                feed: (!flag).then_some(feed),
            },
            // A tiny line, nearly along the last direction.
            1 => Move::Line {
                to: [
                    here[0] + prev_dir[0] * tiny + d[0] * 1e-4,
                    here[1] + prev_dir[1] * tiny + d[1] * 1e-4,
                    here[2] + prev_dir[2] * tiny,
                ],
                feed: Some(feed),
            },
            // A reversal.
            2 => Move::Line {
                to: [
                    here[0] - prev_dir[0] * d[0].abs().max(0.1),
                    here[1] - prev_dir[1] * d[0].abs().max(0.1),
                    here[2] - prev_dir[2] * d[0].abs().max(0.1),
                ],
                feed: Some(feed),
            },
            // An arc or helix.
            _ => {
                let r = 0.5 + d[0].abs() * 0.4;
                let center = [here[0] + r, here[1], here[2]];
                let ang = d[1] * 0.3;
                let to = [
                    center[0] - r * ang.cos(),
                    center[1] - r * ang.sin(),
                    here[2] + d[2] * 0.1,
                ];
                Move::Arc {
                    to,
                    center,
                    turns: if flag { 0 } else { -1 },
                    feed,
                }
            }
        };
        let to = match &mv {
            Move::Line { to, .. } | Move::Arc { to, .. } => *to,
        };
        let dd = [to[0] - here[0], to[1] - here[1], to[2] - here[2]];
        let n = (dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2]).sqrt();
        if n > 1e-9 {
            prev_dir = [dd[0] / n, dd[1] / n, dd[2] / n];
        }
        here = to;
        out.push((mv, term, tol));
    }
    out
}

fn arb_program() -> impl Strategy<Value = Program> {
    (
        prop::array::uniform3(-10.0f64..10.0),
        prop::collection::vec((arb_move(), arb_term()), 1..10),
        arb_limits(),
        any::<bool>(),
    )
        .prop_map(|(start, raw, limits, scurve)| Program {
            start,
            moves: build(start, raw),
            limits,
            scurve,
        })
}

/// Queues the program; returns the largest blend tolerance in effect (0:
/// none) and the programmed end.
fn queue(tp: &mut Planner, p: &Program) -> (f64, [f64; 3]) {
    start(tp, p);
    let mut tol_max: f64 = 0.0;
    let mut end = p.start;
    for k in 0..p.moves.len() {
        queue_move(tp, p, k, &mut tol_max, &mut end);
    }
    (tol_max, end)
}

/// Puts the planner at the program's start, with its planner type.
fn start(tp: &mut Planner, p: &Program) {
    tp.set_pos(pose(p.start));
    if p.scurve {
        tp.set_planner_type(PlannerType::SCurve);
    }
}

/// Queues move `k` of the program; keeps the largest blend tolerance in
/// effect and the programmed end up to date.
fn queue_move(tp: &mut Planner, p: &Program, k: usize, tol_max: &mut f64, end: &mut [f64; 3]) {
    let (mv, term, tol) = &p.moves[k];
    tp.set_term_cond(*term, *tol);
    if *term == TermCond::Blend {
        // Tolerance 0 blends within a quarter of the shorter move.
        *tol_max = tol_max.max(if *tol > 0.0 { *tol } else { 10.0 });
    }
    let id = k as i32 + 1;
    match mv {
        Move::Line { to, feed } => {
            let (kind, vel) = match feed {
                Some(f) => (LineKind::Feed, *f),
                None => (LineKind::Traverse, 0.0),
            };
            tp.add_line(pose(*to), kind, vel, id, ENABLES, &p.limits)
                .unwrap();
            *end = *to;
        }
        Move::Arc {
            to,
            center,
            turns,
            feed,
        } => {
            if tp
                .add_arc(
                    pose(*to),
                    *center,
                    [0.0, 0.0, 1.0],
                    *turns,
                    *feed,
                    id,
                    ENABLES,
                    &p.limits,
                )
                .is_ok()
            {
                *end = *to;
            }
        }
    }
}

/// Checks the sampled poses against the limits.
fn check_limits(samples: &[Pose], lim: &AxisLimits, jerk: bool) -> Result<(), TestCaseError> {
    for i in 0..3 {
        let v: Vec<f64> = samples
            .windows(2)
            .map(|w| (w[1].0[i] - w[0].0[i]) / T)
            .collect();
        let a: Vec<f64> = v.windows(2).map(|w| (w[1] - w[0]) / T).collect();
        for (k, x) in v.iter().enumerate() {
            prop_assert!(
                x.abs() <= lim.vel[i] * (1.0 + 1e-9) + 1e-9,
                "axis {i} velocity {x} > {} at sample {k}",
                lim.vel[i]
            );
        }
        for (k, x) in a.iter().enumerate() {
            prop_assert!(
                x.abs() <= lim.acc[i] * (1.0 + 1e-6) + 1e-6,
                "axis {i} acceleration {x} > {} at sample {k}",
                lim.acc[i]
            );
        }
        if jerk {
            for (k, w) in a.windows(2).enumerate() {
                let j = (w[1] - w[0]) / T;
                prop_assert!(
                    j.abs() <= lim.jerk[i] * (1.0 + 1e-6) + 1e-3,
                    "axis {i} jerk {j} > {} at sample {k}",
                    lim.jerk[i]
                );
            }
        }
    }
    Ok(())
}

/// The programmed moves as start/end points with their arc centres, for
/// distance checks.
struct Geometry {
    /// Start, end, and for arcs the centre and whether counter-clockwise.
    moves: Vec<GeoMove>,
}

type GeoMove = ([f64; 3], [f64; 3], Option<([f64; 3], bool)>);

fn geometry(p: &Program) -> Geometry {
    let mut here = p.start;
    let mut moves = Vec::new();
    for (mv, _, _) in &p.moves {
        match mv {
            Move::Line { to, .. } => {
                moves.push((here, *to, None));
                here = *to;
            }
            Move::Arc {
                to, center, turns, ..
            } => {
                moves.push((here, *to, Some((*center, *turns >= 0))));
                here = *to;
            }
        }
    }
    Geometry { moves }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Distance from `q` to programmed move `k`.
fn move_distance(q: [f64; 3], g: &Geometry, k: usize) -> f64 {
    let Some(&(a, b, arc)) = g.moves.get(k) else {
        return f64::INFINITY;
    };
    match arc {
        None => {
            let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            let t = if l2 > 0.0 {
                (((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1] + (q[2] - a[2]) * ab[2]) / l2)
                    .clamp(0.0, 1.0)
            } else {
                0.0
            };
            dist(q, [a[0] + ab[0] * t, a[1] + ab[1] * t, a[2] + ab[2] * t])
        }
        Some((c, ccw)) => {
            // Angle, radius and height all change linearly along the arc.
            let r0 = ((a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2)).sqrt();
            let r1 = ((b[0] - c[0]).powi(2) + (b[1] - c[1]).powi(2)).sqrt();
            let a0 = (a[1] - c[1]).atan2(a[0] - c[0]);
            let mut a1 = (b[1] - c[1]).atan2(b[0] - c[0]);
            if ccw {
                while a1 <= a0 + 1e-12 {
                    a1 += std::f64::consts::TAU;
                }
            } else {
                while a1 >= a0 - 1e-12 {
                    a1 -= std::f64::consts::TAU;
                }
            }
            let at = |f: f64| {
                let ang = a0 + (a1 - a0) * f;
                let r = r0 + (r1 - r0) * f;
                [
                    c[0] + r * ang.cos(),
                    c[1] + r * ang.sin(),
                    a[2] + (b[2] - a[2]) * f,
                ]
            };
            // The nearest angle, then a local search around it.
            let aq = (q[1] - c[1]).atan2(q[0] - c[0]);
            let mut best = dist(q, at(0.0)).min(dist(q, at(1.0)));
            for turn in -2..=2 {
                let f = (aq + turn as f64 * std::f64::consts::TAU - a0) / (a1 - a0);
                if (0.0..=1.0).contains(&f) {
                    for k in -20..=20 {
                        let g = (f + k as f64 * 1e-5).clamp(0.0, 1.0);
                        best = best.min(dist(q, at(g)));
                    }
                }
            }
            best
        }
    }
}

fn xyz(p: &Pose) -> [f64; 3] {
    [p.0[0], p.0[1], p.0[2]]
}

/// Each sample (with the motion id executing then) lies on the move of
/// that id, or the next one, or within the blend tolerance of them.
fn check_on_path(samples: &[(Pose, i32)], p: &Program, tol: f64) -> Result<(), TestCaseError> {
    let g = geometry(p);
    let slack = 1e-6;
    for (k, (s, id)) in samples.iter().enumerate() {
        let m = (*id).max(1) as usize - 1;
        let d = (m.saturating_sub(1)..=m + 1)
            .map(|i| move_distance(xyz(s), &g, i))
            .fold(f64::INFINITY, f64::min);
        prop_assert!(
            d <= tol + slack,
            "sample {k} at {:?} (id {id}) is {d} from the path (tolerance {tol})",
            xyz(s)
        );
    }
    Ok(())
}

proptest! {
    // Each case runs a whole program; debug builds (cargo test) run fewer.
    #![proptest_config(ProptestConfig {
        cases: if cfg!(debug_assertions) { 24 } else { 256 },
        ..ProptestConfig::default()
    })]

    #[test]
    fn runs_stay_within_limits_and_path_and_end_exactly(p in arb_program()) {
        let mut tp = Planner::new(T);
        let (tol, end) = queue(&mut tp, &p);
        let scales = ScaleInputs::default();
        let mut samples = vec![tp.pos()];
        let mut ids = vec![(tp.pos(), 1)];
        let mut n = 0;
        while !tp.is_done() {
            let q = tp.run(&scales);
            samples.push(q);
            ids.push((q, tp.status().exec_id));
            n += 1;
            prop_assert!(n < 2_000_000, "never finished");
        }
        check_limits(&samples, &p.limits, p.scurve)?;
        let last = samples.last().unwrap();
        prop_assert_eq!(xyz(last), end, "ends exactly on the last point");
        check_on_path(&ids, &p, tol)?;
    }

    #[test]
    fn moves_queued_while_running_keep_the_limits_and_end_exactly(
        p in arb_program(),
        gaps in prop::collection::vec(0usize..400, 10),
    ) {
        // Each move arrives some periods after the one before (MDI):
        // corners are settled, and budgets changed, while a move runs.
        let mut tp = Planner::new(T);
        start(&mut tp, &p);
        let scales = ScaleInputs::default();
        let (mut tol, mut end) = (0.0, p.start);
        let mut samples = vec![tp.pos()];
        let mut ids = vec![(tp.pos(), 1)];
        for (k, gap) in gaps.iter().enumerate().take(p.moves.len()) {
            queue_move(&mut tp, &p, k, &mut tol, &mut end);
            for _ in 0..*gap {
                let q = tp.run(&scales);
                samples.push(q);
                ids.push((q, tp.status().exec_id));
            }
        }
        let mut n = 0;
        while !tp.is_done() {
            let q = tp.run(&scales);
            samples.push(q);
            ids.push((q, tp.status().exec_id));
            n += 1;
            prop_assert!(n < 2_000_000, "never finished");
        }
        check_limits(&samples, &p.limits, p.scurve)?;
        prop_assert_eq!(xyz(samples.last().unwrap()), end, "ends exactly on the last point");
        check_on_path(&ids, &p, tol)?;
    }

    #[test]
    fn interruptions_keep_the_limits(
        p in arb_program(),
        events in prop::collection::vec((1usize..3000, 0u8..6, 0.0f64..1.5), 1..8),
    ) {
        let mut tp = Planner::new(T);
        let (tol, _) = queue(&mut tp, &p);
        let mut scales = ScaleInputs { max_feed_override: 1.5, ..ScaleInputs::default() };
        let mut samples = vec![tp.pos()];
        let mut ids = vec![(tp.pos(), 1)];
        let mut events = events;
        events.sort_by_key(|e| e.0);
        let mut next = 0;
        let mut aborted = false;
        let mut k = 0usize;
        while !tp.is_done() {
            while next < events.len() && events[next].0 == k {
                let (_, what, x) = events[next];
                match what {
                    0 => tp.pause(),
                    1 => tp.resume(),
                    2 => { tp.abort(); aborted = true; }
                    3 => scales.feed = x,
                    4 => scales.feed_hold = !scales.feed_hold,
                    _ => { let _ = tp.step(); }
                }
                next += 1;
            }
            // Once every event has happened, let it finish.
            if next == events.len() && k > events.last().unwrap().0 {
                if tp.status().paused { tp.resume(); }
                scales.feed_hold = false;
                if scales.feed < 0.05 { scales.feed = 1.0; }
            }
            let q = tp.run(&scales);
            samples.push(q);
            ids.push((q, tp.status().exec_id));
            k += 1;
            prop_assert!(k < 4_000_000, "never finished");
        }
        check_limits(&samples, &p.limits, p.scurve)?;
        check_on_path(&ids, &p, tol)?;
        if aborted {
            prop_assert_eq!(tp.status().depth, 0);
        }
    }
}
