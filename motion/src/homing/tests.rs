//! Homing tests on simulated joints: each motor moves to its command one
//! servo period later; home switches, limit switches and encoder index
//! marks sit at physical motor positions; an encoder restarts its count at
//! an index mark while `index-enable` is true and then clears it, as the
//! encoder drivers do; a locking indexer reports itself unlocked a few
//! periods after being told to unlock.

use std::sync::Arc;

use super::*;
use crate::command::{Command, CommandResult, Reject};
use crate::core::{MotionConfig, MotionCore, MotionState};
use crate::events::Event;
use crate::kins::trivkins::Trivkins;
use crate::kins::KinematicsType;

const T: f64 = 0.001;

/// One simulated axis.
#[derive(Debug, Clone)]
struct Axis {
    /// Physical motor position.
    x: f64,
    /// Home switch closed while the motor is in `[lo, hi]`.
    home_sw: Option<(f64, f64)>,
    /// Limit switches trip at or beyond these positions.
    pos_lim: f64,
    neg_lim: f64,
    /// Index marks at `first + k·pitch`.
    index: Option<(f64, f64)>,
    /// The encoder counts `x − encoder_zero`.
    encoder_zero: f64,
    /// Whether the encoder restarts its count at the index.
    resets_on_index: bool,
    /// The `index-enable` signal.
    index_pin: bool,
    /// Periods the indexer takes to unlock or lock.
    unlock_delay: usize,
    unlock_timer: usize,
    is_unlocked: bool,
    /// Extra servo periods the motor lags its command.
    lag: usize,
    history: std::collections::VecDeque<f64>,
}

impl Default for Axis {
    fn default() -> Self {
        Axis {
            x: 0.0,
            home_sw: None,
            pos_lim: f64::INFINITY,
            neg_lim: f64::NEG_INFINITY,
            index: None,
            encoder_zero: 0.0,
            resets_on_index: true,
            index_pin: false,
            unlock_delay: 5,
            unlock_timer: 0,
            is_unlocked: false,
            lag: 0,
            history: Default::default(),
        }
    }
}

impl Axis {
    fn switch_closed(&self) -> bool {
        self.home_sw
            .is_some_and(|(lo, hi)| self.x >= lo && self.x <= hi)
    }

    /// The index mark crossed moving from `from` to `to`, if any.
    fn index_crossed(&self, from: f64, to: f64) -> Option<f64> {
        let (first, pitch) = self.index?;
        let (lo, hi) = if from <= to { (from, to) } else { (to, from) };
        let k = ((lo - first) / pitch).ceil();
        let mark = first + k * pitch;
        (mark > lo && mark <= hi).then_some(mark)
    }
}

/// The controller with its simulated machine.
struct Rig {
    m: MotionCore,
    axes: Vec<Axis>,
    /// The cycle in which each joint's final move was first seen running.
    final_move_at: Vec<Option<usize>>,
    cycles: usize,
}

/// `n` trivkins joints, limits ±100, 10 u/s, 100 u/s², the given axes.
fn rig(axes: Vec<Axis>) -> Rig {
    rig_with_extra(axes, 0)
}

/// Like [`rig`], the last `extra` joints being extra joints; every joint
/// has unlock pins.
fn rig_with_extra(axes: Vec<Axis>, extra: usize) -> Rig {
    let n = axes.len();
    let coords = &"XYZABCUVW"[..n - extra];
    let kins = Arc::new(Trivkins::new(coords, KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: n,
            num_extrajoints: extra,
            unlock_joints_mask: u32::MAX,
            ..MotionConfig::default()
        },
        kins,
    );
    crate::test_support::configure_test_joints(&mut m);
    let mut r = Rig {
        m,
        axes,
        final_move_at: vec![None; n],
        cycles: 0,
    };
    r.run(2);
    r.cmd(Command::Enable).unwrap();
    r.cycle();
    assert!(r.m.is_enabled());
    r
}

fn switch_axis(x: f64, lo: f64, hi: f64) -> Axis {
    Axis {
        x,
        home_sw: Some((lo, hi)),
        ..Axis::default()
    }
}

impl Rig {
    fn cycle(&mut self) {
        for (j, a) in self.axes.iter_mut().enumerate() {
            let js = self.m.joint(j);
            let from = a.x;
            if js.enabled {
                // The drive closes its loop on the encoder count.
                a.history.push_back(js.motor_pos_cmd + a.encoder_zero);
                while a.history.len() > a.lag + 1 {
                    a.history.pop_front();
                }
                a.x = a.history[0];
            } else {
                a.history.clear();
            }
            if a.index_pin {
                if let Some(mark) = a.index_crossed(from, a.x) {
                    if a.resets_on_index {
                        a.encoder_zero = mark;
                    }
                    a.index_pin = false;
                }
            }
            let want = self.m.unlock_output(j);
            if want != a.is_unlocked {
                a.unlock_timer += 1;
                if a.unlock_timer >= a.unlock_delay {
                    a.is_unlocked = want;
                    a.unlock_timer = 0;
                }
            } else {
                a.unlock_timer = 0;
            }
            let inp = &mut self.m.joint_inputs[j];
            inp.motor_pos_fb = a.x - a.encoder_zero;
            inp.home_sw = a.switch_closed();
            inp.pos_lim_sw = a.x >= a.pos_lim;
            inp.neg_lim_sw = a.x <= a.neg_lim;
            inp.index_enable = a.index_pin;
            inp.is_unlocked = a.is_unlocked;
        }
        self.m.cycle(T);
        self.cycles += 1;
        for (j, a) in self.axes.iter_mut().enumerate() {
            if let Some(v) = self.m.index_enable_drive(j) {
                a.index_pin = v;
            }
            if self.m.home_state(j) == HomeState::FinalMoveWait && self.final_move_at[j].is_none() {
                self.final_move_at[j] = Some(self.cycles);
            }
        }
    }

    fn run(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    fn cmd(&mut self, c: Command) -> CommandResult {
        self.m.command(&c)
    }

    fn configure(&mut self, joint: i32, config: HomingConfig) {
        self.cmd(Command::SetJointHomingParams { joint, config })
            .unwrap();
    }

    /// Runs until homing ends; returns the periods it took.
    fn home_to_end(&mut self, limit: usize) -> usize {
        for n in 0..limit {
            self.cycle();
            if !self.m.homing_active() {
                return n + 1;
            }
        }
        panic!(
            "still homing after {limit} periods: states {:?}",
            (0..self.axes.len())
                .map(|j| self.m.home_state(j))
                .collect::<Vec<_>>()
        );
    }

    /// The joint coordinate of physical motor position `p` now.
    fn joint_of(&self, j: usize, p: f64) -> f64 {
        let js = self.m.joint(j);
        p - self.axes[j].encoder_zero - js.backlash_filt - js.motor_offset
    }

    fn events(&self) -> Vec<Event> {
        self.m.events().drain()
    }
}

fn cfg(search: f64, latch: f64) -> HomingConfig {
    HomingConfig {
        search_vel: search,
        latch_vel: latch,
        sequence: 0,
        ..HomingConfig::default()
    }
}

fn assert_visits(r: &Rig, j: usize, want: &[HomeState]) {
    let seen = r.m.homing_trace(j);
    let mut it = seen.iter();
    for w in want {
        assert!(
            it.any(|s| s == w),
            "joint {j} never reached {w} in order; went through {seen:?}"
        );
    }
}

/// The states a switch homing with same-sign search and latch goes
/// through, in order.
const RISE_PATH: &[HomeState] = &[
    HomeState::Start,
    HomeState::UnlockWait,
    HomeState::InitialSearchStart,
    HomeState::InitialSearchWait,
    HomeState::FinalBackoffStart,
    HomeState::FinalBackoffWait,
    HomeState::RiseSearchStart,
    HomeState::RiseSearchWait,
    HomeState::FinalMoveStart,
    HomeState::FinalMoveWait,
    HomeState::Idle,
];

#[test]
fn in_place_homing_declares_home_offset_and_moves_to_home() {
    let mut r = rig(vec![Axis {
        x: 3.0,
        ..Axis::default()
    }]);
    r.configure(
        0,
        HomingConfig {
            offset: 1.0,
            home: 2.5,
            final_vel: 2.0,
            ..cfg(0.0, 0.0)
        },
    );
    let motor_before = r.m.joint(0).motor_pos_cmd;
    r.cmd(Command::Home { joint: 0 }).unwrap();
    assert!(r.m.homing_active() && !r.m.joint(0).homed);
    r.cycle();
    // Set in the first cycle: here is HOME_OFFSET; the motor did not move.
    assert_eq!(r.m.joint(0).pos_fb, 1.0);
    assert_eq!(r.m.joint(0).motor_pos_cmd, motor_before);
    assert!(r.m.joint(0).homing);
    r.home_to_end(5000);
    let js = r.m.joint(0);
    assert!(js.homed && !js.homing);
    assert_eq!(js.pos_cmd, 2.5, "lands exactly on HOME");
    assert_eq!(js.motor_offset, 3.0 - 1.0);
    r.run(2);
    assert!((r.axes[0].x - 4.5).abs() < 1e-9, "moved HOME − HOME_OFFSET");
    assert_eq!(r.m.home_state(0), HomeState::Idle);
    assert_visits(
        &r,
        0,
        &[
            HomeState::Start,
            HomeState::SetSwitchPosition,
            HomeState::FinalMoveStart,
            HomeState::FinalMoveWait,
            HomeState::Idle,
        ],
    );
    assert!(r.m.is_all_homed());
}

#[test]
fn final_move_speed_is_home_final_vel_capped_at_the_joint_limit() {
    for (final_vel, want) in [(2.0, 2.0), (50.0, 10.0), (-1.0, 10.0), (0.0, 10.0)] {
        let mut r = rig(vec![Axis::default()]);
        r.configure(
            0,
            HomingConfig {
                home: 30.0,
                final_vel,
                ..cfg(0.0, 0.0)
            },
        );
        r.cmd(Command::Home { joint: 0 }).unwrap();
        let mut top: f64 = 0.0;
        while r.m.homing_active() {
            r.cycle();
            top = top.max(r.m.joint(0).vel_cmd.abs());
        }
        assert!(
            (top - want).abs() < 1e-9,
            "final vel {final_vel}: top {top}"
        );
    }
}

#[test]
fn switch_homing_latches_on_the_rising_edge_with_same_sign_velocities() {
    // Switch from 5 on; the motor starts at 0.
    let mut r = rig(vec![switch_axis(0.0, 5.0, 1000.0)]);
    r.configure(
        0,
        HomingConfig {
            offset: 10.0,
            home: 8.0,
            ..cfg(4.0, 0.5)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_visits(&r, 0, RISE_PATH);
    assert!(r.m.joint(0).homed);
    // The switch edge is HOME_OFFSET, to within one latch step.
    let edge = r.joint_of(0, 5.0);
    assert!(
        (10.0 - 0.5 * T - 1e-9..=10.0).contains(&edge),
        "edge at {edge}"
    );
    assert_eq!(r.m.joint(0).pos_cmd, 8.0);
    r.run(2);
    assert!((r.axes[0].x - (5.0 + 8.0 - edge)).abs() < 1e-9);
    assert!(r.events().is_empty());
}

#[test]
fn switch_homing_latches_on_the_falling_edge_with_opposite_velocities() {
    let mut r = rig(vec![switch_axis(0.0, 5.0, 1000.0)]);
    r.configure(
        0,
        HomingConfig {
            offset: 0.0,
            home: 1.0,
            ..cfg(4.0, -0.25)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_visits(
        &r,
        0,
        &[
            HomeState::InitialSearchWait,
            HomeState::SetCoarsePosition,
            HomeState::FallSearchStart,
            HomeState::FallSearchWait,
            HomeState::SetSwitchPosition,
            HomeState::FinalMoveWait,
        ],
    );
    assert!(!r.m.homing_trace(0).contains(&HomeState::FinalBackoffWait));
    // Moving negative, the switch opens just below 5.
    let edge = r.joint_of(0, 5.0);
    assert!((0.0..=0.25 * T + 1e-9).contains(&edge), "edge at {edge}");
    assert_eq!(r.m.joint(0).pos_cmd, 1.0);
}

#[test]
fn starting_on_the_switch_backs_off_first() {
    let mut r = rig(vec![switch_axis(6.0, 5.0, 1000.0)]);
    r.configure(0, cfg(4.0, 0.5));
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_visits(
        &r,
        0,
        &[
            HomeState::InitialSearchStart,
            HomeState::InitialBackoffStart,
            HomeState::InitialBackoffWait,
            HomeState::InitialSearchStart,
            HomeState::InitialSearchWait,
            HomeState::FinalBackoffWait,
            HomeState::RiseSearchWait,
        ],
    );
    assert!(r.joint_of(0, 5.0).abs() <= 0.5 * T + 1e-9);
}

#[test]
fn negative_search_finds_a_switch_below() {
    let mut r = rig(vec![switch_axis(0.0, -1000.0, -3.0)]);
    r.configure(
        0,
        HomingConfig {
            offset: -50.0,
            home: -45.0,
            ..cfg(-5.0, -1.0)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_visits(&r, 0, RISE_PATH);
    let edge = r.joint_of(0, -3.0);
    assert!((-50.0..=-50.0 + T + 1e-9).contains(&edge), "edge at {edge}");
    assert_eq!(r.m.joint(0).pos_cmd, -45.0);
}

#[test]
fn switch_then_index_sets_the_index_mark_to_home_offset_exactly() {
    // Index marks every 2 units from 0.3; the switch closes at 5.
    let mut r = rig(vec![Axis {
        index: Some((0.3, 2.0)),
        ..switch_axis(0.0, 5.0, 1000.0)
    }]);
    r.configure(
        0,
        HomingConfig {
            offset: 1.25,
            home: 0.0,
            flags: HomeFlags::USE_INDEX,
            ..cfg(4.0, 0.5)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    let mut drives = Vec::new();
    while r.m.homing_active() {
        r.cycle();
        if let Some(v) = r.m.index_enable_drive(0) {
            drives.push(v);
        }
        assert!(r.cycles < 30_000);
    }
    assert_visits(
        &r,
        0,
        &[
            HomeState::RiseSearchWait,
            HomeState::IndexSearchWait,
            HomeState::SetIndexPosition,
            HomeState::FinalMoveWait,
        ],
    );
    // Armed once; the encoder cleared it; the falling edge is written
    // once more (to an already false signal).
    assert_eq!(drives, [true, false]);
    // The first mark past the switch is 6.3: the encoder restarted there.
    assert_eq!(r.axes[0].encoder_zero, 6.3);
    assert_eq!(r.joint_of(0, 6.3), 1.25);
    assert!(!r.m.joint(0).following_error, "no trip at the count jump");
    assert!(r.events().is_empty());
    r.run(2);
    assert!((r.axes[0].x - (6.3 - 1.25)).abs() < 1e-9);
}

#[test]
fn index_only_homing_moves_at_latch_speed_to_the_next_mark() {
    let mut r = rig(vec![Axis {
        x: 1.0,
        index: Some((0.5, 1.0)),
        ..Axis::default()
    }]);
    r.configure(
        0,
        HomingConfig {
            offset: 0.0,
            home: 0.0,
            flags: HomeFlags::USE_INDEX,
            ..cfg(0.0, -0.2)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_visits(
        &r,
        0,
        &[
            HomeState::UnlockWait,
            HomeState::IndexOnlyStart,
            HomeState::IndexSearchWait,
            HomeState::SetIndexPosition,
            HomeState::FinalMoveWait,
        ],
    );
    assert_eq!(r.axes[0].encoder_zero, 0.5);
    assert_eq!(r.joint_of(0, 0.5), 0.0);
    r.run(2);
    assert!((r.axes[0].x - 0.5).abs() < 1e-9);
}

#[test]
fn index_without_encoder_reset_is_shifted_by_motion() {
    let mut r = rig(vec![Axis {
        x: 1.0,
        index: Some((0.5, 1.0)),
        resets_on_index: false,
        ..Axis::default()
    }]);
    r.configure(
        0,
        HomingConfig {
            offset: 2.0,
            home: 2.0,
            flags: HomeFlags::USE_INDEX | HomeFlags::INDEX_NO_ENCODER_RESET,
            ..cfg(0.0, -0.2)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_eq!(r.axes[0].encoder_zero, 0.0, "the count went on");
    // The mark is HOME_OFFSET to within one latch step.
    let mark = r.joint_of(0, 0.5);
    assert!((mark - 2.0).abs() <= 0.2 * T + 1e-9, "mark at {mark}");
    assert!(r.m.joint(0).homed);
}

#[test]
fn a_limit_switch_aborts_homing_unless_limits_are_ignored() {
    // The home switch is the positive limit switch (both from 5).
    let axis = Axis {
        pos_lim: 5.0,
        ..switch_axis(0.0, 5.0, 1000.0)
    };
    // Not ignored: the limit trips together with the switch and homing
    // aborts (homing joints are exempt from the limit fault; the state
    // machine handles it). The joint, no longer homing, is then on its
    // limit: motion disables as for any tripped limit.
    let mut r = rig(vec![axis.clone()]);
    r.configure(0, cfg(4.0, -0.5));
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    r.cycle();
    assert_eq!(
        r.events(),
        [
            Event::HomingAborted {
                joint: 0,
                fault: HomeFault::HitLimit,
                state: HomeState::FallSearchWait,
            },
            Event::JointOnLimit { joint: 0 }
        ]
    );
    assert!(!r.m.is_enabled());
    assert!(!r.m.joint(0).homed && !r.m.joint(0).homing);
    assert_eq!(r.m.home_state(0), HomeState::Idle);
    // Ignored: homing runs on the switch and finishes off it.
    let mut r = rig(vec![axis]);
    r.configure(
        0,
        HomingConfig {
            home: -1.0,
            flags: HomeFlags::IGNORE_LIMITS,
            ..cfg(4.0, -0.5)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert!(r.m.joint(0).homed, "{:?}", r.events());
    assert!(r.m.is_enabled());
    assert!(r.events().is_empty());
}

#[test]
fn a_search_without_a_switch_ends_at_the_end_of_its_move() {
    let mut r = rig(vec![Axis::default()]);
    r.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -0.5,
        max: 0.5,
    })
    .unwrap();
    r.configure(0, cfg(5.0, 1.0));
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert_eq!(
        r.events(),
        [Event::HomingAborted {
            joint: 0,
            fault: HomeFault::EndOfMove,
            state: HomeState::InitialSearchWait,
        }]
    );
    // Two full travels (2 × 1) from the start.
    assert!((r.axes[0].x - 2.0).abs() < 1e-3, "{}", r.axes[0].x);
}

#[test]
fn a_closed_shared_switch_refuses_or_aborts_homing() {
    let shared = HomingConfig {
        flags: HomeFlags::IS_SHARED,
        ..cfg(4.0, 0.5)
    };
    // Closed when the request comes: refused, nothing changes.
    let mut r = rig(vec![switch_axis(6.0, 5.0, 1000.0)]);
    r.configure(0, shared);
    assert_eq!(
        r.cmd(Command::Home { joint: 0 }),
        Err(Reject::SharedHomeSwitchClosed { joint: 0 })
    );
    assert!(!r.m.homing_active());
    // Closed when its turn comes in a sequence: that sequence aborts.
    let mut r = rig(vec![Axis::default(), switch_axis(0.0, 5.0, 1000.0)]);
    r.configure(0, cfg(0.0, 0.0));
    r.configure(
        1,
        HomingConfig {
            sequence: 1,
            ..shared
        },
    );
    r.cmd(Command::Home { joint: -1 }).unwrap();
    // Another joint closes the shared switch before joint 1's turn.
    r.axes[1].home_sw = Some((-1000.0, 1000.0));
    r.home_to_end(20_000);
    assert_eq!(
        r.events(),
        [Event::HomingAborted {
            joint: 1,
            fault: HomeFault::SharedSwitchClosed,
            state: HomeState::Start,
        }]
    );
    assert!(r.m.joint(0).homed, "joint 0 finished before: kept");
    assert!(!r.m.joint(1).homed);
}

#[test]
fn home_all_runs_the_sequences_in_order_and_equal_numbers_together() {
    let mut r = rig(vec![
        Axis::default(),
        switch_axis(0.0, 1.0, 1000.0),
        switch_axis(0.0, 2.0, 1000.0),
        Axis::default(),
    ]);
    r.configure(0, cfg(0.0, 0.0));
    r.configure(
        1,
        HomingConfig {
            sequence: 1,
            ..cfg(5.0, 1.0)
        },
    );
    r.configure(
        2,
        HomingConfig {
            sequence: 1,
            ..cfg(5.0, 1.0)
        },
    );
    r.configure(
        3,
        HomingConfig {
            sequence: 2,
            home: 1.0,
            ..cfg(0.0, 0.0)
        },
    );
    r.cmd(Command::Home { joint: -1 }).unwrap();
    let mut started = [None; 4];
    let mut finished = [None; 4];
    while r.m.homing_active() {
        r.cycle();
        for j in 0..4 {
            if started[j].is_none() && r.m.home_state(j) != HomeState::Idle {
                started[j] = Some(r.cycles);
            }
            if finished[j].is_none() && r.m.joint(j).homed {
                finished[j] = Some(r.cycles);
            }
            // Published while the sequence still runs.
            assert!(r.m.joint_homing(j) || r.m.joint(j).homed || !r.m.homing_active());
        }
        assert!(r.cycles < 50_000);
    }
    let [s0, s1, s2, s3] = started.map(Option::unwrap);
    let [f0, f1, f2, _] = finished.map(Option::unwrap);
    assert!(s0 < f0 && s1 > f0 && s2 > f0, "sequence 1 after 0");
    assert_eq!(s1, s2, "same number: together");
    assert!(s3 > f1.max(f2), "sequence 2 after 1");
    assert!(r.m.is_all_homed());
    assert!(r.events().is_empty());
}

#[test]
fn home_all_sequences_must_start_at_0_or_1_without_gaps() {
    let mut r = rig(vec![Axis::default(), Axis::default(), Axis::default()]);
    // The module default (1000) is not part of home-all.
    assert_eq!(
        r.cmd(Command::Home { joint: -1 }),
        Err(Reject::NothingToHome)
    );
    r.configure(
        0,
        HomingConfig {
            sequence: 1,
            ..cfg(0.0, 0.0)
        },
    );
    r.configure(
        1,
        HomingConfig {
            sequence: 3,
            ..cfg(0.0, 0.0)
        },
    );
    assert_eq!(
        r.cmd(Command::Home { joint: -1 }),
        Err(Reject::HomeSequenceGap { missing: 2 })
    );
    r.configure(
        0,
        HomingConfig {
            sequence: 2,
            ..cfg(0.0, 0.0)
        },
    );
    assert_eq!(
        r.cmd(Command::Home { joint: -1 }),
        Err(Reject::HomeSequenceGap { missing: 1 })
    );
    assert!(!r.m.homing_active());
    // Over 100: homed only on its own.
    r.configure(
        0,
        HomingConfig {
            sequence: 1,
            ..cfg(0.0, 0.0)
        },
    );
    r.configure(
        1,
        HomingConfig {
            sequence: 2,
            ..cfg(0.0, 0.0)
        },
    );
    r.configure(
        2,
        HomingConfig {
            sequence: 101,
            ..cfg(0.0, 0.0)
        },
    );
    r.cmd(Command::Home { joint: -1 }).unwrap();
    r.home_to_end(5000);
    assert!(r.m.joint(0).homed && r.m.joint(1).homed && !r.m.joint(2).homed);
    r.cmd(Command::Home { joint: 2 }).unwrap();
    r.home_to_end(5000);
    assert!(r.m.is_all_homed());
}

#[test]
fn a_synchronised_group_homes_together_and_starts_its_final_moves_together() {
    // A gantry: two joints, switches at different distances.
    let mut r = rig(vec![
        switch_axis(0.0, 2.0, 1000.0),
        switch_axis(0.0, 3.0, 1000.0),
        Axis::default(),
    ]);
    let gantry = HomingConfig {
        sequence: -1,
        home: 4.0,
        ..cfg(5.0, 1.0)
    };
    r.configure(0, gantry);
    // The partner says 1: the group's negative number wins.
    r.configure(
        1,
        HomingConfig {
            sequence: 1,
            ..gantry
        },
    );
    r.configure(
        2,
        HomingConfig {
            sequence: 0,
            ..cfg(0.0, 0.0)
        },
    );
    // Gantry joints are not jogged alone.
    assert_eq!(
        r.cmd(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::SynchronizedJoint { joint: 0 })
    );
    // Homing one homes the group (not joint 2).
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.cycle();
    assert!(r.m.joint(1).homing && !r.m.joint(2).homing);
    r.home_to_end(50_000);
    assert!(r.m.joint(0).homed && r.m.joint(1).homed && !r.m.joint(2).homed);
    assert_eq!(r.m.homing_config(1).sequence, -1, "normalised");
    assert_eq!(r.final_move_at[0], r.final_move_at[1]);
    assert!(r.final_move_at[0].is_some());
    assert_eq!(r.m.joint(0).pos_cmd, 4.0);
    assert_eq!(r.m.joint(1).pos_cmd, 4.0);
}

#[test]
fn absolute_encoders_set_the_position_without_searching() {
    // Mode 1: raw position + HOME_OFFSET, then the final move.
    let mut r = rig(vec![Axis {
        x: 7.0,
        ..Axis::default()
    }]);
    let abs1 = HomingConfig {
        offset: -2.0,
        home: 1.0,
        flags: HomeFlags::ABSOLUTE_ENCODER | HomeFlags::NO_REHOME,
        ..cfg(0.0, 0.0)
    };
    // An old homing offset, restored while disabled.
    r.cmd(Command::Disable).unwrap();
    r.cycle();
    r.cmd(Command::SetJointMotorOffset {
        joint: 0,
        offset: 0.75,
    })
    .unwrap();
    r.run(2);
    r.cmd(Command::Enable).unwrap();
    r.cycle();
    assert_eq!(r.m.joint(0).pos_fb, 6.25);
    r.configure(0, abs1);
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.cycle();
    assert_eq!(r.m.joint(0).pos_fb, 7.0 - 2.0, "old offset folded away");
    r.home_to_end(5000);
    assert_visits(
        &r,
        0,
        &[
            HomeState::Start,
            HomeState::SetSwitchPosition,
            HomeState::FinalMoveWait,
            HomeState::Idle,
        ],
    );
    assert_eq!(r.m.joint(0).pos_cmd, 1.0);
    // All homed: motion went to teleop by itself, as LinuxCNC does.
    assert_eq!(r.m.state(), MotionState::Teleop);
    r.cmd(Command::Free).unwrap();
    // No re-homing: a single request is refused, home-all skips it.
    assert_eq!(
        r.cmd(Command::Home { joint: 0 }),
        Err(Reject::AlreadyHomed { joint: 0 })
    );
    r.cmd(Command::Home { joint: -1 }).unwrap();
    r.home_to_end(100);
    assert!(r.m.joint(0).homed);
    assert_eq!(r.m.joint(0).pos_cmd, 1.0);
    // Mode 2: no final move.
    let mut r = rig(vec![Axis {
        x: 7.0,
        ..Axis::default()
    }]);
    r.configure(
        0,
        HomingConfig {
            flags: abs1.flags | HomeFlags::NO_FINAL_MOVE,
            ..abs1
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(10);
    assert!(r.m.joint(0).homed);
    assert!(!r.m.homing_trace(0).contains(&HomeState::FinalMoveWait));
    r.run(3);
    assert_eq!(r.m.joint(0).pos_cmd, 5.0);
    assert_eq!(r.axes[0].x, 7.0, "did not move");
}

#[test]
fn a_locking_indexer_unlocks_first_and_locks_after() {
    let mut r = rig(vec![Axis {
        unlock_delay: 20,
        ..Axis::default()
    }]);
    r.configure(
        0,
        HomingConfig {
            home: 90.0,
            flags: HomeFlags::UNLOCK_FIRST,
            ..cfg(0.0, 0.0)
        },
    );
    assert_eq!(
        r.cmd(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::LockingIndexer { joint: 0 })
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.cycle();
    assert!(r.m.unlock_output(0));
    assert_eq!(r.m.home_state(0), HomeState::UnlockWait);
    r.run(10);
    assert_eq!(
        r.m.home_state(0),
        HomeState::UnlockWait,
        "waits for is-unlocked"
    );
    assert_eq!(r.m.joint(0).pos_cmd, 0.0);
    r.home_to_end(20_000);
    assert!(!r.m.unlock_output(0) && !r.axes[0].is_unlocked);
    assert_visits(
        &r,
        0,
        &[
            HomeState::Unlock,
            HomeState::UnlockWait,
            HomeState::FinalMoveWait,
            HomeState::Lock,
            HomeState::LockWait,
            HomeState::Idle,
        ],
    );
    assert!(r.m.joint(0).homed);
    assert_eq!(r.m.joint(0).pos_cmd, 90.0);
}

#[test]
fn home_requirements_are_checked_and_refusals_change_nothing() {
    let mut r = rig(vec![Axis::default(), Axis::default()]);
    r.configure(0, cfg(0.0, 0.0));
    r.configure(1, cfg(0.0, 0.0));
    assert_eq!(
        r.cmd(Command::Home { joint: 2 }),
        Err(Reject::NoSuchJoint {
            joint: 2,
            num_joints: 2
        })
    );
    assert_eq!(
        r.cmd(Command::Home { joint: -3 }),
        Err(Reject::NoSuchJoint {
            joint: -3,
            num_joints: 2
        })
    );
    r.m.inputs.homing_inhibit = true;
    assert_eq!(
        r.cmd(Command::Home { joint: 0 }),
        Err(Reject::HomingInhibited)
    );
    r.m.inputs.homing_inhibit = false;
    r.cmd(Command::Disable).unwrap();
    r.cycle();
    assert_eq!(r.cmd(Command::Home { joint: 0 }), Err(Reject::NotEnabled));
    r.cmd(Command::Enable).unwrap();
    r.cycle();
    r.cmd(Command::Home { joint: 0 }).unwrap();
    assert_eq!(r.cmd(Command::Home { joint: 1 }), Err(Reject::HomingActive));
    assert_eq!(
        r.cmd(Command::JogCont { joint: 1, vel: 1.0 }),
        Err(Reject::HomingActive)
    );
    assert_eq!(
        r.cmd(Command::SetJointHomingParams {
            joint: 1,
            config: cfg(0.0, 0.0)
        }),
        Err(Reject::HomingActive)
    );
    assert_eq!(
        r.cmd(Command::JointDeactivate { joint: 0 }),
        Err(Reject::HomingActive)
    );
    r.home_to_end(5000);
    r.cmd(Command::JointDeactivate { joint: 1 }).unwrap();
    assert_eq!(
        r.cmd(Command::Home { joint: 1 }),
        Err(Reject::JointInactive { joint: 1 })
    );
}

#[test]
fn bad_homing_configurations_are_refused_when_set() {
    let mut r = rig(vec![Axis::default()]);
    let bad = |search, latch, flags| HomingConfig {
        flags,
        ..cfg(search, latch)
    };
    for (c, problem) in [
        (
            bad(1.0, 0.0, HomeFlags::empty()),
            ConfigProblem::SearchWithoutLatch,
        ),
        (
            bad(0.0, 1.0, HomeFlags::empty()),
            ConfigProblem::LatchWithoutSearchOrIndex,
        ),
        (
            bad(0.0, 0.0, HomeFlags::USE_INDEX),
            ConfigProblem::IndexWithoutLatch,
        ),
        (
            bad(0.0, 0.0, HomeFlags::NO_FINAL_MOVE),
            ConfigProblem::NoFinalMoveWithoutAbsoluteEncoder,
        ),
        (
            bad(0.0, 0.0, HomeFlags::from_bits_retain(256)),
            ConfigProblem::UnknownFlags,
        ),
        (
            bad(f64::NAN, 1.0, HomeFlags::empty()),
            ConfigProblem::NotFinite,
        ),
        (
            HomingConfig {
                sequence: i32::MIN,
                ..cfg(0.0, 0.0)
            },
            ConfigProblem::BadSequence,
        ),
    ] {
        assert_eq!(
            r.cmd(Command::SetJointHomingParams {
                joint: 0,
                config: c
            }),
            Err(Reject::BadHomingConfig { joint: 0, problem })
        );
    }
    assert_eq!(r.m.homing_config(0), HomingConfig::default());
    // The update changes only offset, home and sequence.
    r.configure(0, cfg(3.0, 1.0));
    r.cmd(Command::UpdateJointHomingParams {
        joint: 0,
        offset: 1.0,
        home: 2.0,
        sequence: 4,
    })
    .unwrap();
    let c = r.m.homing_config(0);
    assert_eq!((c.offset, c.home, c.sequence), (1.0, 2.0, 4));
    assert_eq!((c.search_vel, c.latch_vel), (3.0, 1.0));
    assert_eq!(
        r.cmd(Command::UpdateJointHomingParams {
            joint: 0,
            offset: f64::INFINITY,
            home: 2.0,
            sequence: 4,
        }),
        Err(Reject::BadHomingConfig {
            joint: 0,
            problem: ConfigProblem::NotFinite
        })
    );
}

#[test]
fn disable_abort_and_jog_abort_cancel_homing_and_disarm_the_index() {
    for how in ["disable", "abort", "jog-abort", "probe"] {
        let mut r = rig(vec![
            Axis {
                index: Some((50.0, 100.0)),
                ..Axis::default()
            },
            Axis::default(),
        ]);
        r.configure(
            0,
            HomingConfig {
                flags: HomeFlags::USE_INDEX,
                ..cfg(0.0, 1.0)
            },
        );
        r.configure(1, cfg(0.0, 0.0));
        r.cmd(Command::Home { joint: 1 }).unwrap();
        r.home_to_end(5000);
        r.cmd(Command::Home { joint: 0 }).unwrap();
        while r.m.home_state(0) != HomeState::IndexSearchWait {
            r.cycle();
            assert!(r.cycles < 5000);
        }
        r.run(20);
        assert!(r.axes[0].index_pin, "armed");
        let moving = r.m.joint(0).vel_cmd;
        assert!(moving > 0.0);
        match how {
            "disable" => r.cmd(Command::Disable).unwrap(),
            "abort" => r.cmd(Command::Abort).unwrap(),
            "jog-abort" => r.cmd(Command::JogAbort { joint: 0 }).unwrap(),
            _ => r.m.inputs.probe_input = true,
        }
        r.cycle();
        let js = r.m.joint(0);
        assert!(!js.homing && !js.homed, "{how}");
        assert!(!r.m.homing_active(), "{how}");
        assert_eq!(r.m.home_state(0), HomeState::Idle, "{how}");
        assert!(!r.axes[0].index_pin, "{how}: index released");
        assert!(r.m.joint(1).homed, "{how}: the other joint keeps its home");
        if how == "probe" {
            assert_eq!(
                r.events(),
                [Event::HomingAborted {
                    joint: 0,
                    fault: HomeFault::ProbeTripped,
                    state: HomeState::IndexSearchWait,
                }]
            );
        }
        if how != "disable" {
            // A controlled stop, not a jump.
            assert!(r.m.joint(0).vel_cmd < moving);
            assert!(r.m.joint(0).vel_cmd > 0.0);
        }
    }
}

/// NO_PROBE_HOME_ERROR (SET_PROBE_ERR_INHIBIT): homing goes on through
/// a probe contact.
#[test]
fn a_probe_contact_with_the_home_inhibit_leaves_homing_running() {
    let mut r = rig(vec![switch_axis(0.0, 5.0, 1000.0)]);
    r.configure(0, cfg(4.0, 0.5));
    r.cmd(Command::SetProbeErrInhibit {
        jog: false,
        home: true,
    })
    .unwrap();
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.run(20);
    r.m.inputs.probe_input = true;
    r.cycle();
    assert!(r.m.homing_active());
    assert_eq!(r.events(), []);
    r.home_to_end(20_000);
    assert!(r.m.joint(0).homed);
}

#[test]
fn unhome_rules() {
    let mut r = rig(vec![Axis::default(), Axis::default(), Axis::default()]);
    for j in 0..3 {
        r.configure(
            j,
            HomingConfig {
                volatile_home: j == 1,
                sequence: 0,
                ..cfg(0.0, 0.0)
            },
        );
    }
    r.cmd(Command::Home { joint: -1 }).unwrap();
    r.home_to_end(5000);
    assert!(r.m.is_all_homed());
    // Teleop now: unhoming needs free mode (or disabled).
    assert_eq!(
        r.cmd(Command::Unhome { joint: -1 }),
        Err(Reject::NotFreeOrDisabled)
    );
    r.cmd(Command::Free).unwrap();
    // −2: only the volatile ones.
    r.cmd(Command::Unhome { joint: -2 }).unwrap();
    assert!(r.m.joint(0).homed && !r.m.joint(1).homed && r.m.joint(2).homed);
    // A moving joint refuses −1 as a whole.
    r.cmd(Command::JogIncr {
        joint: 2,
        vel: 1.0,
        offset: 1.0,
    })
    .unwrap();
    r.cycle();
    assert_eq!(
        r.cmd(Command::Unhome { joint: -1 }),
        Err(Reject::JointMoving { joint: 2 })
    );
    assert!(r.m.joint(0).homed);
    assert_eq!(
        r.cmd(Command::Unhome { joint: 2 }),
        Err(Reject::JointMoving { joint: 2 })
    );
    r.run(2000);
    r.cmd(Command::Unhome { joint: 2 }).unwrap();
    assert!(!r.m.joint(2).homed && r.m.joint(0).homed);
    r.cmd(Command::Unhome { joint: -1 }).unwrap();
    assert!((0..3).all(|j| !r.m.joint(j).homed));
    assert_eq!(
        r.cmd(Command::Unhome { joint: -3 }),
        Err(Reject::NoSuchJoint {
            joint: -3,
            num_joints: 3
        })
    );
    // Allowed while disabled too.
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(5000);
    r.cmd(Command::Disable).unwrap();
    r.cycle();
    assert_eq!(r.m.state(), MotionState::Disabled);
    r.cmd(Command::Unhome { joint: 0 }).unwrap();
    assert!(!r.m.joint(0).homed);
}

#[test]
fn home_state_numbers_are_linuxcnc_s() {
    for n in 0..26 {
        assert_eq!(HomeState::from_number(n).unwrap().number(), n);
    }
    assert_eq!(HomeState::from_number(26), None);
    assert_eq!(HomeState::from_number(-1), None);
    assert_eq!(HomeState::FinalMoveWait.number(), 21);
    assert_eq!(HomeState::Abort.number(), 25);
    for code in 1..=8 {
        assert_eq!(HomeFault::from_code(code).unwrap().code(), code);
    }
    for code in 1..=9 {
        assert_eq!(ConfigProblem::from_code(code).unwrap().code(), code);
    }
    assert_eq!(HomeFault::from_code(9), None);
    assert_eq!(ConfigProblem::from_code(10), None);
}

#[test]
fn index_without_encoder_reset_uses_the_feedback_with_a_lagging_drive() {
    // The drive lags 20 periods: at 5 u/s the feedback is 0.1 behind the
    // command when the index is seen.
    let mut r = rig(vec![Axis {
        x: 1.0,
        index: Some((0.5, 1.0)),
        resets_on_index: false,
        lag: 20,
        ..Axis::default()
    }]);
    // A delay line replays its queued commands after the command steps
    // back to the feedback (a real drive would stop): allow for that.
    for c in [
        Command::SetJointMaxFerror {
            joint: 0,
            ferror: 5.0,
        },
        Command::SetJointMinFerror {
            joint: 0,
            ferror: 1.0,
        },
    ] {
        r.cmd(c).unwrap();
    }
    r.configure(
        0,
        HomingConfig {
            offset: 2.0,
            home: 2.0,
            flags: HomeFlags::USE_INDEX | HomeFlags::INDEX_NO_ENCODER_RESET,
            ..cfg(0.0, -5.0)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    assert!(r.m.joint(0).homed, "{:?}", r.events());
    // Within one latch step of the mark, not 0.1 off.
    let mark = r.joint_of(0, 0.5);
    assert!((mark - 2.0).abs() <= 5.0 * T + 1e-9, "mark at {mark}");
}

#[test]
fn switch_homing_is_exact_with_a_lagging_drive_too() {
    let mut r = rig(vec![Axis {
        lag: 5,
        ..switch_axis(0.0, 5.0, 1000.0)
    }]);
    r.configure(
        0,
        HomingConfig {
            offset: 10.0,
            home: 8.0,
            ..cfg(4.0, 0.5)
        },
    );
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.home_to_end(20_000);
    // The switch is read with the feedback, so the lag does not matter.
    let edge = r.joint_of(0, 5.0);
    assert!((10.0 - 0.5 * T - 1e-9..=10.0).contains(&edge), "{edge}");
    assert!(r.events().is_empty());
}

#[test]
fn a_switch_that_changes_while_settling_aborts_with_the_reason() {
    // (state in which the switch is forced, switch forced closed?, velocities, fault)
    let cases = [
        (
            HomeState::FinalBackoffStart,
            false,
            (4.0, 0.5),
            HomeFault::SwitchInactiveBeforeBackoff,
        ),
        (
            HomeState::RiseSearchStart,
            true,
            (4.0, 0.5),
            HomeFault::SwitchActiveBeforeLatch,
        ),
        (
            HomeState::FallSearchStart,
            false,
            (4.0, -0.5),
            HomeFault::SwitchInactiveBeforeLatch,
        ),
    ];
    for (at, closed, (search, latch), fault) in cases {
        let mut r = rig(vec![switch_axis(0.0, 5.0, 1000.0)]);
        r.configure(0, cfg(search, latch));
        r.cmd(Command::Home { joint: 0 }).unwrap();
        while r.m.home_state(0) != at {
            r.cycle();
            assert!(r.cycles < 20_000, "never reached {at}");
        }
        r.axes[0].home_sw = if closed {
            Some((-1000.0, 1000.0))
        } else {
            None
        };
        r.home_to_end(1000);
        assert_eq!(
            r.events(),
            [Event::HomingAborted {
                joint: 0,
                fault,
                state: at,
            }]
        );
        assert!(!r.m.joint(0).homed);
    }
}

#[test]
fn homing_takes_over_a_running_jog_and_ignores_the_jog_override() {
    let mut r = rig(vec![switch_axis(0.0, 5.0, 1000.0)]);
    r.configure(0, cfg(4.0, 0.5));
    r.cmd(Command::JogCont {
        joint: 0,
        vel: -3.0,
    })
    .unwrap();
    r.run(200);
    assert!(r.m.joint(0).vel_cmd < 0.0);
    // A zero override would stop jogs, but homing moves at full speed.
    r.cmd(Command::Scale { scale: 0.0 }).unwrap();
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.cycle();
    assert!(!r.m.joint(0).kb_jog_active, "the jog ended");
    r.home_to_end(20_000);
    assert!(r.m.joint(0).homed);
    assert!(r.joint_of(0, 5.0).abs() <= 0.5 * T + 1e-9);
    assert!(r.events().is_empty());
}

#[test]
fn jog_abort_of_a_joint_not_homing_now_leaves_the_sequence_running() {
    let mut r = rig(vec![
        Axis::default(),
        switch_axis(0.0, 5.0, 1000.0),
        Axis::default(),
    ]);
    r.configure(0, cfg(0.0, 0.0));
    r.configure(
        1,
        HomingConfig {
            sequence: 1,
            ..cfg(4.0, 0.5)
        },
    );
    r.configure(
        2,
        HomingConfig {
            sequence: 2,
            ..cfg(0.0, 0.0)
        },
    );
    r.cmd(Command::Home { joint: -1 }).unwrap();
    while r.m.home_state(1) != HomeState::InitialSearchWait {
        r.cycle();
        assert!(r.cycles < 5000);
    }
    // Joint 0 has finished, joint 2 has not started: a GUI's key release.
    r.cmd(Command::JogAbort { joint: 0 }).unwrap();
    r.cmd(Command::JogAbort { joint: 2 }).unwrap();
    r.home_to_end(20_000);
    assert!(r.m.is_all_homed(), "{:?}", r.events());
    r.cmd(Command::Free).unwrap();
    // The joint homing now is cancelled by its own jog abort.
    r.cmd(Command::Home { joint: 1 }).unwrap();
    r.run(300);
    r.cmd(Command::JogAbort { joint: 1 }).unwrap();
    r.cycle();
    assert!(!r.m.homing_active() && !r.m.joint(1).homed);
    assert!(r.m.joint(0).homed && r.m.joint(2).homed);
}

#[test]
fn a_gantry_partner_with_a_positive_number_is_synchronised_too() {
    let mut r = rig(vec![Axis::default(), Axis::default()]);
    r.configure(
        0,
        HomingConfig {
            sequence: -1,
            ..cfg(0.0, 0.0)
        },
    );
    r.configure(
        1,
        HomingConfig {
            sequence: 1,
            ..cfg(0.0, 0.0)
        },
    );
    for joint in 0..2 {
        assert_eq!(
            r.cmd(Command::JogCont { joint, vel: 1.0 }),
            Err(Reject::SynchronizedJoint {
                joint: joint as usize
            })
        );
    }
}

#[test]
fn locking_indexers_need_unlock_pins_and_no_move_while_locked() {
    let kins = Arc::new(Trivkins::new("X", KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: 1,
            ..MotionConfig::default()
        },
        kins,
    );
    let locking = HomingConfig {
        flags: HomeFlags::UNLOCK_FIRST,
        ..cfg(0.0, 0.0)
    };
    assert_eq!(
        m.command(&Command::SetJointHomingParams {
            joint: 0,
            config: locking
        }),
        Err(Reject::BadHomingConfig {
            joint: 0,
            problem: ConfigProblem::NoUnlockPins
        })
    );
    let mut r = rig(vec![Axis::default()]);
    let abs = HomeFlags::ABSOLUTE_ENCODER | HomeFlags::NO_REHOME | HomeFlags::UNLOCK_FIRST;
    assert_eq!(
        r.cmd(Command::SetJointHomingParams {
            joint: 0,
            config: HomingConfig {
                flags: abs,
                ..locking
            }
        }),
        Err(Reject::BadHomingConfig {
            joint: 0,
            problem: ConfigProblem::LockedFinalMove
        })
    );
    r.configure(
        0,
        HomingConfig {
            flags: abs | HomeFlags::NO_FINAL_MOVE,
            ..locking
        },
    );
}

#[test]
fn extra_joints_come_back_from_posthome_cmd_without_a_jump() {
    let mut r = rig_with_extra(vec![Axis::default(), Axis::default()], 1);
    r.configure(
        1,
        HomingConfig {
            home: 5.0,
            ..cfg(0.0, 0.0)
        },
    );
    r.cmd(Command::Home { joint: 1 }).unwrap();
    r.home_to_end(5000);
    assert!(r.m.joint(1).homed);
    // Homed: the extra joint follows posthome-cmd.
    r.m.joint_inputs[1].posthome_cmd = 20.0;
    r.run(5);
    assert!((r.axes[1].x - 20.0).abs() < 1e-9);
    // Unhoming it while enabled is refused, alone or with the others.
    assert_eq!(
        r.cmd(Command::Unhome { joint: 1 }),
        Err(Reject::ExtraJointEnabled { joint: 1 })
    );
    assert_eq!(
        r.cmd(Command::Unhome { joint: -1 }),
        Err(Reject::ExtraJointEnabled { joint: 1 })
    );
    // Homing it again starts where it is: no following error.
    r.cmd(Command::Home { joint: 1 }).unwrap();
    r.home_to_end(20_000);
    assert!(r.m.joint(1).homed, "{:?}", r.events());
    assert!(r.events().is_empty());
    assert!(r.m.is_enabled());
}

#[test]
fn disabling_mid_homing_says_so() {
    let mut r = rig(vec![switch_axis(0.0, 5.0, 1000.0)]);
    r.configure(0, cfg(4.0, 0.5));
    r.cmd(Command::Home { joint: 0 }).unwrap();
    r.run(300);
    r.cmd(Command::Disable).unwrap();
    r.cycle();
    assert_eq!(
        r.events(),
        [Event::HomingAborted {
            joint: 0,
            fault: HomeFault::Disabled,
            state: HomeState::InitialSearchWait,
        }]
    );
    assert_eq!(
        r.cmd(Command::SetJointMotorOffset {
            joint: 0,
            offset: 1.0
        }),
        Ok(())
    );
}
