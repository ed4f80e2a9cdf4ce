//! Tests of the start-up settings task sends through the core: each
//! move's own speed and acceleration caps (SET_LINE's `ini_maxvel` and
//! `acc`) and a rapid's speed, SET_NUM_JOINTS, SET_NUM_SPINDLES,
//! SET_SPINDLE_PARAMS, SET_OFFSET, SET_VEL and SETUP_ARC_BLENDS.

use super::coord_tests::{at, extremes, xyz};
use crate::command::{Command, LineKind, Quantity, Reject};
use crate::kins::Pose;

/// A move along X to `x` of `kind` at `vel` with caps `ini_maxvel`, `acc`.
fn capped(x: f64, kind: LineKind, vel: f64, ini_maxvel: f64, acc: f64) -> Command {
    Command::Line {
        end: at(x, 0.0, 0.0),
        vel,
        ini_maxvel,
        acc,
        kind,
        id: 1,
    }
}

/// The largest X velocity and acceleration of `cmd` run alone from rest.
fn x_extremes(cmd: Command, feed_scale: f64) -> (f64, f64) {
    let mut s = xyz();
    s.coord();
    s.cmd(Command::SetMaxFeedOverride { scale: 2.0 }).unwrap();
    s.cmd(Command::FeedScale { scale: feed_scale }).unwrap();
    s.cmd(cmd).unwrap();
    let (v, a) = extremes(&s.run_queue(100_000));
    (v[0], a[0])
}

#[test]
fn a_moves_own_caps_hold_its_speed_and_acceleration_even_with_the_override() {
    // The axes allow 10 u/s and 100 u/s². A lone move under G64 may
    // still be blended: half of either acceleration, as LinuxCNC halves
    // a move's own maxaccel.
    let (v, a) = x_extremes(capped(5.0, LineKind::Feed, 8.0, 0.0, 0.0), 1.0);
    assert!(
        (v - 8.0).abs() < 1e-6 && a > 45.0 && a <= 50.0 + 1e-6,
        "{v} {a}"
    );
    let (v, a) = x_extremes(capped(5.0, LineKind::Feed, 8.0, 2.0, 20.0), 1.0);
    assert!(v <= 2.0 + 1e-9 && v > 1.99, "{v}");
    assert!(a <= 10.0 + 1e-6 && a > 9.5, "{a}");
    let (v, _) = x_extremes(capped(5.0, LineKind::Feed, 1.5, 2.0, 0.0), 2.0);
    assert!(
        v <= 2.0 + 1e-9 && v > 1.99,
        "the override stops at the cap: {v}"
    );
}

#[test]
fn a_rapid_goes_at_the_speed_task_gave_or_as_fast_as_the_limits_allow() {
    let (v, _) = x_extremes(capped(5.0, LineKind::Traverse, 3.0, 3.0, 0.0), 1.0);
    assert!((v - 3.0).abs() < 1e-6, "{v}");
    let (v, _) = x_extremes(capped(5.0, LineKind::Traverse, 0.0, 0.0, 0.0), 1.0);
    assert!((v - 10.0).abs() < 1e-6, "{v}");
}

#[test]
fn bad_caps_and_rapid_speeds_are_refused() {
    let mut s = xyz();
    s.coord();
    let bad = [
        (
            capped(1.0, LineKind::Feed, 1.0, f64::NAN, 0.0),
            Quantity::MoveSpeedCap,
        ),
        (
            capped(1.0, LineKind::Feed, 1.0, 0.0, -1.0),
            Quantity::MoveAccelerationCap,
        ),
        (
            capped(1.0, LineKind::Traverse, 0.0, f64::INFINITY, 0.0),
            Quantity::MoveSpeedCap,
        ),
    ];
    for (cmd, what) in bad {
        assert!(
            matches!(s.cmd(cmd), Err(Reject::BadValue { what: w, .. }) if w == what),
            "{cmd:?}"
        );
    }
    assert_eq!(
        s.cmd(capped(1.0, LineKind::Traverse, -2.0, 0.0, 0.0)),
        Err(Reject::BadVelocity { vel: -2.0 })
    );
    assert_eq!(s.m.planner().depth, 0);
}

#[test]
fn set_num_joints_limits_the_joints_commands_name() {
    let mut s = xyz();
    for n in [0, 4, -1] {
        assert_eq!(
            s.cmd(Command::SetNumJoints { joints: n }),
            Err(Reject::BadJointCount {
                count: n,
                loaded: 3
            })
        );
    }
    s.cmd(Command::SetNumJoints { joints: 2 }).unwrap();
    assert_eq!(s.m.joints_in_use(), 2);
    assert!(!s.j(2).active);
    assert_eq!(
        s.cmd(Command::JointActivate { joint: 2 }),
        Err(Reject::NoSuchJoint {
            joint: 2,
            num_joints: 2
        })
    );
    s.cmd(Command::SetNumJoints { joints: 3 }).unwrap();
    s.cmd(Command::JointActivate { joint: 2 }).unwrap();
    s.enable();
    assert_eq!(
        s.cmd(Command::SetNumJoints { joints: 3 }),
        Err(Reject::MustBeDisabled)
    );
}

#[test]
fn spindle_count_and_speed_range() {
    let mut s = xyz();
    assert_eq!(
        s.cmd(Command::SetNumSpindles { spindles: 2 }),
        Err(Reject::BadSpindleCount {
            count: 2,
            loaded: 1
        })
    );
    s.cmd(Command::SetNumSpindles { spindles: 1 }).unwrap();
    let params = |max_pos, min_pos, max_neg, min_neg| Command::SetSpindleParams {
        spindle: 0,
        max_pos,
        min_pos,
        max_neg,
        min_neg,
    };
    s.cmd(params(3000.0, 100.0, -2000.0, -200.0)).unwrap();
    for (bad, low, high) in [
        (params(100.0, 3000.0, -1.0, 0.0), 3000.0, 100.0),
        (params(100.0, 0.0, -1.0, 5.0), -1.0, 5.0),
    ] {
        assert_eq!(s.cmd(bad), Err(Reject::SpindleRangeReversed { low, high }));
    }
    assert!(matches!(
        s.cmd(params(f64::NAN, 0.0, -1.0, 0.0)),
        Err(Reject::BadValue {
            what: Quantity::SpindleSpeedLimit,
            ..
        })
    ));
    s.coord();
    for (asked, got) in [
        (5000.0, 3000.0),
        (50.0, 100.0),
        (-5000.0, -2000.0),
        (-10.0, -200.0),
        (1500.0, 1500.0),
    ] {
        s.cmd(Command::SpindleOn {
            spindle: 0,
            speed: asked,
            wait: false,
        })
        .unwrap();
        assert_eq!(s.m.spindle_output(0).speed, got, "{asked}");
    }
}

#[test]
fn the_tool_offset_is_kept_for_the_tooloffset_pins() {
    let mut s = xyz();
    let offset = Pose([0.0, 0.0, 1.25, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5]);
    s.cmd(Command::SetToolOffset { offset }).unwrap();
    assert_eq!(s.m.tool_offset(), offset);
    let mut bad = offset;
    bad.0[3] = f64::INFINITY;
    assert!(matches!(
        s.cmd(Command::SetToolOffset { offset: bad }),
        Err(Reject::BadValue {
            what: Quantity::ToolOffset,
            ..
        })
    ));
    assert_eq!(s.m.tool_offset(), offset);
}

#[test]
fn set_vel_is_kept_by_the_planner_and_limits_no_move() {
    let mut s = xyz();
    s.cmd(Command::SetVel {
        vel: 0.0,
        ini_maxvel: 1.2,
    })
    .unwrap();
    assert_eq!(s.m.tp.traj_vel(), (0.0, 1.2));
    assert!(matches!(
        s.cmd(Command::SetVel {
            vel: -1.0,
            ini_maxvel: 1.2
        }),
        Err(Reject::BadValue {
            what: Quantity::TrajVelocity,
            ..
        })
    ));
    s.coord();
    s.cmd(capped(5.0, LineKind::Feed, 8.0, 0.0, 0.0)).unwrap();
    let (v, _) = extremes(&s.run_queue(100_000));
    assert!((v[0] - 8.0).abs() < 1e-6, "{v:?}");
}

/// The closest the path of two moves meeting at a right angle at (1, 0)
/// comes to the corner.
fn corner_miss(blends: bool) -> f64 {
    let mut s = xyz();
    s.cmd(Command::SetupArcBlends {
        enable: blends,
        fallback: false,
        depth: 50,
        gap_cycles: 4,
        ramp_freq: 100.0,
    })
    .unwrap();
    s.coord();
    s.cmd(super::coord_tests::line(1.0, 0.0, 5.0, 1)).unwrap();
    s.cmd(super::coord_tests::line(1.0, 1.0, 5.0, 2)).unwrap();
    s.run_queue(100_000)
        .iter()
        .map(|p| ((p[0] - 1.0).powi(2) + p[1].powi(2)).sqrt())
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn without_arc_blends_a_corner_is_not_rounded() {
    assert!(corner_miss(true) > 1e-3);
    assert!(corner_miss(false) < 1e-9);
    let mut s = xyz();
    let bad = Command::SetupArcBlends {
        enable: true,
        fallback: false,
        depth: -1,
        gap_cycles: 4,
        ramp_freq: 100.0,
    };
    assert!(matches!(
        s.cmd(bad),
        Err(Reject::BadValue {
            what: Quantity::ArcBlendSetting,
            ..
        })
    ));
}
