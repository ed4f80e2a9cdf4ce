//! Tests of coordinated mode through the core: queueing and its checks,
//! joint limits taking part in the planning, probing, pause/step/abort by
//! command, disable, the soft-limit stop, the planner type, and screw
//! compensation and backlash on the motor command. Each joint's motor
//! follows its command one period later.

use super::*;
use crate::command::{Command, LineKind, ProbeType, Quantity, Reject, TermCond};
use crate::events::Event;
use crate::kins::trivkins::Trivkins;
use crate::test_support::{Sim, T};

/// Three trivkins joints X Y Z: joints ±100, 10 u/s, 100 u/s²; axes ±50,
/// 10 u/s, 100 u/s².
pub(super) fn xyz() -> Sim {
    let kins = Arc::new(Trivkins::new("xyz", KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(MotionConfig::default(), kins);
    crate::test_support::configure_test_joints(&mut m);
    crate::test_support::configure_test_axes(&mut m, 50.0);
    Sim::new(m)
}

pub(super) fn at(x: f64, y: f64, z: f64) -> Pose {
    let mut p = Pose::ZERO;
    p.0[0] = x;
    p.0[1] = y;
    p.0[2] = z;
    p
}

pub(super) fn line(x: f64, y: f64, vel: f64, id: i32) -> Command {
    Command::Line {
        end: at(x, y, 0.0),
        vel,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id,
    }
}

impl Sim {
    /// Enabled and in coordinated mode.
    pub(super) fn coord(&mut self) {
        self.enable();
        self.cmd(Command::Coord).unwrap();
        assert_eq!(self.m.state(), MotionState::Coord);
    }

    /// Runs until the queue is done; returns each period's joint commands.
    pub(super) fn run_queue(&mut self, limit: usize) -> Vec<[f64; 3]> {
        let mut out = Vec::new();
        for _ in 0..limit {
            self.cycle();
            out.push([self.j(0).pos_cmd, self.j(1).pos_cmd, self.j(2).pos_cmd]);
            if self.m.in_position() {
                return out;
            }
        }
        panic!("queue not done after {limit} periods");
    }
}

/// Largest |velocity| and |acceleration| of each joint.
pub(super) fn extremes(p: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut v = [0.0f64; 3];
    let mut a = [0.0f64; 3];
    for j in 0..3 {
        let vs: Vec<f64> = p.windows(2).map(|w| (w[1][j] - w[0][j]) / T).collect();
        for w in vs.windows(2) {
            a[j] = a[j].max(((w[1] - w[0]) / T).abs());
        }
        v[j] = vs.iter().fold(0.0, |m, x| m.max(x.abs()));
    }
    (v, a)
}

#[test]
fn moves_are_queued_only_in_coordinated_mode_and_enabled() {
    let mut s = xyz();
    assert_eq!(s.cmd(line(1.0, 0.0, 5.0, 1)), Err(Reject::NotEnabled));
    s.enable();
    assert_eq!(s.cmd(line(1.0, 0.0, 5.0, 1)), Err(Reject::NotCoordMode));
    s.cmd(Command::Coord).unwrap();
    assert_eq!(
        s.cmd(line(1.0, 0.0, 0.0, 1)),
        Err(Reject::BadVelocity { vel: 0.0 })
    );
    assert_eq!(s.cmd(line(1.0, 0.0, 5.0, 10)), Ok(()));
    s.cycle();
    assert!(!s.m.in_position());
    assert_eq!(s.m.planner().exec_id, 10);
    assert_eq!(s.m.planner().depth, 1);
    let p = s.run_queue(10_000);
    assert_eq!(p.last().unwrap()[0], 1.0);
    assert_eq!(s.j(0).pos_cmd, 1.0, "ends exactly");
    // Rapids ignore the velocity.
    s.cmd(Command::Line {
        end: at(0.0, 2.0, 0.0),
        vel: 0.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Traverse,
        id: 11,
    })
    .unwrap();
    s.run_queue(10_000);
    assert_eq!((s.j(0).pos_cmd, s.j(1).pos_cmd), (0.0, 2.0));
}

#[test]
fn moves_beyond_axis_or_joint_limits_or_on_a_limit_switch_are_refused() {
    let mut s = xyz();
    s.coord();
    assert_eq!(
        s.cmd(line(51.0, 0.0, 5.0, 1)),
        Err(Reject::OutsideAxisLimits {
            axis: 0,
            value: 51.0,
            min: -50.0,
            max: 50.0
        })
    );
    // An arc from (49, 0) about (45, 0) to (41, 0) bulges to y = ±4 but
    // stays in X; one about (47, 0) ending at (45, 0) passes x = 49 only.
    s.cmd(line(45.0, 0.0, 10.0, 1)).unwrap();
    s.run_queue(100_000);
    let bulge = Command::Circle {
        end: at(45.0, 0.0, 0.0),
        center: [47.5, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        turns: 0,
        vel: 5.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        id: 2,
    };
    // Radius 2.5 about 47.5: reaches x = 50 exactly (allowed).
    assert_eq!(s.cmd(bulge), Ok(()));
    s.run_queue(100_000);
    let beyond = Command::Circle {
        end: at(45.0, 0.0, 0.0),
        center: [48.0, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        turns: 0,
        vel: 5.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        id: 3,
    };
    assert!(matches!(
        s.cmd(beyond),
        Err(Reject::OutsideAxisLimits { axis: 0, value, .. }) if (value - 51.0).abs() < 1e-9
    ));
    // Joint limits narrower than the axis's.
    s.cmd(Command::SetJointPositionLimits {
        joint: 1,
        min: -10.0,
        max: 10.0,
    })
    .unwrap();
    assert_eq!(
        s.cmd(line(45.0, 20.0, 5.0, 4)),
        Err(Reject::OutsideJointLimits {
            joint: 1,
            value: 20.0,
            min: -10.0,
            max: 10.0
        })
    );
    // A switch seen between two cycles (the next cycle disables).
    s.m.joints[2].phl = true;
    assert_eq!(
        s.cmd(line(40.0, 0.0, 5.0, 5)),
        Err(Reject::HardLimitTripped { joint: 2 })
    );
}

#[test]
fn joint_limits_below_the_axis_limits_hold_the_move() {
    let mut s = xyz();
    s.cmd(Command::SetJointVelLimit { joint: 0, vel: 4.0 })
        .unwrap();
    s.cmd(Command::SetJointAccLimit {
        joint: 0,
        acc: 40.0,
    })
    .unwrap();
    s.coord();
    s.cmd(Command::SetTermCond {
        cond: TermCond::Stop,
        tolerance: 0.0,
    })
    .unwrap();
    s.cmd(line(10.0, 0.0, 10.0, 1)).unwrap();
    let p = s.run_queue(100_000);
    let (v, a) = extremes(&p);
    assert!((v[0] - 4.0).abs() < 1e-9, "joint speed {}", v[0]);
    assert!(a[0] <= 40.0 + 1e-6 && a[0] > 39.0, "joint accel {}", a[0]);
}

#[test]
fn disable_drops_the_queue_at_once() {
    let mut s = xyz();
    s.coord();
    s.cmd(line(10.0, 0.0, 10.0, 1)).unwrap();
    s.run(200);
    assert!(!s.m.in_position());
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert_eq!(s.m.planner().depth, 0);
    assert!(s.m.in_position());
    // Enabled again, coordinated mode resumes empty where the joints are.
    s.enable();
    assert_eq!(s.m.state(), MotionState::Coord);
    s.run(5);
    assert!(s.m.in_position());
    let x = s.j(0).pos_cmd;
    s.cmd(line(x + 1.0, 0.0, 5.0, 2)).unwrap();
    s.run_queue(10_000);
    assert!((s.j(0).pos_cmd - (x + 1.0)).abs() < 1e-12);
}

#[test]
fn pause_step_resume_and_abort_by_command() {
    let mut s = xyz();
    s.coord();
    s.cmd(Command::SetTermCond {
        cond: TermCond::Blend,
        tolerance: 0.01,
    })
    .unwrap();
    for (k, (x, y)) in [(2.0, 0.0), (2.0, 2.0), (0.0, 2.0)].into_iter().enumerate() {
        s.cmd(line(x, y, 5.0, k as i32 + 1)).unwrap();
    }
    assert_eq!(s.cmd(Command::Step), Err(Reject::NotPaused));
    s.cmd(Command::Pause).unwrap();
    s.run(300);
    assert_eq!(s.m.planner().current_vel, 0.0);
    assert!(s.m.planner().paused);
    assert_eq!(s.cmd(Command::Step), Ok(()));
    while !s.m.planner().paused || s.m.planner().current_vel > 0.0 {
        s.cycle();
    }
    let id = s.m.planner().exec_id;
    s.cmd(Command::Resume).unwrap();
    s.run(100);
    assert!(s.m.planner().exec_id >= id);
    s.cmd(Command::Abort).unwrap();
    let p = s.run_queue(10_000);
    let (_, a) = extremes(&p);
    assert!(a.iter().all(|&x| x <= 100.0 + 1e-6), "{a:?}");
    assert_eq!(s.m.planner().depth, 0);
    assert!(s.j(0).pos_cmd < 2.0 + 1e-12 || s.j(1).pos_cmd < 2.0);
}

#[test]
fn the_feed_override_scales_and_stops_coordinated_moves() {
    let mut s = xyz();
    s.coord();
    s.cmd(Command::FeedScale { scale: 0.5 }).unwrap();
    s.cmd(line(20.0, 0.0, 8.0, 1)).unwrap();
    s.run(500);
    assert!((s.m.planner().current_vel - 4.0).abs() < 1e-9);
    assert_eq!(
        s.cmd(Command::FeedScale { scale: -1.0 }),
        Err(Reject::BadValue {
            what: Quantity::Scale,
            value: -1.0
        })
    );
    s.m.inputs.feed_hold = true;
    s.run(200);
    assert_eq!(s.m.planner().current_vel, 0.0);
    // Feed hold disabled (M53 P0) for the next moves only: this one holds.
    s.cmd(Command::FeedHoldEnable { on: false }).unwrap();
    s.run(10);
    assert_eq!(s.m.planner().current_vel, 0.0);
    s.m.inputs.feed_hold = false;
    s.run_queue(100_000);
}

#[test]
fn g38_2_latches_the_feedback_where_the_probe_trips_and_stops() {
    let mut s = xyz();
    s.coord();
    s.cmd(Command::Probe {
        end: at(10.0, 0.0, 0.0),
        vel: 2.0,
        probe: ProbeType::G38_2,
        id: 5,
    })
    .unwrap();
    let mut tripped_at = None;
    for _ in 0..100_000 {
        s.cycle();
        if s.m.probing() {
            assert!(!s.m.probe_result().0);
        }
        if tripped_at.is_none() && s.j(0).pos_fb >= 3.0 {
            s.m.inputs.probe_input = true;
            tripped_at = Some(s.j(0).pos_fb);
            s.cycle();
            let (tripped, pos) = s.m.probe_result();
            assert!(tripped);
            // The feedback of the cycle that saw the input.
            assert_eq!(pos.0[0], s.m.carte_pos_fb().0 .0[0]);
            assert!(pos.0[0] >= tripped_at.unwrap());
        }
        if s.m.in_position() {
            break;
        }
    }
    assert!(s.j(0).pos_cmd < 10.0, "stopped before the end");
    assert!(!s.m.error());
    // Already tripped: a new G38.2 is refused, G38.3 is not.
    let probe = |p| Command::Probe {
        end: at(0.0, 0.0, 0.0),
        vel: 2.0,
        probe: p,
        id: 6,
    };
    assert_eq!(
        s.cmd(probe(ProbeType::G38_2)),
        Err(Reject::ProbeAlreadyThere {
            trip_on_clear: false
        })
    );
    assert_eq!(s.cmd(probe(ProbeType::G38_3)), Ok(()));
    assert!(!s.m.probe_result().0, "PROBE clears the tripped flag");
}

#[test]
fn a_probe_move_without_contact_is_an_error_unless_g38_3() {
    let mut s = xyz();
    s.coord();
    s.events();
    s.cmd(Command::Probe {
        end: at(1.0, 0.0, 0.0),
        vel: 5.0,
        probe: ProbeType::G38_2,
        id: 1,
    })
    .unwrap();
    s.run_queue(10_000);
    s.cycle();
    assert!(s.m.error());
    assert_eq!(
        s.events(),
        [Event::ProbeNoContact {
            trip_on_clear: false
        }]
    );
    let (tripped, pos) = s.m.probe_result();
    assert!(!tripped && (pos.0[0] - 1.0).abs() < 0.01, "{pos:?}");
    s.cmd(Command::Probe {
        end: at(2.0, 0.0, 0.0),
        vel: 5.0,
        probe: ProbeType::G38_3,
        id: 2,
    })
    .unwrap();
    assert!(!s.m.error(), "queueing clears the error");
    s.run_queue(10_000);
    s.cycle();
    assert!(!s.m.error());
    assert!(s.events().is_empty());
}

#[test]
fn the_probe_tripping_during_an_ordinary_move_aborts_it() {
    let mut s = xyz();
    s.coord();
    s.cmd(line(10.0, 0.0, 5.0, 1)).unwrap();
    s.run(100);
    s.m.inputs.probe_input = true;
    s.run_queue(10_000);
    assert!(s.j(0).pos_cmd < 10.0);
    assert!(s.m.error());
    assert!(s.events().contains(&Event::ProbeTrippedDuringMove));
}

#[test]
fn a_joint_leaving_its_soft_limits_in_coord_stops_the_queue() {
    let mut s = xyz();
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.coord();
    s.cmd(line(20.0, 0.0, 10.0, 1)).unwrap();
    s.run(300);
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -100.0,
        max: 1.0,
    })
    .unwrap();
    s.run_queue(10_000);
    assert!(s.j(0).pos_cmd < 20.0, "stopped along the path");
    assert!(s.m.error());
}

#[test]
fn the_s_curve_planner_needs_a_jerk_limit() {
    let mut s = xyz();
    s.cmd(Command::SetJerkLimit { jerk: 0.5 }).unwrap();
    assert_eq!(
        s.cmd(Command::SetPlannerType { planner: 1 }),
        Err(Reject::NeedsJerkLimit { jerk: 0.5 })
    );
    assert!(matches!(
        s.cmd(Command::SetPlannerType { planner: 7 }),
        Err(Reject::BadValue {
            what: Quantity::PlannerType,
            ..
        })
    ));
    s.cmd(Command::SetJerkLimit { jerk: 5000.0 }).unwrap();
    s.cmd(Command::SetPlannerType { planner: 1 }).unwrap();
    assert_eq!(s.m.planner().planner, crate::tp::PlannerType::SCurve);
    s.coord();
    s.cmd(line(3.0, 1.0, 5.0, 1)).unwrap();
    s.run_queue(100_000);
    assert_eq!((s.j(0).pos_cmd, s.j(1).pos_cmd), (3.0, 1.0));
}

#[test]
fn a_comp_table_shifts_the_motor_command_by_direction() {
    let mut s = xyz();
    for (n, f, r) in [
        (-1.0, 0.005, -0.005),
        (0.0, 0.002, -0.003),
        (1.0, 0.003, -0.004),
    ] {
        s.cmd(Command::SetJointComp {
            joint: 0,
            nominal: n,
            forward: f,
            reverse: r,
        })
        .unwrap();
    }
    assert_eq!(
        s.cmd(Command::SetJointComp {
            joint: 0,
            nominal: 0.5,
            forward: 0.0,
            reverse: 0.0
        }),
        Err(Reject::CompNotIncreasing {
            joint: 0,
            nominal: 0.5,
            previous: 1.0
        })
    );
    s.coord();
    assert_eq!(
        s.cmd(Command::ClearJointComp { joint: 0 }),
        Err(Reject::MustBeDisabled)
    );
    // Forward to 0.5, then back to -0.5: once the take-up has settled the
    // motor command is the position plus the table's trim there.
    s.cmd(line(0.5, 0.0, 2.0, 1)).unwrap();
    s.run_queue(100_000);
    s.run(200);
    let j = s.j(0);
    assert!(
        (j.backlash_filt - 0.0025).abs() < 1e-12,
        "{}",
        j.backlash_filt
    );
    assert!((j.motor_pos_cmd - 0.5025).abs() < 1e-12);
    s.cmd(line(-0.5, 0.0, 2.0, 2)).unwrap();
    s.run_queue(100_000);
    s.run(200);
    let j = s.j(0);
    assert!(
        (j.backlash_filt + 0.004).abs() < 1e-12,
        "{}",
        j.backlash_filt
    );
    assert!((j.motor_pos_cmd - (-0.504)).abs() < 1e-12);
}
