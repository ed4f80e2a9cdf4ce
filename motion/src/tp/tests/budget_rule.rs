//! The acceleration each move gets from the axes' MAX_ACCELERATION, by
//! termination, as LinuxCNC's planner gives it: half along the path for a
//! move that may be blended (G64, the last queued move included), the
//! whole for an exact-path (G61) or exact-stop (G61.1) move, and blend
//! arcs turning at up to 0.866 of it.

use super::super::budget::NORMAL_SHARE;
use super::*;

/// The path acceleration (X only) of every period of a move along X.
fn x_accels(p: &[Pose]) -> Vec<f64> {
    let v: Vec<f64> = p.windows(2).map(|w| (w[1].0[0] - w[0].0[0]) / T).collect();
    v.windows(2).map(|w| (w[1] - w[0]) / T).collect()
}

/// A lone 1-unit move along X at rapid speed 4 with the axes' limits at
/// 100, queued under `term`; its sampled poses from rest to rest.
fn lone_rapid(term: TermCond) -> Vec<Pose> {
    let mut tp = Planner::new(T);
    tp.set_term_cond(term, 0.0);
    let lim = limits(4.0, 100.0, 0.0);
    tp.add_line(
        xyz(1.0, 0.0, 0.0),
        LineKind::Traverse,
        4.0,
        1,
        ENABLES,
        &lim,
    )
    .unwrap();
    let mut p = vec![tp.pos()];
    p.extend(run(&mut tp, &ScaleInputs::default(), 10_000));
    assert_eq!(p.last().unwrap().0[0], 1.0, "exactly on the end");
    assert_within(&p, &lim, false);
    p
}

/// Speeds up at `acc` every period, cruises at 4, slows down at `acc`
/// every period (LinuxCNC's motion/g0 test's reading of a profile).
fn assert_trapezoid_at(p: &[Pose], acc: f64) {
    let a = x_accels(p);
    let up: Vec<f64> = a.iter().copied().take_while(|x| *x > 1e-6).collect();
    let down: Vec<f64> = a.iter().rev().copied().take_while(|x| *x < -1e-6).collect();
    assert!(
        up.len() > 10 && down.len() > 10,
        "{} up, {} down",
        up.len(),
        down.len()
    );
    for x in up.iter().chain(down.iter()) {
        assert!((x.abs() - acc).abs() < 1e-6, "{x} instead of ±{acc}");
    }
    let cruise = &a[up.len()..a.len() - down.len()];
    assert!(cruise.iter().all(|x| x.abs() < 1e-6), "a constant cruise");
    let top = (p[up.len() + 1].0[0] - p[up.len()].0[0]) / T;
    assert!(
        (top - 4.0).abs() < 1e-9,
        "cruises at the rapid speed: {top}"
    );
}

#[test]
fn a_lone_move_under_g64_runs_at_half_the_acceleration() {
    assert_trapezoid_at(&lone_rapid(TermCond::Blend), 50.0);
}

#[test]
fn a_lone_move_under_g61_or_g61_1_runs_at_the_whole_acceleration() {
    assert_trapezoid_at(&lone_rapid(TermCond::ExactPath), 100.0);
    assert_trapezoid_at(&lone_rapid(TermCond::Stop), 100.0);
}

#[test]
fn a_g61_move_crossed_at_speed_keeps_the_kink_reserve() {
    // Two G61 lines meeting at a slight kink, queued before the first
    // starts: the corner is crossed at speed, and the first line gives up
    // the kink reserve it would not have needed alone.
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::ExactPath, 0.0);
    let lim = limits(4.0, 100.0, 0.0);
    tp.add_line(xyz(1.0, 0.0, 0.0), LineKind::Feed, 2.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(2.0, 0.01, 0.0), LineKind::Feed, 2.0, 2, ENABLES, &lim)
        .unwrap();
    let mut p = vec![tp.pos()];
    p.extend(run(&mut tp, &ScaleInputs::default(), 10_000));
    assert_within(&p, &lim, false);
    let a = x_accels(&p);
    assert!((a[0] - 90.0).abs() < 1e-6, "kink reserve kept: {}", a[0]);
    let slowest = p
        .windows(2)
        .filter(|w| w[0].0[0] > 0.9 && w[1].0[0] < 1.1)
        .map(|w| (w[1].0[0] - w[0].0[0]).hypot(w[1].0[1] - w[0].0[1]) / T)
        .fold(f64::INFINITY, f64::min);
    assert!(slowest > 0.5, "the kink is crossed at speed: {slowest}");
    assert_eq!(p.last().unwrap().0[0], 2.0);
}

#[test]
fn a_running_g61_move_is_not_changed_by_the_next_one() {
    // The first line already speeds up at the whole acceleration when the
    // second arrives: it keeps it and stops at the corner instead.
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::ExactPath, 0.0);
    let lim = limits(4.0, 100.0, 0.0);
    tp.add_line(xyz(1.0, 0.0, 0.0), LineKind::Feed, 2.0, 1, ENABLES, &lim)
        .unwrap();
    let scales = ScaleInputs::default();
    let mut p = vec![tp.pos()];
    for _ in 0..5 {
        p.push(tp.run(&scales));
    }
    tp.add_line(xyz(2.0, 0.01, 0.0), LineKind::Feed, 2.0, 2, ENABLES, &lim)
        .unwrap();
    p.extend(run(&mut tp, &scales, 10_000));
    assert_within(&p, &lim, false);
    let a = x_accels(&p);
    assert!((a[0] - 100.0).abs() < 1e-6, "{}", a[0]);
    assert!(p.contains(&xyz(1.0, 0.0, 0.0)), "stops on the corner");
    assert_eq!(p.last().unwrap().0[0], 2.0);
}

/// The path acceleration (Y only) of every period.
fn y_accels(p: &[Pose]) -> Vec<f64> {
    let v: Vec<f64> = p.windows(2).map(|w| (w[1].0[1] - w[0].0[1]) / T).collect();
    v.windows(2).map(|w| (w[1] - w[0]) / T).collect()
}

#[test]
fn a_blended_corner_gives_the_settled_line_the_whole_and_turns_at_0_866() {
    // A right angle under G64 at a feed far above what the tolerance
    // allows through the corner. As in LinuxCNC: the first line, its end
    // settled as a tangent blend arc, speeds up at the whole limit; the
    // last line, which may still be blended, slows down at half; the arc
    // is crossed at the speed whose centripetal acceleration is 0.866 of
    // the limit.
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.01);
    let lim = limits(20.0, 100.0, 0.0);
    tp.add_line(xyz(2.0, 0.0, 0.0), LineKind::Feed, 10.0, 1, ENABLES, &lim)
        .unwrap();
    tp.add_line(xyz(2.0, 2.0, 0.0), LineKind::Feed, 10.0, 2, ENABLES, &lim)
        .unwrap();
    assert_eq!(tp.status().depth, 3, "line, blend arc, line");
    let mut p = vec![tp.pos()];
    p.extend(run(&mut tp, &ScaleInputs::default(), 100_000));
    assert_within(&p, &lim, false);
    let a = x_accels(&p);
    assert!(
        (a[0] - 100.0).abs() < 1e-6,
        "the whole along the first line: {}",
        a[0]
    );
    let ay = y_accels(&p);
    let down: Vec<f64> = ay
        .iter()
        .rev()
        .copied()
        .take_while(|x| *x < -1e-6)
        .collect();
    assert!(down.len() > 10, "{down:?}");
    // The last period or two land the stop exactly: no harder.
    assert!(down.iter().all(|y| *y > -50.0 - 1e-6), "{down:?}");
    for y in &down[2..] {
        assert!((y + 50.0).abs() < 1e-6, "half along the last line: {y}");
    }
    // The arc: 90°, midpoint 0.01 from the corner, radius 0.01/(√2 − 1).
    let r = 0.01 / (2f64.sqrt() - 1.0);
    let v_arc = (NORMAL_SHARE * 100.0 * r).sqrt();
    let slowest = p
        .windows(2)
        .filter(|w| w[0].0[0] > 1.9 && w[1].0[1] < 0.1)
        .map(|w| (w[1].0[0] - w[0].0[0]).hypot(w[1].0[1] - w[0].0[1]) / T)
        .fold(f64::INFINITY, f64::min);
    assert!(
        slowest > 0.97 * v_arc && slowest < 1.01 * v_arc,
        "crossed at {slowest}, arc speed {v_arc}"
    );
}

#[test]
fn a_line_blended_at_both_ends_gets_the_whole_acceleration() {
    // A zigzag of G64 lines along X: each middle line meets blend arcs at
    // both ends and speeds up at the whole limit; the lines keep it once
    // the next corner is settled, not before.
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.001);
    let lim = limits(20.0, 100.0, 0.0);
    let pts = [(1.0, 0.0), (1.0, 1.0), (2.0, 1.0), (2.0, 2.0)];
    for (k, (x, y)) in pts.iter().enumerate() {
        tp.add_line(
            xyz(*x, *y, 0.0),
            LineKind::Feed,
            10.0,
            k as i32 + 1,
            ENABLES,
            &lim,
        )
        .unwrap();
    }
    let lines: Vec<_> = tp.queue.iter().filter(|s| s.blendable_line()).collect();
    assert_eq!(lines.len(), 4);
    for l in &lines[..3] {
        assert_eq!(l.joins(), budget::Joins::Tangent);
        assert!((l.budget.acc - 100.0).abs() < 1e-9, "{}", l.budget.acc);
    }
    assert_eq!(lines[3].joins(), budget::Joins::Blend);
    assert!((lines[3].budget.acc - 50.0).abs() < 1e-9);
    let mut p = vec![tp.pos()];
    p.extend(run(&mut tp, &ScaleInputs::default(), 100_000));
    assert_within(&p, &lim, false);
    assert_eq!(*p.last().unwrap(), xyz(2.0, 2.0, 0.0));
}

#[test]
fn a_running_line_settled_by_a_blend_arc_speeds_up_harder_from_then_on() {
    // The first G64 line starts alone (half); once the next line blends
    // into it, the trapezoidal planner may use the whole limit for the
    // rest of it. The S-curve planner keeps what it planned with.
    for planner in [PlannerType::Trapezoidal, PlannerType::SCurve] {
        let mut tp = Planner::new(T);
        tp.set_planner_type(planner);
        tp.set_term_cond(TermCond::Blend, 0.01);
        let lim = limits(20.0, 100.0, 1e6);
        tp.add_line(xyz(2.0, 0.0, 0.0), LineKind::Feed, 10.0, 1, ENABLES, &lim)
            .unwrap();
        let scales = ScaleInputs::default();
        let mut p = vec![tp.pos()];
        for _ in 0..10 {
            p.push(tp.run(&scales));
        }
        tp.add_line(xyz(2.0, 2.0, 0.0), LineKind::Feed, 10.0, 2, ENABLES, &lim)
            .unwrap();
        for _ in 0..10 {
            p.push(tp.run(&scales));
        }
        let a = x_accels(&p);
        let before = a[..9].iter().fold(0.0f64, |m, x| m.max(*x));
        let after = a[11..].iter().fold(0.0f64, |m, x| m.max(*x));
        assert!(
            before <= 50.0 + 1e-6,
            "{planner:?}: half while alone: {before}"
        );
        match planner {
            PlannerType::Trapezoidal => {
                assert!(
                    (after - 100.0).abs() < 1e-6,
                    "the whole once settled: {after}"
                )
            }
            PlannerType::SCurve => assert!(after <= 50.0 + 1e-6, "unchanged: {after}"),
        }
        p.extend(run(&mut tp, &scales, 100_000));
        assert_within(&p, &lim, planner == PlannerType::SCurve);
        assert_eq!(*p.last().unwrap(), xyz(2.0, 2.0, 0.0));
    }
}
