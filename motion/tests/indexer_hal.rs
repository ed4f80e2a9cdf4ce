//! A locking indexer through HAL: `motmod` with unlock pins in a running
//! servo thread, and another thread acting as the clamp (it answers
//! `joint.3.unlock` on `joint.3.is-unlocked` a few milliseconds late).
//! A rapid of B unlocks, moves and relocks before the feed move queued
//! after it starts; `motion.motion-type` reads 6 meanwhile; B's joint
//! never moves while the clamp reports itself locked.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

mod common;

use common::*;
use hal_core::Value;
use motion::command::{LineKind, Reject};
use motion::{Command, MotionClient, Pose};

/// X Y Z B trivkins, joint 3 with unlock pins and B's locking indexer;
/// homed, in coordinated mode.
fn machine(h: &hal_core::Host) -> MotionClient {
    loadrt(h, "trivkins", &["coordinates=xyzb"]).unwrap();
    loadrt(h, "motmod", &["num_joints=4", "unlock_joints_mask=0x8"]).unwrap();
    loop_back_motors(h, 4);
    start_motion(h);
    let mut c = MotionClient::open(h.instance())
        .unwrap()
        .with_timeout(Duration::from_secs(2));
    for j in 0..4 {
        let axis = if j == 3 { 4 } else { j };
        for cmd in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -100.0,
                max: 100.0,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 40.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 500.0,
            },
            Command::SetJointHomingParams {
                joint: j,
                config: motion::homing::HomingConfig {
                    sequence: 0,
                    ..Default::default()
                },
            },
            Command::SetAxisPositionLimits {
                axis,
                min: -50.0,
                max: 50.0,
            },
            Command::SetAxisVelLimit { axis, vel: 40.0 },
            Command::SetAxisAccLimit { axis, acc: 500.0 },
        ] {
            c.send(cmd).unwrap();
        }
    }
    c.send(Command::SetAxisLockingIndexer { axis: 4, joint: 3 })
        .unwrap();
    c.send(Command::Enable).unwrap();
    wait_for("enabled", || bit(h, "motion.motion-enabled"));
    c.send(Command::Home { joint: -1 }).unwrap();
    wait_for("homed", || bit(h, "motion.is-all-homed"));
    wait_for("coord to be accepted", || c.send(Command::Coord).is_ok());
    wait_for("coord", || c.status().unwrap().mode == "COORD");
    c
}

fn at(x: f64, b: f64) -> Pose {
    let mut p = Pose::ZERO;
    p.0[0] = x;
    p.0[4] = b;
    p
}

fn motion_type(h: &hal_core::Host) -> i32 {
    match h.instance().pin_value("motion.motion-type").unwrap() {
        Value::S32(v) => v,
        v => panic!("motion-type: {v:?}"),
    }
}

#[test]
fn a_rapid_of_the_indexer_axis_unlocks_moves_and_relocks() {
    let h = host("indexer-move");
    let mut c = machine(&h);
    let inst = h.instance();
    // Only a lone rapid may move B.
    let refused = c
        .send(Command::Line {
            end: at(0.0, 10.0),
            vel: 5.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Feed,
            id: 1,
        })
        .unwrap_err();
    assert_eq!(refused.reason, Reject::IndexerNeedsRapid { axis: 4 });
    c.send(Command::Line {
        end: at(0.0, 30.0),
        vel: 0.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Traverse,
        id: 2,
    })
    .unwrap();
    c.send(Command::Line {
        end: at(2.0, 30.0),
        vel: 20.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id: 3,
    })
    .unwrap();
    let done = AtomicBool::new(false);
    let (moved_locked, x_before_lock, saw_6, unlocks) = std::thread::scope(|s| {
        // The clamp: follows the request 5 ms late; reports whether B's
        // joint moved while it was locked, or X before B relocked.
        let clamp = s.spawn(|| {
            let mut unlocked = false;
            let mut b_locked = float(&h, "joint.3.pos-cmd");
            let mut moved_locked = false;
            let mut x_before_lock = false;
            let mut unlocks = 0;
            while !done.load(Ordering::Relaxed) {
                let want = bit(&h, "joint.3.unlock");
                if want != unlocked {
                    std::thread::sleep(Duration::from_millis(5));
                    unlocked = want;
                    unlocks += usize::from(want);
                    if !want {
                        // The move is over: X must not have started yet.
                        x_before_lock |= float(&h, "joint.0.pos-cmd") != 0.0;
                    }
                    inst.set_pin("joint.3.is-unlocked", Value::Bit(unlocked))
                        .unwrap();
                    b_locked = float(&h, "joint.3.pos-cmd");
                }
                if !unlocked {
                    moved_locked |= float(&h, "joint.3.pos-cmd") != b_locked;
                }
                std::thread::sleep(Duration::from_micros(200));
            }
            (moved_locked, x_before_lock, unlocks)
        });
        let mut saw_6 = false;
        wait_for("the program to run", || {
            saw_6 |= motion_type(&h) == 6;
            (float(&h, "joint.0.pos-cmd") - 2.0).abs() < 1e-9 && bit(&h, "motion.in-position")
        });
        done.store(true, Ordering::Relaxed);
        let (m, x, u) = clamp.join().unwrap();
        (m, x, saw_6, u)
    });
    assert!(!moved_locked, "joint 3 moved while its clamp was locked");
    assert!(!x_before_lock, "X started before B relocked");
    assert!(saw_6, "motion-type 6 during the indexer move");
    assert_eq!(unlocks, 1);
    assert!((float(&h, "joint.3.pos-cmd") - 30.0).abs() < 1e-9);
    assert!(!bit(&h, "joint.3.unlock"));
    assert_eq!(motion_type(&h), 0);
}
