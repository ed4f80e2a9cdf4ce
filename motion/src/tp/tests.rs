//! Planner tests on their own: the per-period positions are differenced
//! into per-axis velocity, acceleration and jerk and checked against the
//! limits; paths against the programmed geometry.

use super::*;
use crate::command::{LineKind, TermCond};
use crate::kins::NUM_AXES;

mod budget_rule;

const T: f64 = 0.001;

fn xyz(x: f64, y: f64, z: f64) -> Pose {
    let mut p = Pose::ZERO;
    p.0[0] = x;
    p.0[1] = y;
    p.0[2] = z;
    p
}

fn limits(v: f64, a: f64, j: f64) -> AxisLimits {
    AxisLimits {
        vel: [v; NUM_AXES],
        acc: [a; NUM_AXES],
        jerk: [j; NUM_AXES],
        ..AxisLimits::default()
    }
}

const ENABLES: u8 = FS_ENABLED | FH_ENABLED;

/// Runs until done; returns the poses, one per period.
fn run(tp: &mut Planner, scales: &ScaleInputs, limit: usize) -> Vec<Pose> {
    let mut out = Vec::new();
    for _ in 0..limit {
        out.push(tp.run(scales));
        if tp.is_done() {
            return out;
        }
    }
    panic!("not done after {limit} periods");
}

/// The largest per-axis |v|, |a|, |j| of a sampled motion.
fn extremes(p: &[Pose]) -> ([f64; NUM_AXES], [f64; NUM_AXES], [f64; NUM_AXES]) {
    let mut v = [0.0f64; NUM_AXES];
    let mut a = [0.0f64; NUM_AXES];
    let mut j = [0.0f64; NUM_AXES];
    for i in 0..NUM_AXES {
        let vs: Vec<f64> = p.windows(2).map(|w| (w[1].0[i] - w[0].0[i]) / T).collect();
        let acs: Vec<f64> = vs.windows(2).map(|w| (w[1] - w[0]) / T).collect();
        let js: Vec<f64> = acs.windows(2).map(|w| (w[1] - w[0]) / T).collect();
        v[i] = vs.iter().fold(0.0, |m, x| m.max(x.abs()));
        a[i] = acs.iter().fold(0.0, |m, x| m.max(x.abs()));
        j[i] = js.iter().fold(0.0, |m, x| m.max(x.abs()));
    }
    (v, a, j)
}

fn assert_within(p: &[Pose], lim: &AxisLimits, jerk: bool) {
    let (v, a, j) = extremes(p);
    for i in 0..NUM_AXES {
        assert!(v[i] <= lim.vel[i] * (1.0 + 1e-9), "axis {i} vel {}", v[i]);
        assert!(a[i] <= lim.acc[i] * (1.0 + 1e-6), "axis {i} acc {}", a[i]);
        if jerk {
            assert!(j[i] <= lim.jerk[i] * (1.0 + 1e-6), "axis {i} jerk {}", j[i]);
        }
    }
}

#[test]
fn a_lone_line_uses_the_full_acceleration_and_ends_exactly() {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Stop, 0.0);
    let lim = limits(10.0, 100.0, 0.0);
    tp.add_line(xyz(1.0, 0.0, 0.0), LineKind::Feed, 5.0, 7, ENABLES, &lim)
        .unwrap();
    assert_eq!(tp.status().depth, 1);
    let mut p = vec![tp.pos()];
    p.extend(run(&mut tp, &ScaleInputs::default(), 10_000));
    assert_eq!(p.last().unwrap().0[0], 1.0, "exactly on the end");
    assert_within(&p, &lim, false);
    let (v, a, _) = extremes(&p);
    assert!((v[0] - 5.0).abs() < 1e-9, "cruises at the feed");
    assert!((a[0] - 100.0).abs() < 1e-6, "full acceleration: {}", a[0]);
    assert_eq!(tp.status().exec_id, 7);
}

#[test]
fn a_right_angle_under_g64_is_blended_within_the_tolerance() {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.05);
    let lim = limits(20.0, 200.0, 0.0);
    tp.add_line(xyz(10.0, 0.0, 0.0), LineKind::Feed, 10.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(10.0, 10.0, 0.0), LineKind::Feed, 10.0, 2, ENABLES, &lim)
        .unwrap();
    assert_eq!(tp.status().depth, 3, "line, blend arc, line");
    let p = run(&mut tp, &ScaleInputs::default(), 100_000);
    assert_within(&p, &lim, false);
    let end = p.last().unwrap();
    assert_eq!((end.0[0], end.0[1]), (10.0, 10.0));
    // Never further from the corner path than the tolerance, and the
    // corner is rounded (no stop there).
    let mut closest = f64::INFINITY;
    for q in &p {
        let d_first = q.0[1].abs().max((q.0[0] - 10.0).max(0.0));
        let d_second = (q.0[0] - 10.0).abs().max((-q.0[1]).max(0.0));
        let dev = d_first.min(d_second);
        assert!(dev <= 0.05 + 1e-9, "deviation {dev} at {q:?}");
        closest = closest.min(((q.0[0] - 10.0).powi(2) + q.0[1].powi(2)).sqrt());
    }
    assert!(closest > 0.05 - 1e-6, "the corner itself is not reached");
}

#[test]
fn exact_stop_stops_at_the_corner() {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Stop, 0.0);
    let lim = limits(20.0, 200.0, 0.0);
    tp.add_line(xyz(1.0, 0.0, 0.0), LineKind::Feed, 10.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(1.0, 1.0, 0.0), LineKind::Feed, 10.0, 2, ENABLES, &lim)
        .unwrap();
    let p = run(&mut tp, &ScaleInputs::default(), 100_000);
    assert!(
        p.iter().any(|q| q.0[0] == 1.0 && q.0[1] == 0.0),
        "lands on the corner"
    );
    assert_within(&p, &lim, false);
}

#[test]
fn a_full_circle_keeps_its_centripetal_acceleration() {
    let mut tp = Planner::new(T);
    let lim = limits(50.0, 100.0, 0.0);
    tp.set_pos(xyz(5.0, 0.0, 0.0));
    tp.add_arc(
        xyz(5.0, 0.0, 0.0),
        [0.0; 3],
        [0.0, 0.0, 1.0],
        0,
        40.0,
        3,
        ENABLES,
        &lim,
    )
    .unwrap();
    let p = run(&mut tp, &ScaleInputs::default(), 100_000);
    assert_within(&p, &lim, false);
    for q in &p {
        let r = (q.0[0] * q.0[0] + q.0[1] * q.0[1]).sqrt();
        assert!((r - 5.0).abs() < 1e-9);
    }
    let end = p.last().unwrap();
    assert!((end.0[0] - 5.0).abs() < 1e-12 && end.0[1].abs() < 1e-12);
}

#[test]
fn pause_stops_along_the_path_and_resume_finishes_exactly() {
    let mut tp = Planner::new(T);
    let lim = limits(10.0, 100.0, 0.0);
    tp.add_line(xyz(5.0, 5.0, 0.0), LineKind::Feed, 8.0, 1, ENABLES, &lim)
        .unwrap();
    let s = ScaleInputs::default();
    let mut p = vec![tp.pos()];
    for _ in 0..300 {
        p.push(tp.run(&s));
    }
    tp.pause();
    for _ in 0..300 {
        p.push(tp.run(&s));
    }
    assert_eq!(tp.status().current_vel, 0.0);
    assert!(!tp.is_done());
    let held = tp.pos();
    p.push(tp.run(&s));
    assert_eq!(tp.pos(), held, "paused at rest");
    tp.resume();
    p.extend(run(&mut tp, &s, 100_000));
    assert_within(&p, &lim, false);
    assert_eq!(tp.pos(), xyz(5.0, 5.0, 0.0));
}

#[test]
fn abort_stops_along_the_path_and_empties_the_queue() {
    let mut tp = Planner::new(T);
    let lim = limits(10.0, 100.0, 0.0);
    tp.add_line(xyz(5.0, 0.0, 0.0), LineKind::Feed, 8.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(5.0, 5.0, 0.0), LineKind::Feed, 8.0, 2, ENABLES, &lim)
        .unwrap();
    let s = ScaleInputs::default();
    let mut p = vec![tp.pos()];
    for _ in 0..200 {
        p.push(tp.run(&s));
    }
    tp.abort();
    assert_eq!(
        tp.add_line(xyz(0.0, 0.0, 0.0), LineKind::Feed, 1.0, 3, ENABLES, &lim),
        Err(Reject::Aborting)
    );
    p.extend(run(&mut tp, &s, 10_000));
    assert_within(&p, &lim, false);
    assert!(tp.is_done() && !tp.is_aborting());
    let end = tp.pos();
    assert!(
        end.0[1] == 0.0 && end.0[0] < 5.0,
        "stopped on the first line"
    );
    // Queueing works again, from where it stopped.
    tp.add_line(xyz(0.0, 0.0, 0.0), LineKind::Feed, 1.0, 3, ENABLES, &lim)
        .unwrap();
}

#[test]
fn step_runs_one_motion_id_and_pauses() {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.0);
    let lim = limits(10.0, 100.0, 0.0);
    for (k, x) in [1.0, 2.0, 3.0].into_iter().enumerate() {
        tp.add_line(
            xyz(x, x * 0.5, 0.0),
            LineKind::Feed,
            5.0,
            k as i32 + 1,
            ENABLES,
            &lim,
        )
        .unwrap();
    }
    tp.pause();
    let s = ScaleInputs::default();
    tp.run(&s);
    assert_eq!(tp.step(), Ok(()));
    let mut p = vec![tp.pos()];
    for _ in 0..10_000 {
        p.push(tp.run(&s));
        if tp.status().paused && tp.status().current_vel == 0.0 {
            break;
        }
    }
    assert_eq!(tp.pos(), xyz(1.0, 0.5, 0.0), "stopped at the end of id 1");
    assert!(tp.status().paused);
    assert_eq!(tp.step(), Ok(()));
    assert_eq!(tp.step(), Err(Reject::NotPaused), "already stepping");
    tp.resume();
    p.extend(run(&mut tp, &s, 10_000));
    assert_within(&p, &lim, false);
    assert_eq!(tp.pos(), xyz(3.0, 1.5, 0.0));
}

#[test]
fn a_dwell_waits_its_time_at_rest() {
    let mut tp = Planner::new(T);
    let lim = limits(10.0, 100.0, 0.0);
    tp.add_line(xyz(1.0, 0.0, 0.0), LineKind::Feed, 5.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_dwell(0.25, 2).unwrap();
    tp.add_line(xyz(2.0, 0.0, 0.0), LineKind::Feed, 5.0, 3, ENABLES, &lim)
        .unwrap();
    let p = run(&mut tp, &ScaleInputs::default(), 100_000);
    let at_one = p.iter().filter(|q| q.0[0] == 1.0).count();
    assert!(
        (250..=253).contains(&at_one),
        "{at_one} periods at the dwell"
    );
    assert_within(&p, &lim, false);
}

#[test]
fn feed_scale_and_feed_hold_slow_and_stop() {
    let mut tp = Planner::new(T);
    let lim = limits(10.0, 100.0, 0.0);
    tp.add_line(xyz(20.0, 0.0, 0.0), LineKind::Feed, 8.0, 1, ENABLES, &lim)
        .unwrap();
    let mut s = ScaleInputs {
        feed: 0.5,
        ..ScaleInputs::default()
    };
    for _ in 0..500 {
        tp.run(&s);
    }
    assert!((tp.status().current_vel - 4.0).abs() < 1e-9);
    s.feed_hold = true;
    for _ in 0..500 {
        tp.run(&s);
    }
    assert_eq!(tp.status().current_vel, 0.0);
    s.feed_hold = false;
    s.feed = 2.0;
    s.max_feed_override = 1.2;
    for _ in 0..500 {
        tp.run(&s);
    }
    assert!((tp.status().current_vel - 8.0 * 1.2).abs() < 1e-9, "capped");
}

#[test]
fn the_s_curve_planner_keeps_jerk_limits_and_ends_exactly() {
    let mut tp = Planner::new(T);
    tp.set_planner_type(PlannerType::SCurve);
    tp.set_term_cond(TermCond::Blend, 0.02);
    let lim = limits(20.0, 200.0, 4000.0);
    tp.add_line(xyz(5.0, 0.0, 0.0), LineKind::Feed, 10.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(5.0, 5.0, 0.0), LineKind::Feed, 10.0, 2, ENABLES, &lim)
        .unwrap();
    let p = run(&mut tp, &ScaleInputs::default(), 100_000);
    assert_within(&p, &lim, true);
    assert_eq!(tp.pos(), xyz(5.0, 5.0, 0.0));
}

/// The closest the path comes to the corner at (10, 0), and the slowest
/// path speed between X 5 and Y 5 (around the corner).
fn corner_approach(p: &[Pose]) -> (f64, f64) {
    let closest = p
        .iter()
        .map(|q| ((q.0[0] - 10.0).powi(2) + q.0[1].powi(2)).sqrt())
        .fold(f64::INFINITY, f64::min);
    let slowest = p
        .windows(2)
        .filter(|w| w[0].0[0] > 5.0 && w[1].0[1] < 5.0)
        .map(|w| ((w[1].0[0] - w[0].0[0]).hypot(w[1].0[1] - w[0].0[1])) / T)
        .fold(f64::INFINITY, f64::min);
    (closest, slowest)
}

fn right_angle(feed: f64, scales: &ScaleInputs) -> Vec<Pose> {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.1);
    let lim = limits(20.0, 100.0, 0.0);
    // One period first, so the planner has seen the override.
    tp.run(scales);
    tp.add_line(xyz(10.0, 0.0, 0.0), LineKind::Feed, feed, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(10.0, 10.0, 0.0), LineKind::Feed, feed, 2, ENABLES, &lim)
        .unwrap();
    let p = run(&mut tp, scales, 100_000);
    assert_within(&p, &lim, false);
    p
}

#[test]
fn a_slow_corner_gets_the_smallest_blend_arc_that_keeps_the_feed() {
    // At 1 unit/s the tolerance (0.1: an arc 0.24 from the corner) is far
    // more than the speed needs: as LinuxCNC, the arc is only as large as
    // the feed needs, so the path stays near the corner, at full feed.
    let (closest, slowest) = corner_approach(&right_angle(1.0, &ScaleInputs::default()));
    assert!(closest < 0.01, "the arc keeps near the corner: {closest}");
    assert!(closest > 0.0, "the corner is still rounded");
    assert!(
        slowest > 0.999,
        "the corner is crossed at the feed: {slowest}"
    );
    // Room for a feed override of 2: a larger arc, crossed at twice the
    // feed when the override asks for it.
    let mut scales = ScaleInputs {
        max_feed_override: 2.0,
        ..ScaleInputs::default()
    };
    scales.feed = 2.0;
    let (wider, fast) = corner_approach(&right_angle(1.0, &scales));
    assert!(wider > 3.0 * closest, "{wider} vs {closest}");
    assert!(fast > 1.999, "crossed at twice the feed: {fast}");
    // A fast feed still uses the whole tolerance (the arc midpoint is the
    // tolerance from the corner).
    let (tol_limited, _) = corner_approach(&right_angle(15.0, &ScaleInputs::default()));
    assert!((tol_limited - 0.1).abs() < 1e-3, "{tol_limited}");
}

#[test]
fn dtg_is_the_executing_segments_end_minus_the_position() {
    let mut tp = Planner::new(T);
    let lim = limits(10.0, 100.0, 0.0);
    assert_eq!(tp.status().dtg, Pose::ZERO, "nothing queued");
    tp.add_line(xyz(5.0, -3.0, 0.0), LineKind::Feed, 8.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_dwell(0.5, 2).unwrap();
    let s = ScaleInputs::default();
    for _ in 0..200 {
        tp.run(&s);
    }
    let (pos, dtg) = (tp.pos(), tp.status().dtg);
    assert!(pos.0[0] > 0.0 && pos.0[0] < 5.0, "still on the line");
    for (a, goal) in [(0, 5.0), (1, -3.0), (2, 0.0)] {
        assert!(
            (dtg.0[a] - (goal - pos.0[a])).abs() < 1e-12,
            "axis {a}: {dtg:?}"
        );
    }
    // The line ends, the dwell runs: no distance to go.
    while tp.status().exec_id != 2 {
        tp.run(&s);
    }
    assert_eq!(tp.status().dtg, Pose::ZERO);
}
