//! Tests of locking indexers through the core: the unlock, is-unlocked,
//! move, lock sequence of an indexer's rapid with motion-type 6, the
//! refused moves, the configuration command, and the timeouts. A
//! simulated indexer answers its unlock request a few periods late.

use super::*;
use crate::command::{Command, LineKind, Reject};
use crate::events::Event;
use crate::kins::trivkins::Trivkins;
use crate::test_support::{Sim, T};
use crate::tp::INDEXER_TIMEOUT;

/// The indexer joint (B of X Y Z B).
const JB: usize = 3;
/// World axis B.
const B: usize = 4;
/// Periods the simulated indexer takes to unlock or lock.
const DELAY: usize = 5;

/// X Y Z B on trivkins, joint 3 with unlock pins and B its locking
/// indexer; homed, enabled, in coordinated mode.
fn xyzb() -> Sim {
    let kins = Arc::new(Trivkins::new("xyzb", KinematicsType::Identity).unwrap());
    let cfg = MotionConfig {
        num_joints: 4,
        unlock_joints_mask: 1 << JB,
        ..MotionConfig::default()
    };
    let mut m = MotionCore::new(cfg, kins);
    crate::test_support::configure_test_joints(&mut m);
    crate::test_support::configure_test_axes(&mut m, 50.0);
    m.command(&Command::SetAxisLockingIndexer {
        axis: B as i32,
        joint: JB as i32,
    })
    .unwrap();
    for j in 0..4 {
        m.set_homed(j, true);
    }
    let mut s = Sim::new(m);
    s.enable();
    s.cmd(Command::Coord).unwrap();
    s
}

fn pose(x: f64, b: f64) -> Pose {
    let mut p = Pose::ZERO;
    p.0[0] = x;
    p.0[B] = b;
    p
}

fn rapid(x: f64, b: f64, id: i32) -> Command {
    Command::Line {
        end: pose(x, b),
        vel: 0.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Traverse,
        id,
    }
}

fn feed(x: f64, b: f64, id: i32) -> Command {
    Command::Line {
        end: pose(x, b),
        vel: 5.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id,
    }
}

/// One period as seen from HAL.
#[derive(Debug, Clone, Copy)]
struct Period {
    unlock: bool,
    is_unlocked: bool,
    motion_type: i32,
    x: f64,
    b: f64,
}

/// A simulated indexer: is-unlocked follows the unlock request `DELAY`
/// periods late (never, for `stuck`).
struct Indexer {
    timer: usize,
    is_unlocked: bool,
    stuck: bool,
}

impl Indexer {
    fn new() -> Indexer {
        Indexer {
            timer: 0,
            is_unlocked: false,
            stuck: false,
        }
    }

    /// Runs `n` periods at most, or until the queue is done.
    fn run(&mut self, s: &mut Sim, n: usize) -> Vec<Period> {
        let mut out = Vec::new();
        for _ in 0..n {
            let want = s.m.unlock_output(JB);
            if want != self.is_unlocked && !self.stuck {
                self.timer += 1;
                if self.timer >= DELAY {
                    self.is_unlocked = want;
                    self.timer = 0;
                }
            } else {
                self.timer = 0;
            }
            s.m.joint_inputs[JB].is_unlocked = self.is_unlocked;
            s.cycle();
            out.push(Period {
                unlock: s.m.unlock_output(JB),
                is_unlocked: self.is_unlocked,
                motion_type: s.m.planner().motion_type(),
                x: s.j(0).pos_cmd,
                b: s.j(JB).pos_cmd,
            });
            if s.m.in_position() && !s.m.unlock_output(JB) && !self.is_unlocked {
                break;
            }
        }
        out
    }
}

#[test]
fn an_indexer_rapid_unlocks_moves_and_locks_before_the_next_move() {
    indexer_sequence(xyzb());
}

#[test]
fn the_s_curve_planner_runs_the_same_sequence() {
    let mut s = xyzb();
    s.cmd(Command::SetJerkLimit { jerk: 1e5 }).unwrap();
    s.cmd(Command::SetPlannerType { planner: 1 }).unwrap();
    indexer_sequence(s);
}

/// A feed move of X, the indexer's rapid of B, a feed move of X: the
/// handshake around the rapid, at rest on both sides.
fn indexer_sequence(mut s: Sim) {
    s.cmd(feed(2.0, 0.0, 1)).unwrap();
    s.cmd(rapid(2.0, 30.0, 2)).unwrap();
    s.cmd(feed(4.0, 30.0, 3)).unwrap();
    let p = Indexer::new().run(&mut s, 20_000);
    assert!(s.m.in_position(), "queue not done");
    assert!(!s.m.error());
    assert!(s.events().is_empty());

    // The unlock is raised only once X stands at 2, and B stays still
    // until the joint reports itself unlocked.
    let up = p
        .iter()
        .position(|q| q.unlock)
        .expect("unlock never raised");
    assert!(p[..up].iter().all(|q| q.b == 0.0));
    assert!((p[up - 1].x - 2.0).abs() < 1e-12 && p[up - 1].x == p[up].x);
    let unlocked = p.iter().position(|q| q.is_unlocked).unwrap();
    assert!(unlocked >= up + DELAY - 1);
    assert!(
        p[..unlocked].iter().all(|q| q.b == 0.0),
        "B moved while locked"
    );
    assert!(p[up..=unlocked].iter().all(|q| q.motion_type == 6));

    // B moves alone, unlocked, with motion-type 6, and reaches 30 exactly.
    let drop = up + p[up..].iter().position(|q| !q.unlock).unwrap();
    assert!((p[drop].b - 30.0).abs() < 1e-12, "{:?}", p[drop]);
    assert!(p[unlocked..drop]
        .iter()
        .all(|q| q.is_unlocked && q.motion_type == 6 && q.x == 2.0));
    assert!(p[unlocked + 1].b > 0.0);

    // X waits until is-unlocked has fallen again.
    let locked = drop + p[drop..].iter().position(|q| !q.is_unlocked).unwrap();
    assert!(locked >= drop + DELAY - 1);
    assert!(p[drop..locked]
        .iter()
        .all(|q| q.x == 2.0 && q.motion_type == 6));
    assert!(p[locked + 1..].iter().any(|q| q.x > 2.0));
    assert!(p[locked + 1..].iter().all(|q| !q.unlock && q.b == 30.0));
    let last = p.last().unwrap();
    assert!((last.x - 4.0).abs() < 1e-12 && last.motion_type == 0);
}

#[test]
fn moves_of_an_indexer_axis_other_than_a_lone_rapid_are_refused() {
    let mut s = xyzb();
    assert_eq!(
        s.cmd(feed(0.0, 10.0, 1)),
        Err(Reject::IndexerNeedsRapid { axis: B })
    );
    assert_eq!(
        s.cmd(rapid(1.0, 10.0, 1)),
        Err(Reject::IndexerNotAlone { axis: B })
    );
    let mut end = pose(0.0, 10.0);
    end.0[1] = 2.0;
    assert_eq!(
        s.cmd(Command::Circle {
            end,
            center: [0.0, 1.0, 0.0],
            normal: [0.0, 0.0, 1.0],
            turns: 0,
            vel: 5.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            id: 1,
        }),
        Err(Reject::IndexerNeedsRapid { axis: B })
    );
    // Nothing was queued; moves that leave B alone are plain moves.
    assert!(s.m.planner().done);
    s.cmd(rapid(1.0, 0.0, 2)).unwrap();
    s.cmd(feed(2.0, 0.0, 3)).unwrap();
    let p = Indexer::new().run(&mut s, 5_000);
    assert!(p.iter().all(|q| !q.unlock && q.motion_type != 6));
    assert!((p.last().unwrap().x - 2.0).abs() < 1e-12);
}

#[test]
fn the_indexer_command_needs_unlock_pins_and_motion_disabled() {
    let mut s = xyzb();
    let set = |axis: i32, joint: i32| Command::SetAxisLockingIndexer { axis, joint };
    assert_eq!(s.cmd(set(4, 3)), Err(Reject::MustBeDisabled));
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert_eq!(s.cmd(set(4, 2)), Err(Reject::NoUnlockPins { joint: 2 }));
    assert_eq!(
        s.cmd(set(4, 4)),
        Err(Reject::NoSuchJoint {
            joint: 4,
            num_joints: 4
        })
    );
    assert_eq!(s.cmd(set(9, 3)), Err(Reject::NoSuchAxis { axis: 9 }));
    // -1 makes B an ordinary axis again: a feed move of it is queued.
    s.cmd(set(4, -1)).unwrap();
    s.enable();
    s.cmd(Command::Coord).unwrap();
    s.cmd(feed(0.0, 1.0, 1)).unwrap();
}

/// Periods in the timeout, and a margin.
fn timeout_periods() -> usize {
    (INDEXER_TIMEOUT / T) as usize + 10
}

#[test]
fn an_indexer_that_never_unlocks_faults_naming_its_joint() {
    let mut s = xyzb();
    s.cmd(rapid(0.0, 30.0, 1)).unwrap();
    s.cmd(feed(1.0, 30.0, 2)).unwrap();
    let mut ix = Indexer::new();
    ix.stuck = true;
    let p = ix.run(&mut s, timeout_periods());
    assert!(p.iter().all(|q| q.b == 0.0 && q.x == 0.0));
    let up = p.iter().filter(|q| q.unlock).count();
    assert!((up as f64 * T - INDEXER_TIMEOUT).abs() < 2.0 * T, "{up}");
    assert!(!s.m.unlock_output(JB));
    assert!(s.m.error());
    assert!(s.m.planner().done && s.m.planner().depth == 0);
    let ev = s.events();
    assert_eq!(
        ev,
        [Event::IndexerTimeout {
            joint: JB,
            unlocking: true
        }]
    );
    assert!(ev[0].stops_a_program());
    let text = ev[0].to_string();
    assert!(
        text.contains("joint 3") && text.contains("joint.3.is-unlocked"),
        "{text}"
    );
}

#[test]
fn an_indexer_that_never_locks_again_faults_and_aborts_the_rest() {
    let mut s = xyzb();
    s.cmd(rapid(0.0, 5.0, 1)).unwrap();
    s.cmd(feed(1.0, 5.0, 2)).unwrap();
    let mut ix = Indexer::new();
    // Unlock normally, then stay unlocked.
    let mut p = Vec::new();
    while !p.iter().any(|q: &Period| q.is_unlocked) {
        p.extend(ix.run(&mut s, 1));
    }
    ix.stuck = true;
    p.extend(ix.run(&mut s, 2_000 + timeout_periods()));
    assert!((s.j(JB).pos_cmd - 5.0).abs() < 1e-12);
    assert_eq!(s.j(0).pos_cmd, 0.0, "the feed move after it ran");
    assert_eq!(
        s.events(),
        [Event::IndexerTimeout {
            joint: JB,
            unlocking: false
        }]
    );
    assert!(s.m.error() && s.m.planner().depth == 0);
}

#[test]
fn disabling_drops_the_unlock_and_the_queue() {
    let mut s = xyzb();
    s.cmd(rapid(0.0, 30.0, 1)).unwrap();
    let mut ix = Indexer::new();
    ix.run(&mut s, 3);
    assert!(s.m.unlock_output(JB));
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert!(!s.m.unlock_output(JB));
    s.enable();
    s.cmd(Command::Coord).unwrap();
    s.cycle();
    assert!(!s.m.unlock_output(JB) && s.m.planner().depth == 0);
}

#[test]
fn a_locking_indexer_axis_does_not_jog_in_teleop() {
    let mut s = xyzb();
    s.cmd(Command::Teleop).unwrap();
    s.cycle();
    assert_eq!(
        s.cmd(Command::AxisJogCont {
            axis: B as i32,
            vel: 5.0
        }),
        Err(Reject::IndexerJog { axis: B, joint: JB })
    );
    let refused = Reject::IndexerJog { axis: B, joint: JB }.to_string();
    assert!(
        refused.contains("axis B") && refused.contains("joint 3"),
        "{refused}"
    );
    // Its wheel counts are ignored; X's wheel still jogs X.
    for a in [0, B] {
        s.m.axis_inputs[a].jog_enable = true;
        s.m.axis_inputs[a].jog_scale = 0.1;
    }
    s.cycle();
    s.m.axis_inputs[0].jog_counts = 10;
    s.m.axis_inputs[B].jog_counts = 10;
    s.run(500);
    assert!((s.j(0).pos_cmd - 1.0).abs() < 1e-9);
    assert_eq!(s.j(JB).pos_cmd, 0.0);
    assert!(!s.m.unlock_output(JB));
}

#[test]
fn an_abort_during_the_move_stops_b_before_dropping_the_unlock() {
    let mut s = xyzb();
    s.cmd(rapid(0.0, 30.0, 1)).unwrap();
    let mut ix = Indexer::new();
    let mut p = Vec::new();
    while !p.iter().any(|q: &Period| q.b > 10.0) {
        p.extend(ix.run(&mut s, 1));
        assert!(p.len() < 10_000, "B never got past 10");
    }
    s.cmd(Command::Abort).unwrap();
    let after = ix.run(&mut s, 2_000);
    // B slows down within its acceleration limit while still unlocked.
    let drop = after.iter().position(|q| !q.unlock).unwrap();
    let mut last = p.last().unwrap().b;
    let mut v = (last - p[p.len() - 2].b) / T;
    for q in &after[..drop] {
        let v1 = (q.b - last) / T;
        assert!((v1 - v).abs() / T <= 100.0 + 1e-6, "{v} -> {v1}");
        (last, v) = (q.b, v1);
    }
    assert!(after[drop..].iter().all(|q| q.b == after[drop].b));
    assert!(after[drop].b < 30.0 && s.m.planner().depth == 0);
    assert!(!s.m.error());
}
