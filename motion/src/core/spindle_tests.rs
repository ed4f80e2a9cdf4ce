//! Tests of the spindle commands through the core: what the outputs
//! show, the override and its enable, inhibit, the brake, the stop on
//! disable, and the at-speed barrier of the feed move after a start.

use super::coord_tests::{at, line, xyz};
use crate::command::{Command, LineKind, ProbeType, Quantity, Reject};
use crate::test_support::T;

fn on(speed: f64, wait: bool) -> Command {
    Command::SpindleOn {
        spindle: 0,
        speed,
        wait,
    }
}

#[test]
fn a_start_drives_the_outputs_and_a_stop_brakes() {
    let mut s = xyz();
    assert_eq!(s.cmd(on(1000.0, false)), Err(Reject::NotEnabled));
    s.coord();
    s.cmd(on(-1200.0, false)).unwrap();
    s.cycle();
    let o = s.m.spindle_output(0);
    assert!(o.on && o.reverse && !o.forward && !o.brake, "{o:?}");
    assert_eq!((o.speed, o.cmd_rps), (-1200.0, -20.0));
    s.cmd(Command::SpindleOff { spindle: 0 }).unwrap();
    let o = s.m.spindle_output(0);
    assert!(!o.on && !o.forward && !o.reverse && o.brake, "{o:?}");
    assert_eq!((o.speed, o.cmd_rps), (0.0, 0.0));
    assert_eq!(
        s.cmd(Command::SpindleOff { spindle: 1 }),
        Err(Reject::NoSuchSpindle {
            spindle: 1,
            num_spindles: 1
        })
    );
    assert!(matches!(
        s.cmd(on(f64::NAN, false)),
        Err(Reject::BadValue {
            what: Quantity::SpindleSpeed,
            ..
        })
    ));
}

#[test]
fn the_override_applies_while_enabled_and_inhibit_holds_zero() {
    let mut s = xyz();
    s.coord();
    s.cmd(on(1000.0, false)).unwrap();
    s.cmd(Command::SpindleScale {
        spindle: -1,
        scale: 1.5,
    })
    .unwrap();
    assert_eq!(s.m.spindle_output(0).speed, 1500.0);
    // The command speed is the programmed one.
    assert!((s.m.spindle_output(0).cmd_rps - 1000.0 / 60.0).abs() < 1e-12);
    s.cmd(Command::SpindleScaleEnable { on: false }).unwrap();
    assert_eq!(s.m.spindle_output(0).speed, 1000.0);
    s.cmd(Command::SpindleScaleEnable { on: true }).unwrap();
    s.m.inputs.spindle_inhibit[0] = true;
    let o = s.m.spindle_output(0);
    assert!(o.on && o.forward);
    assert_eq!(o.speed, 0.0);
    s.m.inputs.spindle_inhibit[0] = false;
    // An override of 0 stops it, as LinuxCNC.
    s.cmd(Command::SpindleScale {
        spindle: 0,
        scale: 0.0,
    })
    .unwrap();
    assert!(!s.m.spindle_output(0).on);
}

#[test]
fn the_brake_commands_and_disable_stop_the_spindle() {
    let mut s = xyz();
    s.coord();
    s.cmd(on(500.0, false)).unwrap();
    s.cmd(Command::SpindleBrake {
        spindle: 0,
        on: true,
    })
    .unwrap();
    let o = s.m.spindle_output(0);
    assert!(!o.on && o.brake);
    s.cmd(Command::SpindleBrake {
        spindle: 0,
        on: false,
    })
    .unwrap();
    assert!(!s.m.spindle_output(0).brake);
    s.cmd(on(500.0, true)).unwrap();
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    let o = s.m.spindle_output(0);
    assert!(!o.on && o.brake && o.speed == 0.0, "{o:?}");
    assert!(!s.m.atspeed_next_feed());
}

#[test]
fn the_feed_move_after_a_start_waits_for_at_speed() {
    let mut s = xyz();
    s.coord();
    s.m.inputs.spindle_at_speed[0] = false;
    s.cmd(on(1000.0, true)).unwrap();
    assert!(s.m.atspeed_next_feed());
    // A rapid does not wait and does not take the barrier.
    s.cmd(Command::Line {
        end: at(1.0, 0.0, 0.0),
        vel: 0.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Traverse,
        id: 1,
    })
    .unwrap();
    assert!(s.m.atspeed_next_feed());
    s.cmd(line(2.0, 0.0, 5.0, 2)).unwrap();
    assert!(!s.m.atspeed_next_feed());
    for _ in 0..2000 {
        s.cycle();
    }
    // The rapid ran, the feed waits at its start.
    assert!((s.j(0).pos_cmd - 1.0).abs() < 1e-9, "{}", s.j(0).pos_cmd);
    let st = s.m.planner();
    assert!(st.waiting_for_atspeed && st.depth == 1, "{st:?}");
    s.m.inputs.spindle_at_speed[0] = true;
    s.settle(5000);
    assert!((s.j(0).pos_cmd - 2.0).abs() < 1e-9);
    assert!(!s.m.planner().waiting_for_atspeed);
    // Without the wait flag the next feed move goes at once.
    s.m.inputs.spindle_at_speed[0] = false;
    s.cmd(on(800.0, false)).unwrap();
    s.cmd(line(3.0, 0.0, 5.0, 3)).unwrap();
    s.settle(5000);
    assert!((s.j(0).pos_cmd - 3.0).abs() < 1e-9);
}

fn orient(angle: f64, mode: i32) -> Command {
    Command::SpindleOrient {
        spindle: 0,
        angle,
        mode,
    }
}

#[test]
fn m19_orients_until_is_oriented_locks_and_m3_cancels() {
    use crate::core::OrientState;
    let mut s = xyz();
    assert_eq!(s.cmd(orient(90.0, 1)), Err(Reject::NotEnabled));
    s.coord();
    s.cmd(on(1000.0, false)).unwrap();
    s.cmd(orient(90.0, 1)).unwrap();
    s.cycle();
    let o = s.m.spindle_output(0);
    assert!(o.orient && !o.locked && !o.on && !o.brake, "{o:?}");
    assert_eq!((o.orient_angle, o.orient_mode), (90.0, 1));
    assert_eq!(s.m.spindle(0).orient, OrientState::InProgress);
    s.m.inputs.spindle_is_oriented[0] = true;
    s.cycle();
    let o = s.m.spindle_output(0);
    assert!(!o.orient && o.locked && o.brake, "{o:?}");
    assert_eq!(s.m.spindle(0).orient, OrientState::Complete);
    s.cmd(on(500.0, false)).unwrap();
    let o = s.m.spindle_output(0);
    assert!(!o.orient && !o.locked && o.on, "{o:?}");
    assert_eq!(s.m.spindle(0).orient, OrientState::None);
    assert!(matches!(
        s.cmd(orient(f64::INFINITY, 0)),
        Err(Reject::BadValue {
            what: Quantity::OrientAngle,
            ..
        })
    ));
}

#[test]
fn an_orient_fault_fails_the_orientation_with_an_error() {
    use crate::core::OrientState;
    let mut s = xyz();
    s.coord();
    s.events();
    s.cmd(orient(45.0, 0)).unwrap();
    s.m.inputs.spindle_orient_fault[0] = 7;
    s.cycle();
    assert_eq!(s.m.spindle(0).orient, OrientState::Faulted);
    assert_eq!(s.m.spindle(0).orient_fault, 7);
    assert!(!s.m.spindle_output(0).orient);
    assert!(s.m.error());
    assert_eq!(
        s.events(),
        [crate::Event::SpindleOrientFault {
            spindle: 0,
            fault: 7
        }]
    );
    assert_eq!(
        crate::Event::SpindleOrientFault {
            spindle: 0,
            fault: 7
        }
        .to_string(),
        "fault 7 during orient in progress"
    );
}

#[test]
fn feed_per_revolution_follows_the_spindle_speed_feedback() {
    let mut s = xyz();
    s.coord();
    s.cmd(Command::SetFeedPerRev {
        spindle: 0,
        per_rev: 0.5,
    })
    .unwrap();
    // The programmed speed of the move is not used: 0.5 per revolution
    // at 10 rev/s is 5 u/s.
    s.cmd(line(40.0, 0.0, 1.0, 1)).unwrap();
    s.m.inputs.spindle_speed_in[0] = 10.0;
    s.run(300);
    assert!((s.m.planner().current_vel - 5.0).abs() < 1e-9);
    // Turning in reverse counts the same; slower, slower feed.
    s.m.inputs.spindle_speed_in[0] = -4.0;
    s.run(300);
    assert!((s.m.planner().current_vel - 2.0).abs() < 1e-9);
    // No spindle speed, no feed.
    s.m.inputs.spindle_speed_in[0] = 0.0;
    s.run(300);
    assert_eq!(s.m.planner().current_vel, 0.0);
    // Faster than the axes allow: held to their limit (10 u/s).
    s.m.inputs.spindle_speed_in[0] = 100.0;
    s.run(300);
    assert!((s.m.planner().current_vel - 10.0).abs() < 1e-9);
    s.run_queue(100_000);
    // Off again: the next move runs at its programmed speed.
    s.cmd(Command::SetFeedPerRev {
        spindle: 0,
        per_rev: 0.0,
    })
    .unwrap();
    s.cmd(line(0.0, 0.0, 3.0, 2)).unwrap();
    s.run(300);
    assert!((s.m.planner().current_vel - 3.0).abs() < 1e-9);
    assert_eq!(
        s.cmd(Command::SetFeedPerRev {
            spindle: -1,
            per_rev: 1.0
        }),
        Err(Reject::NoSuchSpindle {
            spindle: -1,
            num_spindles: 1
        })
    );
    assert!(matches!(
        s.cmd(Command::SetFeedPerRev {
            spindle: 0,
            per_rev: -1.0
        }),
        Err(Reject::BadValue {
            what: Quantity::FeedPerRev,
            ..
        })
    ));
}

/// LinuxCNC's interpreter refuses G38.n under G95 ("Cannot probe with
/// feed per rev mode"), and its probe moves carry no feed mode: a probe
/// queued while feed per revolution is set moves at its own speed (the
/// program's F per minute), whatever the spindle turns; the feed move
/// after it follows the spindle again.
#[test]
fn a_probe_move_under_feed_per_revolution_keeps_its_speed_per_minute() {
    let mut s = xyz();
    s.coord();
    s.cmd(Command::SetFeedPerRev {
        spindle: 0,
        per_rev: 0.5,
    })
    .unwrap();
    s.m.inputs.spindle_speed_in[0] = 10.0;
    // F120 per minute: 2 u/s, not 0.5 per revolution at 10 rev/s (5 u/s).
    s.cmd(Command::Probe {
        end: at(0.0, 0.0, -20.0),
        vel: 2.0,
        probe: ProbeType::G38_3,
        id: 1,
    })
    .unwrap();
    s.run(300);
    assert!((s.m.planner().current_vel - 2.0).abs() < 1e-9);
    // Without spindle speed the probe still moves.
    s.m.inputs.spindle_speed_in[0] = 0.0;
    s.run(300);
    assert!((s.m.planner().current_vel - 2.0).abs() < 1e-9);
    s.run_queue(100_000);
    s.m.inputs.spindle_speed_in[0] = 10.0;
    s.cmd(line(30.0, 0.0, 1.0, 2)).unwrap();
    s.run(300);
    assert!((s.m.planner().current_vel - 5.0).abs() < 1e-9);
}

#[test]
fn constant_surface_speed_follows_the_x_radius_up_to_the_limit() {
    let mut s = xyz();
    s.coord();
    let css = |factor| Command::SpindleCss {
        spindle: 0,
        factor,
        x_offset: -5.0,
    };
    s.cmd(css(1000.0)).unwrap();
    s.cmd(on(-800.0, false)).unwrap();
    s.cycle();
    // X 0 is 5 from the spindle axis: 200 rpm, in reverse.
    assert!((s.m.spindle_output(0).speed + 200.0).abs() < 1e-9);
    s.cmd(line(15.0, 0.0, 10.0, 1)).unwrap();
    s.run_queue(100_000);
    assert!((s.m.spindle_output(0).speed + 50.0).abs() < 1e-9);
    // On the axis: the limit (the SPINDLE_ON speed).
    s.cmd(line(-5.0, 0.0, 10.0, 2)).unwrap();
    s.run_queue(100_000);
    assert_eq!(s.m.spindle_output(0).speed, -800.0);
    assert!((s.m.spindle_output(0).cmd_rps + 800.0 / 60.0).abs() < 1e-9);
    // Off: the SPINDLE_ON speed.
    s.cmd(css(0.0)).unwrap();
    s.cmd(line(15.0, 0.0, 10.0, 3)).unwrap();
    s.run_queue(100_000);
    assert_eq!(s.m.spindle_output(0).speed, -800.0);
    assert!(matches!(
        s.cmd(css(f64::NAN)),
        Err(Reject::BadValue {
            what: Quantity::SurfaceSpeed,
            ..
        })
    ));
}

/// SET_SPINDLESYNC and RIGID_TAP through the core: their checks, the
/// `index-enable` the controller sets for the start of a G33 move, and a
/// rigid tap reversing the commanded spindle (its direction outputs
/// follow) and restoring it.
#[test]
fn spindle_sync_arms_the_index_and_a_rigid_tap_reverses_the_spindle() {
    let mut s = xyz();
    s.coord();
    let sync = |spindle, per_rev| Command::SpindleSync {
        spindle,
        per_rev,
        velocity_mode: false,
    };
    assert!(matches!(
        s.cmd(sync(-1, 1.0)),
        Err(Reject::NoSuchSpindle { spindle: -1, .. })
    ));
    assert!(matches!(
        s.cmd(sync(0, -1.0)),
        Err(Reject::BadValue {
            what: Quantity::FeedPerRev,
            ..
        })
    ));
    let tap = Command::RigidTap {
        end: at(0.0, 0.0, -5.0),
        vel: 5.0,
        scale: 1.0,
        id: 3,
    };
    assert_eq!(s.cmd(tap), Err(Reject::RigidTapNotSynchronised));
    // A G33 move: index-enable is set once, and nothing moves until it
    // clears.
    s.cmd(on(600.0, false)).unwrap();
    s.cmd(sync(0, 0.5)).unwrap();
    s.cmd(Command::Line {
        end: at(0.0, 0.0, -2.0),
        vel: 5.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id: 1,
    })
    .unwrap();
    s.cmd(sync(0, 0.0)).unwrap();
    s.m.inputs.spindle_speed_in[0] = 10.0;
    s.cycle();
    assert!(s.m.spindle_index_arm(0));
    s.m.inputs.spindle_index_enable[0] = true;
    for _ in 0..20 {
        s.cycle();
        assert!(!s.m.spindle_index_arm(0));
        assert_eq!(s.j(2).pos_cmd, 0.0);
    }
    // The index: revs restart at 0 and count on at 10 rev/s.
    s.m.inputs.spindle_index_enable[0] = false;
    let mut revs = 0.0;
    for _ in 0..2000 {
        revs += 10.0 * T;
        s.m.inputs.spindle_revs[0] = revs;
        s.cycle();
        if s.m.in_position() {
            break;
        }
    }
    assert_eq!(s.j(2).pos_cmd, -2.0);
    // A rigid tap: reversed at the depth (twice as fast), forward again
    // at the top; the direction outputs follow.
    s.cmd(sync(0, 0.5)).unwrap();
    s.cmd(Command::RigidTap {
        end: at(0.0, 0.0, -4.0),
        vel: 5.0,
        scale: 2.0,
        id: 3,
    })
    .unwrap();
    s.cmd(sync(0, 0.0)).unwrap();
    let mut rps = 10.0;
    let mut speeds = vec![s.m.spindle(0).speed];
    let mut reverse_seen = false;
    for _ in 0..20_000 {
        // The spindle follows its command at 200 rev/s².
        let want = s.m.spindle(0).speed / 60.0;
        rps += (want - rps).clamp(-200.0 * T, 200.0 * T);
        revs += rps * T;
        s.m.inputs.spindle_revs[0] = revs;
        s.cycle();
        let speed = s.m.spindle(0).speed;
        if speeds.last() != Some(&speed) {
            speeds.push(speed);
        }
        reverse_seen |= s.m.spindle_output(0).reverse;
        if s.m.in_position() {
            break;
        }
    }
    assert_eq!(speeds, [600.0, -1200.0, 600.0]);
    assert!(reverse_seen && s.m.spindle_output(0).forward);
    assert_eq!(s.j(2).pos_cmd, -2.0, "back where it started");
}
