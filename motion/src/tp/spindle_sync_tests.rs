//! Position-synchronised segments against a simulated spindle: an
//! encoder whose `revs` ramp with the spindle's speed and which, once
//! `index-enable` is set, clears it and restarts its count at the index
//! mark, as LinuxCNC's encoders do.

use super::*;
use crate::command::{LineKind, Reject, TermCond};
use crate::kins::NUM_AXES;

const T: f64 = 0.001;
const ENABLES: u8 = FS_ENABLED | FH_ENABLED;

/// A spindle turning at `rps` with an index mark at revolution
/// `index_at` (fraction of a turn) of its own angle.
struct SimSpindle {
    /// Revolutions turned in total (the spindle's angle).
    angle: f64,
    rps: f64,
    /// Where the count restarted (the last index taken), in `angle`.
    zero: f64,
    index_enable: bool,
    index_at: f64,
    /// Index pulses taken.
    indexes: u32,
}

impl SimSpindle {
    fn new(rps: f64, angle: f64) -> SimSpindle {
        SimSpindle {
            angle,
            rps,
            zero: 0.0,
            index_enable: false,
            index_at: 0.25,
            indexes: 0,
        }
    }

    /// One period: the spindle turns; an armed index mark passed
    /// restarts the count there.
    fn turn(&mut self) {
        let before = self.angle;
        self.angle += self.rps * T;
        if self.index_enable {
            let mark = (before - self.index_at).floor() + 1.0 + self.index_at;
            if self.angle >= mark {
                self.zero = mark;
                self.index_enable = false;
                self.indexes += 1;
            }
        }
    }

    fn revs(&self) -> f64 {
        self.angle - self.zero
    }
}

/// One period of the planner with the spindle: the encoder runs first,
/// the planner reads it, the controller writes `index-enable`.
fn step(tp: &mut Planner, sp: &mut SimSpindle, scales: &mut ScaleInputs) -> Pose {
    sp.turn();
    scales.spindle_revs[0] = sp.revs();
    scales.spindle_rps[0] = sp.rps;
    scales.spindle_index_enable = u32::from(sp.index_enable);
    let p = tp.run(scales);
    if tp.index_arm() == Some(0) {
        sp.index_enable = true;
    }
    p
}

fn z(v: f64) -> Pose {
    let mut p = Pose::ZERO;
    p.0[2] = v;
    p
}

fn limits(v: f64, a: f64) -> AxisLimits {
    AxisLimits {
        vel: [v; NUM_AXES],
        acc: [a; NUM_AXES],
        jerk: [0.0; NUM_AXES],
        path_vel: f64::INFINITY,
        path_acc: f64::INFINITY,
    }
}

fn lock(per_rev: f64) -> Option<FeedPerRev> {
    Some(FeedPerRev {
        spindle: 0,
        per_rev,
    })
}

/// Runs until done; the poses and the spindle's `revs` and angle of
/// each period.
fn run_all(
    tp: &mut Planner,
    sp: &mut SimSpindle,
    scales: &mut ScaleInputs,
) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::new();
    for _ in 0..200_000 {
        let p = step(tp, sp, scales);
        out.push((p.0[2], sp.revs(), sp.angle));
        if tp.is_done() {
            return out;
        }
    }
    panic!("not done");
}

/// The largest |v| and |a| of Z.
fn extremes(z: &[f64]) -> (f64, f64) {
    let v: Vec<f64> = z.windows(2).map(|w| (w[1] - w[0]) / T).collect();
    let a = v.windows(2).map(|w| ((w[1] - w[0]) / T).abs());
    (
        v.iter().fold(0.0, |m, x| m.max(x.abs())),
        a.fold(0.0, f64::max),
    )
}

#[test]
fn a_synchronised_move_waits_for_the_index_then_follows_the_revolutions() {
    let mut tp = Planner::new(T);
    let lim = limits(20.0, 500.0);
    tp.set_position_sync(lock(0.5));
    // 10 rev/s at 0.5 per revolution: 5 u/s.
    tp.add_line(z(-10.0), LineKind::Feed, 1.0, 3, ENABLES, &lim)
        .unwrap();
    let mut sp = SimSpindle::new(10.0, 0.0);
    // Not at speed: it waits, index-enable untouched.
    let mut scales = ScaleInputs {
        spindle_at_speed: false,
        ..ScaleInputs::default()
    };
    for _ in 0..50 {
        assert_eq!(step(&mut tp, &mut sp, &mut scales), Pose::ZERO);
        assert!(!sp.index_enable);
        assert!(tp.status().waiting_for_atspeed);
    }
    scales.spindle_at_speed = true;
    // At speed: index-enable is set, and nothing moves until the mark
    // (a quarter turn on: 25 periods).
    let mut waited = 0;
    loop {
        let p = step(&mut tp, &mut sp, &mut scales);
        if sp.indexes > 0 {
            break;
        }
        assert_eq!(p, Pose::ZERO);
        assert!(tp.waiting_for_index() && sp.index_enable);
        waited += 1;
        assert!(waited < 200, "the index never came");
    }
    assert!(waited > 20, "waited {waited} periods for the mark");
    let trace = run_all(&mut tp, &mut sp, &mut scales);
    // Locked once the start's lag is made up: Z = -revs × pitch, with
    // the revs counted from the index.
    let locked: Vec<_> = trace.iter().filter(|t| t.0 < -2.0 && t.0 > -8.0).collect();
    assert!(locked.len() > 1000);
    for (zpos, revs, _) in &locked {
        assert!((zpos + revs * 0.5).abs() < 1e-9, "z {zpos} revs {revs}");
    }
    let zs: Vec<f64> = trace.iter().map(|t| t.0).collect();
    assert_eq!(*zs.last().unwrap(), -10.0, "ends on the end point");
    let (v, a) = extremes(&zs);
    assert!(v <= 20.0 * (1.0 + 1e-9), "velocity {v}");
    assert!(a <= 500.0 * (1.0 + 1e-6), "acceleration {a}");
    assert_eq!(sp.indexes, 1);
}

#[test]
fn every_pass_starts_at_the_same_spindle_angle() {
    let lim = limits(20.0, 300.0);
    let mut angles = Vec::new();
    // Passes that start at different spindle angles and depths.
    for (k, start_angle) in [0.0, 0.6, 3.9].into_iter().enumerate() {
        let mut tp = Planner::new(T);
        let x = -(k as f64) * 0.1;
        tp.set_pos(Pose([x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]));
        tp.set_position_sync(lock(0.25));
        let mut end = z(-5.0);
        end.0[0] = x;
        tp.add_line(end, LineKind::Feed, 1.0, 1, ENABLES, &lim)
            .unwrap();
        let mut sp = SimSpindle::new(12.0, start_angle);
        let mut scales = ScaleInputs::default();
        let trace = run_all(&mut tp, &mut sp, &mut scales);
        // The spindle angle (mod 1) where the tool is at Z = -2.5.
        let t = trace.iter().find(|t| t.0 <= -2.5).unwrap();
        let frac = (t.2 + t.0 / 0.25).rem_euclid(1.0);
        angles.push(frac);
    }
    for a in &angles {
        assert!((a - angles[0]).abs() < 1e-6, "angles {angles:?}");
    }
}

#[test]
fn consecutive_synchronised_moves_stay_locked_without_a_new_index() {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.0);
    let lim = limits(20.0, 400.0);
    tp.set_position_sync(lock(0.2));
    tp.add_line(z(-4.0), LineKind::Feed, 1.0, 1, ENABLES, &lim)
        .unwrap();
    // A taper: X and Z together, a larger pitch along the path.
    tp.set_position_sync(lock(0.3));
    tp.add_line(
        Pose([0.6, 0.0, -8.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        LineKind::Feed,
        1.0,
        2,
        ENABLES,
        &lim,
    )
    .unwrap();
    let mut sp = SimSpindle::new(8.0, 0.1);
    let mut scales = ScaleInputs::default();
    let mut trace = Vec::new();
    let mut arms = 0;
    for _ in 0..200_000 {
        let p = step(&mut tp, &mut sp, &mut scales);
        arms += u32::from(tp.index_arm().is_some());
        trace.push((p, sp.revs()));
        if tp.is_done() {
            break;
        }
    }
    assert!(tp.is_done());
    assert_eq!((arms, sp.indexes), (1, 1), "one index for both");
    // In the second move the progress is 4 (the first) + revs past the
    // first's 20 revolutions × 0.3.
    let len2 = (0.6f64.powi(2) + 16.0).sqrt();
    for (p, revs) in &trace {
        if p.0[2] < -5.0 && p.0[2] > -7.0 {
            let progress = 4.0 + (revs - 20.0) * 0.3;
            let want = -4.0 - progress_to_z(progress - 4.0, len2);
            assert!((p.0[2] - want).abs() < 1e-9, "z {} want {want}", p.0[2]);
        }
    }
    let zs: Vec<f64> = trace.iter().map(|t| t.0 .0[2]).collect();
    let (v, a) = extremes(&zs);
    assert!(
        v <= 20.0 * (1.0 + 1e-9) && a <= 400.0 * (1.0 + 1e-6),
        "{v} {a}"
    );
}

/// The Z travel of the taper at path progress `s`.
fn progress_to_z(s: f64, len: f64) -> f64 {
    s * 4.0 / len
}

#[test]
fn a_spindle_too_fast_for_the_axis_is_followed_within_its_limits() {
    let mut tp = Planner::new(T);
    let lim = limits(4.0, 1000.0);
    // 2000 rpm at 0.24 per revolution asks 8 u/s of an axis limited to 4.
    tp.set_position_sync(lock(0.24));
    tp.add_line(z(-5.0), LineKind::Feed, 1.0, 1, ENABLES, &lim)
        .unwrap();
    let mut sp = SimSpindle::new(2000.0 / 60.0, 0.0);
    let mut scales = ScaleInputs::default();
    let trace = run_all(&mut tp, &mut sp, &mut scales);
    let zs: Vec<f64> = trace.iter().map(|t| t.0).collect();
    let (v, a) = extremes(&zs);
    assert!(v <= 4.0 * (1.0 + 1e-9), "velocity {v}");
    assert!(a <= 1000.0 * (1.0 + 1e-6), "acceleration {a}");
    assert_eq!(*zs.last().unwrap(), -5.0);
}

#[test]
fn feed_override_feed_hold_and_pause_leave_a_synchronised_move_alone() {
    let mut tp = Planner::new(T);
    let lim = limits(20.0, 500.0);
    tp.set_position_sync(lock(0.5));
    tp.add_line(z(-10.0), LineKind::Feed, 1.0, 1, ENABLES, &lim)
        .unwrap();
    // An ordinary move after it stops for the pause.
    tp.set_position_sync(None);
    tp.add_line(z(-12.0), LineKind::Feed, 5.0, 2, ENABLES, &lim)
        .unwrap();
    let mut sp = SimSpindle::new(10.0, 0.0);
    let mut scales = ScaleInputs {
        feed: 0.3,
        feed_hold: true,
        ..ScaleInputs::default()
    };
    let mut p = Pose::ZERO;
    while p.0[2] > -3.0 {
        p = step(&mut tp, &mut sp, &mut scales);
    }
    tp.pause();
    let mut last = p;
    for _ in 0..3000 {
        let q = step(&mut tp, &mut sp, &mut scales);
        if q.0[2] > -10.0 + 1e-9 {
            assert!((q.0[2] + sp.revs() * 0.5).abs() < 1e-9 || q.0[2] < -9.0);
        }
        last = q;
    }
    // Ran to its end and stopped there (the next move is paused). The
    // corner into the next move is settled at speed, so the stop is on
    // the next move's first point, within rounding of the end.
    assert!((last.0[2] + 10.0).abs() < 1e-12, "{}", last.0[2]);
    assert_eq!(tp.status().exec_id, 2);
}

#[test]
fn an_abort_while_waiting_for_the_index_drops_the_queue() {
    let mut tp = Planner::new(T);
    let lim = limits(20.0, 500.0);
    tp.set_position_sync(lock(0.5));
    tp.add_line(z(-10.0), LineKind::Feed, 1.0, 1, ENABLES, &lim)
        .unwrap();
    let mut sp = SimSpindle::new(0.0, 0.0);
    let mut scales = ScaleInputs::default();
    for _ in 0..10 {
        step(&mut tp, &mut sp, &mut scales);
    }
    assert!(tp.waiting_for_index());
    tp.abort();
    step(&mut tp, &mut sp, &mut scales);
    assert!(tp.is_done() && !tp.waiting_for_index());
    assert_eq!(tp.pos(), Pose::ZERO);
}

/// A spindle whose speed follows its command at `acc` rev/s².
struct DrivenSpindle {
    sp: SimSpindle,
    cmd: f64,
    acc: f64,
}

impl DrivenSpindle {
    fn step(&mut self, tp: &mut Planner, scales: &mut ScaleInputs) -> Pose {
        let dv = (self.cmd - self.sp.rps).clamp(-self.acc * T, self.acc * T);
        self.sp.rps += dv;
        scales.spindle_reverse = u32::from(self.cmd < 0.0);
        let p = step(tp, &mut self.sp, scales);
        if let Some((0, f)) = tp.take_spindle_reversal() {
            self.cmd *= f;
        }
        p
    }
}

#[test]
fn a_rigid_tap_follows_the_spindle_down_reverses_and_returns_to_its_start() {
    let mut tp = Planner::new(T);
    let lim = limits(30.0, 800.0);
    tp.set_pos(Pose([1.0, 2.0, 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]));
    // No synchronisation: refused, as LinuxCNC.
    let bottom = Pose([1.0, 2.0, -5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(
        tp.add_rigid_tap(bottom, 5.0, 1.0, 4, ENABLES, &lim),
        Err(Reject::RigidTapNotSynchronised)
    );
    // M6 × 1: 1 mm per revolution, 8 rev/s, back twice as fast.
    tp.set_position_sync(lock(1.0));
    tp.add_rigid_tap(bottom, 8.0, 2.0, 4, ENABLES, &lim)
        .unwrap();
    assert_eq!(tp.goal().0[2], 5.0, "it comes back");
    let mut sp = DrivenSpindle {
        sp: SimSpindle::new(8.0, 0.0),
        cmd: 8.0,
        acc: 400.0,
    };
    let mut scales = ScaleInputs::default();
    let mut zs = Vec::new();
    let mut states = Vec::new();
    let mut cmds = Vec::new();
    for _ in 0..100_000 {
        let p = sp.step(&mut tp, &mut scales);
        assert_eq!((p.0[0], p.0[1]), (1.0, 2.0), "straight along Z");
        if let Some(s) = tp.tap_state() {
            if states.last() != Some(&s) {
                states.push(s);
            }
            // Locked while tapping and coming back (once the lag of
            // each start is made up): the same helix.
            let locked = match s {
                TapState::Tapping => p.0[2] < 2.0,
                TapState::Retraction => p.0[2] > 0.0 && p.0[2] < 4.0,
                _ => false,
            };
            if locked {
                let helix = 5.0 - sp.sp.revs();
                assert!(
                    (p.0[2] - helix).abs() < 1e-6,
                    "{s:?}: z {} helix {helix}",
                    p.0[2]
                );
            }
        }
        if cmds.last() != Some(&sp.cmd) {
            cmds.push(sp.cmd);
        }
        zs.push(p.0[2]);
        if tp.is_done() {
            break;
        }
    }
    assert!(tp.is_done());
    assert_eq!(
        states,
        [
            TapState::Tapping,
            TapState::Reversing,
            TapState::Retraction,
            TapState::FinalReversal,
            TapState::FinalPlacement
        ]
    );
    // Reversed twice as fast, then forward at the speed again.
    assert_eq!(cmds, [8.0, -16.0, 8.0]);
    let deepest = zs.iter().fold(f64::INFINITY, |m, &z| m.min(z));
    assert!(deepest <= -5.0 && deepest > -5.5, "deepest {deepest}");
    assert_eq!(*zs.last().unwrap(), 5.0, "back on the start exactly");
    let (v, a) = extremes(&zs);
    assert!(v <= 30.0 * (1.0 + 1e-9), "velocity {v}");
    assert!(a <= 800.0 * (1.0 + 1e-6), "acceleration {a}");
}

#[test]
fn an_encoder_counting_whole_counts_does_not_shake_the_axis() {
    let mut tp = Planner::new(T);
    let lim = limits(20.0, 1000.0);
    tp.set_position_sync(lock(0.1));
    tp.add_line(z(-10.0), LineKind::Feed, 1.0, 1, ENABLES, &lim)
        .unwrap();
    // 2000 rpm on an encoder of 64 counts per revolution: 2.1 counts a
    // period, so the count's change per period jumps between 2 and 3.
    let mut sp = SimSpindle::new(2000.0 / 60.0, 0.0);
    let mut scales = ScaleInputs::default();
    let counts = 64.0;
    let mut trace = Vec::new();
    for _ in 0..100_000 {
        sp.turn();
        scales.spindle_revs[0] = (sp.revs() * counts).floor() / counts;
        scales.spindle_rps[0] = sp.rps;
        scales.spindle_index_enable = u32::from(sp.index_enable);
        let p = tp.run(&scales);
        if tp.index_arm() == Some(0) {
            sp.index_enable = true;
        }
        trace.push((p.0[2], sp.revs()));
        if tp.is_done() {
            break;
        }
    }
    let zs: Vec<f64> = trace.iter().map(|t| t.0).collect();
    let spindle_speed = sp.rps * 0.1;
    for (w, t) in zs.windows(2).zip(&trace[1..]) {
        if t.0 < -2.0 && t.0 > -8.0 {
            let v = (w[0] - w[1]) / T;
            assert!((v - spindle_speed).abs() < 0.1 * spindle_speed, "speed {v}");
            // Within two counts of the true helix.
            assert!((t.0 + t.1 * 0.1).abs() < 2.0 / counts * 0.1, "{t:?}");
        }
    }
    let (v, a) = extremes(&zs);
    assert!(
        v <= 20.0 * (1.0 + 1e-9) && a <= 1000.0 * (1.0 + 1e-6),
        "{v} {a}"
    );
}

#[test]
fn an_unsynchronised_move_after_a_synchronised_one_follows_it_at_its_own_feed() {
    let mut tp = Planner::new(T);
    tp.set_term_cond(TermCond::Blend, 0.0);
    let lim = limits(20.0, 500.0);
    tp.set_position_sync(lock(0.5));
    tp.add_line(z(-5.0), LineKind::Feed, 1.0, 1, ENABLES, &lim)
        .unwrap();
    tp.set_position_sync(None);
    tp.add_line(z(-10.0), LineKind::Feed, 2.0, 2, ENABLES, &lim)
        .unwrap();
    let mut sp = SimSpindle::new(10.0, 0.0);
    // The feed override applies to the second move only.
    let mut scales = ScaleInputs {
        feed: 0.5,
        ..ScaleInputs::default()
    };
    let trace = run_all(&mut tp, &mut sp, &mut scales);
    let zs: Vec<f64> = trace.iter().map(|t| t.0).collect();
    let speeds: Vec<f64> = zs.windows(2).map(|w| (w[0] - w[1]) / T).collect();
    // No stop where they meet: crossed while slowing from 5 to 1.
    let at_corner = zs.iter().position(|&z| z <= -5.0).unwrap();
    assert!(speeds[at_corner - 1] > 0.9, "{}", speeds[at_corner - 1]);
    // Then the programmed 2 u/s times the override.
    let cruise = zs.iter().position(|&z| z <= -8.0).unwrap();
    assert!((speeds[cruise] - 1.0).abs() < 1e-9, "{}", speeds[cruise]);
    assert_eq!(*zs.last().unwrap(), -10.0);
    let (v, a) = extremes(&zs);
    assert!(
        v <= 20.0 * (1.0 + 1e-9) && a <= 500.0 * (1.0 + 1e-6),
        "{v} {a}"
    );
}
