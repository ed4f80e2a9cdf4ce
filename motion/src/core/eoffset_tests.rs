//! Tests of the external axis offsets through the core: added to
//! coordinated and teleop motion within their share of the limits, the
//! planned moves kept to the rest, the soft limits, machine off and on,
//! mode changes and the ratio command. Each joint's motor follows its
//! command one period later.

use super::coord_tests::{at, xyz};
use super::*;
use crate::command::{Command, LineKind, Quantity, Reject};
use crate::eoffset::EoffsetInputs;
use crate::events::Event;
use crate::test_support::{Sim, T};

const Z: usize = 2;

impl Sim {
    /// Every joint homed, `ratio` on axis `axis`, enabled in `mode`.
    fn with_ratio(&mut self, axis: i32, ratio: f64, mode: Command) {
        self.cmd(Command::SetAxisEoffsetRatio { axis, ratio })
            .unwrap();
        for j in 0..self.m.num_joints() {
            self.m.set_homed(j, true);
        }
        self.enable();
        self.cmd(mode).unwrap();
        self.cycle();
    }

    /// The offset inputs of axis `a`: enabled, `counts` at `scale`.
    fn eoffset_pins(&mut self, a: usize, counts: i32, scale: f64) {
        self.m.axis_inputs[a].eoffset = EoffsetInputs {
            enable: true,
            clear: false,
            counts,
            scale,
        };
    }

    fn eoffset(&self, a: usize) -> f64 {
        self.m.axis(a).unwrap().eoffset
    }
}

/// Largest |velocity| and |acceleration| of a sequence of positions.
fn extremes(p: &[f64]) -> (f64, f64) {
    let v: Vec<f64> = p.windows(2).map(|w| (w[1] - w[0]) / T).collect();
    let a = v
        .windows(2)
        .map(|w| ((w[1] - w[0]) / T).abs())
        .fold(0.0, f64::max);
    (v.iter().fold(0.0, |m, x| m.max(x.abs())), a)
}

#[test]
fn a_coordinated_move_carries_the_offset_within_its_share() {
    let mut s = xyz();
    s.with_ratio(Z as i32, 0.2, Command::Coord);
    s.eoffset_pins(Z, 0, 0.01);
    s.cycle();
    s.eoffset_pins(Z, 100, 0.01);
    s.cmd(Command::Line {
        end: at(10.0, 0.0, 0.0),
        vel: 5.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id: 1,
    })
    .unwrap();
    let mut z = Vec::new();
    let mut moved_together = false;
    for _ in 0..5000 {
        s.cycle();
        z.push(s.j(Z).pos_cmd);
        let x = s.j(0).pos_cmd;
        moved_together |= x > 0.1 && x < 9.9 && s.j(Z).pos_cmd > 0.5;
        if s.m.in_position() && !s.m.eoffset_active() {
            break;
        }
        // The commanded Z is the planned Z (0) plus the offset.
        assert_eq!(s.j(Z).pos_cmd, s.eoffset(Z));
    }
    assert!(moved_together, "the offset is applied while the move runs");
    assert!((s.j(0).pos_cmd - 10.0).abs() < 1e-9);
    assert!((s.j(Z).pos_cmd - 1.0).abs() < 1e-6, "{}", s.j(Z).pos_cmd);
    assert_eq!(s.m.axis(Z).unwrap().eoffset_request, 1.0);
    assert!(s.m.eoffset_active() && !s.m.eoffset_limited());
    // 0.2 of 10 u/s and 100 u/s².
    let (v, a) = extremes(&z);
    assert!(v <= 2.0 + 1e-9, "velocity {v}");
    assert!(a <= 20.0 + 1e-6, "acceleration {a}");
}

#[test]
fn planned_moves_get_what_the_offset_leaves() {
    let mut s = xyz();
    s.with_ratio(0, 0.5, Command::Coord);
    s.cmd(Command::Line {
        end: at(20.0, 0.0, 0.0),
        vel: 0.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Traverse,
        id: 1,
    })
    .unwrap();
    let x: Vec<f64> = s.run_queue(20_000).iter().map(|p| p[0]).collect();
    let (v, a) = extremes(&x);
    assert!(v <= 5.0 + 1e-9 && v > 4.9, "velocity {v}");
    assert!(a <= 50.0 + 1e-6, "acceleration {a}");
}

#[test]
fn teleop_jogs_get_what_the_offset_leaves_and_carry_it() {
    let mut s = xyz();
    s.with_ratio(0, 0.3, Command::Teleop);
    s.eoffset_pins(0, 0, 0.5);
    s.cycle();
    s.eoffset_pins(0, 2, 0.5);
    s.cmd(Command::AxisJogIncr {
        axis: 0,
        vel: 10.0,
        offset: 5.0,
    })
    .unwrap();
    for _ in 0..3000 {
        s.cycle();
        let ax = s.m.axis(0).unwrap();
        assert!(ax.teleop_vel_cmd.abs() <= 7.0 + 1e-9);
        assert_eq!(s.j(0).pos_cmd, ax.teleop_pos + ax.eoffset);
    }
    assert!((s.j(0).pos_cmd - 6.0).abs() < 1e-6, "{}", s.j(0).pos_cmd);
}

#[test]
fn the_soft_limit_bounds_planned_plus_offset_and_raises_eoffset_limited() {
    let mut s = xyz();
    s.with_ratio(Z as i32, 0.5, Command::Coord);
    s.cmd(Command::Line {
        end: at(0.0, 0.0, 48.0),
        vel: 10.0,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Feed,
        id: 1,
    })
    .unwrap();
    s.run_queue(20_000);
    s.eoffset_pins(Z, 0, 1.0);
    s.cycle();
    s.eoffset_pins(Z, 5, 1.0);
    for _ in 0..3000 {
        s.cycle();
        assert!(s.j(Z).pos_cmd <= 50.0 + 1e-9, "{}", s.j(Z).pos_cmd);
    }
    assert!((s.j(Z).pos_cmd - 50.0).abs() < 1e-9);
    assert!((s.eoffset(Z) - 2.0).abs() < 1e-9);
    assert!(s.m.eoffset_limited() && !s.m.on_soft_limit() && !s.m.error());
    assert_eq!(s.m.axis(Z).unwrap().eoffset_request, 5.0);
    // Counting back below the room left clears the flag.
    s.eoffset_pins(Z, 1, 1.0);
    s.run(3000);
    assert!((s.j(Z).pos_cmd - 49.0).abs() < 1e-6);
    assert!(!s.m.eoffset_limited());
}

#[test]
fn a_continuous_jog_stops_where_the_sum_reaches_the_limit() {
    let mut s = xyz();
    s.with_ratio(0, 0.2, Command::Teleop);
    s.eoffset_pins(0, 0, 1.0);
    s.cycle();
    s.eoffset_pins(0, 3, 1.0);
    s.run(3000);
    s.cmd(Command::AxisJogCont { axis: 0, vel: 8.0 }).unwrap();
    for _ in 0..10_000 {
        s.cycle();
        assert!(s.j(0).pos_cmd <= 50.0 + 1e-9);
    }
    let ax = s.m.axis(0).unwrap();
    assert!((ax.teleop_pos - 47.0).abs() < 1e-6, "{}", ax.teleop_pos);
    assert!((s.j(0).pos_cmd - 50.0).abs() < 1e-6);
    assert!(s.m.eoffset_limited());
}

#[test]
fn disabling_an_applied_offset_holds_it_and_says_so() {
    let mut s = xyz();
    s.with_ratio(Z as i32, 0.2, Command::Teleop);
    s.eoffset_pins(Z, 0, 0.25);
    s.cycle();
    s.eoffset_pins(Z, 4, 0.25);
    s.run(2000);
    s.events();
    s.m.axis_inputs[Z].eoffset.enable = false;
    s.run(100);
    assert_eq!(s.events(), [Event::EoffsetDisabledWhileApplied { axis: 2 }]);
    assert!((s.j(Z).pos_cmd - 1.0).abs() < 1e-6, "held");
    assert_eq!(
        Event::EoffsetDisabledWhileApplied { axis: 2 }.to_string(),
        "axis Z external offset disabled while not zero: it is held; to clear it, re-enable \
         it and count it back to zero, pulse eoffset-clear, or turn the machine off and on"
    );
    // Re-enabled and counted back to zero: disabling then says nothing.
    s.eoffset_pins(Z, 4, 0.25);
    s.cycle();
    s.eoffset_pins(Z, 0, 0.25);
    s.run(2000);
    assert!(s.j(Z).pos_cmd.abs() < 1e-6);
    s.m.axis_inputs[Z].eoffset.enable = false;
    s.run(10);
    assert_eq!(s.events(), []);
}

#[test]
fn machine_off_keeps_the_position_and_machine_on_zeroes_the_offset() {
    let mut s = xyz();
    s.with_ratio(Z as i32, 0.2, Command::Teleop);
    s.eoffset_pins(Z, 0, 0.25);
    s.cycle();
    s.eoffset_pins(Z, 4, 0.25);
    s.run(2000);
    assert!((s.j(Z).pos_cmd - 1.0).abs() < 1e-6);
    s.cmd(Command::Disable).unwrap();
    s.run(10);
    let here = s.j(Z).pos_cmd;
    assert!((here - 1.0).abs() < 1e-6, "nothing moves at machine off");
    assert!((s.eoffset(Z) - 1.0).abs() < 1e-6, "still shown while off");
    // Counts turned while off are dropped.
    s.eoffset_pins(Z, 40, 0.25);
    s.run(10);
    s.enable();
    assert_eq!(s.m.state(), MotionState::Teleop);
    let ax = s.m.axis(Z).unwrap();
    assert_eq!((ax.eoffset, ax.eoffset_request), (0.0, 0.0));
    s.run(1000);
    assert!((s.j(Z).pos_cmd - here).abs() < 1e-9, "nor at machine on");
    assert!(
        (ax.teleop_pos - here).abs() < 1e-9,
        "the plan took its place"
    );
    assert!(!s.m.eoffset_active());
}

#[test]
fn mode_changes_keep_the_commanded_position() {
    let mut s = xyz();
    s.with_ratio(Z as i32, 0.2, Command::Teleop);
    s.eoffset_pins(Z, 0, 0.5);
    s.cycle();
    s.eoffset_pins(Z, 1, 0.5);
    s.cycle();
    assert!(s.m.eoffset_active());
    // Free mode waits for the offset to stop.
    assert_eq!(s.cmd(Command::Free), Err(Reject::NotInPosition));
    s.run(2000);
    let here = s.j(Z).pos_cmd;
    for mode in [
        Command::Coord,
        Command::Free,
        Command::Teleop,
        Command::Coord,
    ] {
        s.cmd(mode).unwrap();
        s.run(5);
        assert!((s.j(Z).pos_cmd - here).abs() < 1e-12, "{mode:?}");
    }
    assert!((s.m.planner_pos().0[Z] - (here - s.eoffset(Z))).abs() < 1e-12);
    assert!((s.eoffset(Z) - 0.5).abs() < 1e-6);
    // Counts taken in free mode move the offset once back in a world
    // mode.
    s.cmd(Command::Free).unwrap();
    s.eoffset_pins(Z, 2, 0.5);
    s.run(100);
    assert!((s.j(Z).pos_cmd - here).abs() < 1e-12, "still in free mode");
    s.cmd(Command::Teleop).unwrap();
    s.run(2000);
    assert!((s.j(Z).pos_cmd - (here + 0.5)).abs() < 1e-6);
}

#[test]
fn without_a_ratio_or_unhomed_the_pins_do_nothing() {
    let mut s = xyz();
    s.with_ratio(Z as i32, 0.0, Command::Teleop);
    s.eoffset_pins(Z, 0, 1.0);
    s.cycle();
    s.eoffset_pins(Z, 10, 1.0);
    s.run(1000);
    assert_eq!((s.eoffset(Z), s.j(Z).pos_cmd), (0.0, 0.0));
    assert_eq!(s.m.axis(Z).unwrap().eoffset_request, 0.0);
    let mut u = xyz();
    u.cmd(Command::SetAxisEoffsetRatio {
        axis: 2,
        ratio: 0.2,
    })
    .unwrap();
    u.enable();
    u.cmd(Command::Teleop).unwrap();
    u.eoffset_pins(Z, 0, 1.0);
    u.cycle();
    u.eoffset_pins(Z, 10, 1.0);
    u.run(1000);
    assert_eq!((u.eoffset(Z), u.j(Z).pos_cmd), (0.0, 0.0), "not homed");
}

#[test]
fn the_ratio_is_checked_and_set_only_while_disabled() {
    let mut s = xyz();
    for bad in [-0.1, 0.91, f64::NAN] {
        assert!(matches!(
            s.cmd(Command::SetAxisEoffsetRatio {
                axis: 0,
                ratio: bad
            }),
            Err(Reject::BadValue {
                what: Quantity::EoffsetRatio,
                ..
            })
        ));
    }
    assert_eq!(
        s.cmd(Command::SetAxisEoffsetRatio {
            axis: 9,
            ratio: 0.1
        }),
        Err(Reject::NoSuchAxis { axis: 9 })
    );
    s.cmd(Command::SetAxisEoffsetRatio {
        axis: 0,
        ratio: 0.9,
    })
    .unwrap();
    assert_eq!(s.m.axis(0).unwrap().config.eoffset_ratio, 0.9);
    s.enable();
    assert_eq!(
        s.cmd(Command::SetAxisEoffsetRatio {
            axis: 0,
            ratio: 0.1
        }),
        Err(Reject::MustBeDisabled)
    );
}
