//! Property tests of the free-mode planner: for random limits, SCALE,
//! periods, targets and mid-move target changes it never exceeds the
//! velocity limit (times SCALE) or the acceleration limit, never overshoots
//! a rest-to-rest move, and comes to rest on the target (within the
//! planner's dead band `0.001·A·T²`, the only tolerance it has).
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;

use motion::kins::trivkins::Trivkins;
use motion::simple_tp::SimpleTp;
use motion::{Command, KinematicsType, MotionConfig, MotionCore};
use proptest::prelude::*;

/// Relative slack for comparing against limits computed in floating point.
const REL: f64 = 1e-9;

#[derive(Debug, Clone)]
struct Case {
    vel: f64,
    acc: f64,
    period: f64,
    scale: f64,
    first: f64,
    /// (period index, new target) changes, in time order.
    changes: Vec<(usize, f64)>,
}

fn case() -> impl Strategy<Value = Case> {
    (
        0.01f64..50.0,
        1.0f64..5000.0,
        prop_oneof![Just(0.0005), Just(0.001), Just(0.002), 0.0001f64..0.005],
        0.05f64..=1.0,
        -3.0f64..3.0,
        prop::collection::vec((1usize..3000, -3.0f64..3.0), 0..4),
    )
        .prop_map(|(vel, acc, period, scale, first, mut changes)| {
            // Targets are in "seconds of travel at the scaled speed", so
            // every case finishes in a bounded number of periods.
            let unit = vel * scale;
            changes.sort_by_key(|c| c.0);
            Case {
                vel,
                acc,
                period,
                scale,
                first: first * unit,
                changes: changes.into_iter().map(|(k, t)| (k, t * unit)).collect(),
            }
        })
}

/// Periods enough for any case: travel at the scaled speed plus ramps.
fn budget(c: &Case) -> usize {
    let v = c.vel * c.scale;
    let ramps = 4.0 * v / c.acc;
    let travel = 3.0 * (1 + c.changes.len()) as f64 * 2.0;
    let last_change = c.changes.last().map_or(0, |x| x.0);
    last_change + ((travel + ramps) / c.period) as usize + 1000
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn limits_hold_and_the_planner_stops_on_target(c in case()) {
        let mut tp = SimpleTp {
            pos_cmd: c.first,
            max_vel: c.vel,
            max_acc: c.acc,
            enable: true,
            ..SimpleTp::default()
        };
        let vmax = c.vel * c.scale;
        let dv = c.acc * c.period;
        let tiny = SimpleTp::tiny_dp(c.acc, c.period);
        let mut changes = c.changes.iter().peekable();
        let mut prev_v = 0.0;
        let mut k = 0;
        loop {
            while let Some(&&(at, target)) = changes.peek() {
                if at > k {
                    break;
                }
                tp.pos_cmd = target;
                changes.next();
            }
            tp.update(c.period, c.scale);
            prop_assert!(tp.curr_vel.abs() <= vmax * (1.0 + REL),
                "v {} over {} at {}", tp.curr_vel, vmax, k);
            prop_assert!((tp.curr_vel - prev_v).abs() <= dv * (1.0 + REL),
                "dv {} over {} at {}", tp.curr_vel - prev_v, dv, k);
            prev_v = tp.curr_vel;
            k += 1;
            if !tp.active && changes.peek().is_none() {
                break;
            }
            prop_assert!(k < budget(&c), "still moving after {} periods", k);
        }
        prop_assert_eq!(tp.curr_vel, 0.0);
        prop_assert!((tp.curr_pos - tp.pos_cmd).abs() <= tiny,
            "rests {} from target (dead band {})", tp.curr_pos - tp.pos_cmd, tiny);
    }

    #[test]
    fn rest_to_rest_moves_never_overshoot(c in case()) {
        let mut tp = SimpleTp {
            pos_cmd: c.first,
            max_vel: c.vel,
            max_acc: c.acc,
            enable: true,
            ..SimpleTp::default()
        };
        let tiny = SimpleTp::tiny_dp(c.acc, c.period);
        let up = c.first > 0.0;
        let mut last = 0.0;
        loop {
            tp.update(c.period, c.scale);
            if up {
                prop_assert!(tp.curr_pos >= last && tp.curr_pos <= c.first + tiny);
            } else {
                prop_assert!(tp.curr_pos <= last && tp.curr_pos >= c.first - tiny);
            }
            last = tp.curr_pos;
            if !tp.active {
                break;
            }
        }
    }

    /// The same through the controller: a joint jogged by random absolute
    /// and incremental jogs, retargeted mid-move, with a random SCALE.
    #[test]
    fn jogged_joints_respect_their_limits(
        vel in 0.1f64..20.0,
        acc in 5.0f64..2000.0,
        scale in 0.05f64..=1.0,
        jogs in prop::collection::vec((0usize..400, any::<bool>(), -1.0f64..1.0, 0.2f64..2.0), 1..6),
    ) {
        let kins = Arc::new(Trivkins::new("x", KinematicsType::Identity).unwrap());
        let mut m = MotionCore::new(MotionConfig { num_joints: 1, ..Default::default() }, kins);
        for c in [
            Command::JointActivate { joint: 0 },
            Command::SetJointPositionLimits { joint: 0, min: -50.0, max: 50.0 },
            Command::SetJointVelLimit { joint: 0, vel },
            Command::SetJointAccLimit { joint: 0, acc },
            Command::SetJointMaxFerror { joint: 0, ferror: 1e9 },
            Command::Scale { scale },
            Command::Enable,
        ] {
            m.command(&c).unwrap();
        }
        let period = 0.001;
        m.cycle(period); // the enable takes effect in the cycle
        let vmax = vel * scale;
        let mut jogs = jogs;
        jogs.sort_by_key(|j| j.0);
        let mut pending = jogs.into_iter().peekable();
        let mut prev_v = 0.0;
        let mut k = 0;
        loop {
            while let Some(&(at, abs, pos, jog_vel)) = pending.peek() {
                if at > k {
                    break;
                }
                let pos = pos * vmax;
                // A jog speed relative to the joint's (capped at it).
                let jog_vel = jog_vel * vel;
                let cmd = if abs {
                    Command::JogAbs { joint: 0, vel: jog_vel, pos }
                } else {
                    Command::JogIncr { joint: 0, vel: jog_vel * pos.signum(), offset: pos.abs() }
                };
                m.command(&cmd).unwrap();
                pending.next();
            }
            m.joint_inputs[0].motor_pos_fb = m.joint(0).motor_pos_cmd;
            m.cycle(period);
            let v = m.joint(0).vel_cmd;
            prop_assert!(v.abs() <= vmax * (1.0 + REL), "v {} over {}", v, vmax);
            prop_assert!((v - prev_v).abs() <= acc * period * (1.0 + REL));
            prev_v = v;
            k += 1;
            if m.in_position() && k > 1 && pending.peek().is_none() {
                break;
            }
            prop_assert!(k < 200_000);
        }
        let j = m.joint(0);
        prop_assert!(m.is_enabled());
        prop_assert!((j.pos_cmd - j.free_pos_cmd).abs() <= SimpleTp::tiny_dp(acc, period));
    }
}
