//! Tests of moveoff: the state machine driven through both functions as
//! a thread would, then the HAL pins.

use super::logic::*;
use super::*;
use crate::testing::TestHost;
use hal_core::Value::{Bit, Float, S32};

/// A 3-joint instance with its pins, stepped at 1 ms.
struct Sim {
    m: Moveoff,
    i: InputVars,
    o: OutputVars,
    now: i64,
    warnings: u32,
}

impl Sim {
    fn new() -> Sim {
        Sim {
            m: Moveoff::new(3),
            i: InputVars {
                power_on: true,
                move_enable: true,
                apply_offsets: true,
                backtrack_enable: false,
                epsilon: 0.0005,
                waypoint_threshold: 0.02,
                waypoint_sample_secs: 0.02,
                ..Default::default()
            },
            o: OutputVars::default(),
            now: 1_000_000_000,
            warnings: 0,
        }
    }

    /// One servo cycle: read-inputs, write-outputs, pins carried over.
    fn cycle(&mut self) {
        self.i.offset_current = self.o.offset_current;
        self.i.offset_applied = self.o.offset_applied;
        self.i.waypoint_limit = self.o.waypoint_limit;
        if self.m.read_inputs(&mut self.i, self.now, 1_000_000) {
            self.warnings += 1;
        }
        self.o.offset_applied = self.i.offset_applied;
        self.o.waypoint_limit = self.i.waypoint_limit;
        self.m.write_outputs(&mut self.o);
        self.now += 1_000_000;
    }

    fn run(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }
}

#[test]
fn offsets_follow_the_inputs_within_the_limits_and_return() {
    let mut s = Sim::new();
    s.o.pos[..3].copy_from_slice(&[10.0, 20.0, 30.0]);
    s.o.fb[..3].copy_from_slice(&[10.0, 20.0, 30.0]);
    s.i.offset_in = [0.5, -0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    s.cycle();
    assert_eq!(s.o.dbg_state, 0, "the first cycle is still idle");
    s.run(1000);
    assert_eq!(s.m.state(), State::MoveAway);
    assert!((s.o.offset_current[0] - 0.5).abs() < 1e-9);
    assert!((s.o.offset_current[1] + 0.25).abs() < 1e-9);
    assert!(s.o.offset_applied);
    assert_eq!(s.o.pos_plusoffset[0], 10.0 + s.o.offset_current[0]);
    // Settled: feedback minus the offset.
    assert_eq!(s.o.fb_minusoffset[1], 20.0 - s.o.offset_current[1]);
    // Dropping move-enable returns the offsets to zero, then idles.
    s.i.move_enable = false;
    s.run(1000);
    assert!(s.o.offset_current[0].abs() < 0.0005);
    assert!(!s.o.offset_applied);
    assert_eq!(s.m.state(), State::Idle);
    assert_eq!(s.o.pos_plusoffset[0], 10.0);
}

#[test]
fn speed_is_limited() {
    let mut s = Sim::new();
    s.i.offset_in[0] = 5.0;
    s.run(2);
    let mut prev = s.o.offset_current[0];
    for _ in 0..300 {
        s.cycle();
        let v = (s.o.offset_current[0] - prev) / 0.001;
        assert!(v <= 10.0 + 1e-9, "{v}");
        prev = s.o.offset_current[0];
    }
}

#[test]
fn backtracking_returns_along_the_waypoints() {
    let mut s = Sim::new();
    s.i.backtrack_enable = true;
    s.i.offset_in[0] = 1.0;
    s.run(500);
    s.i.offset_in[1] = 1.0;
    s.run(500);
    assert!(s.o.waypoint_ct > 10, "{}", s.o.waypoint_ct);
    s.i.move_enable = false;
    // On the way back joint 0 stays out until joint 1 is home: the path
    // retraces the L instead of cutting the corner.
    let mut corner_kept = true;
    for _ in 0..3000 {
        s.cycle();
        if s.o.offset_current[1] > 0.1 && s.o.offset_current[0] < 0.9 {
            corner_kept = false;
        }
    }
    assert!(corner_kept);
    assert!(!s.o.offset_applied);
    assert_eq!((s.m.state(), s.o.waypoint_ct), (State::Idle, 0));
}

#[test]
fn power_loss_drops_the_offsets_at_once() {
    let mut s = Sim::new();
    s.i.offset_in[2] = 0.3;
    s.run(200);
    assert!(s.o.offset_applied);
    s.i.power_on = false;
    s.run(2);
    assert_eq!(s.o.offset_current[2], 0.0);
    assert_eq!(s.m.state(), State::Idle);
}

#[test]
fn dropping_apply_offsets_while_applied_warns_once() {
    let mut s = Sim::new();
    s.i.offset_in[0] = 0.3;
    s.run(200);
    s.i.apply_offsets = false;
    s.run(3);
    assert!(s.i.warning);
    assert_eq!(s.warnings, 1);
    s.run(1000);
    assert!(!s.i.warning, "cleared once the offsets are gone");
}

#[test]
fn the_waypoint_limit_freezes_the_offsets() {
    let mut s = Sim::new();
    s.i.dbg_waypoint_limit_test = true;
    s.i.waypoint_threshold = 0.0;
    s.i.waypoint_sample_secs = 0.0;
    s.i.offset_in[0] = 1.0;
    s.run(200);
    assert!(s.o.waypoint_limit);
    assert_eq!(s.o.waypoint_ct, TEST_WAYPOINTS as i32);
    assert_eq!(s.o.waypoint_percent_used, 100);
    let frozen = s.o.offset_current[0];
    s.run(10);
    assert_eq!(s.o.offset_current[0], frozen);
    // Removing an enable lets the offset move again.
    s.i.move_enable = false;
    s.run(100);
    assert_ne!(s.o.offset_current[0], frozen);
    assert_eq!(s.m.state(), State::MoveBack);
}

#[test]
fn pins_functions_and_personality() {
    let h = TestHost::new("moveoff-pins");
    h.load(&MODULE, &["names=mv", "personality=2"]).unwrap();
    let mut want: Vec<String> = [
        "power-on bit in 0",
        "move-enable bit in 0",
        "apply-offsets bit in 0",
        "backtrack-enable bit in 1",
        "epsilon float in 0.0005",
        "waypoint-threshold float in 0.02",
        "waypoint-sample-secs float in 0.02",
        "warning bit out 0",
        "offset-applied bit out 0",
        "waypoint-limit bit out 0",
        "waypoint-ct s32 out 0",
        "waypoint-percent-used s32 out 0",
        "dbg-waypoint-limit-test bit in 0",
        "dbg-state s32 out 0",
    ]
    .map(String::from)
    .to_vec();
    for m in 0..2 {
        for p in [
            "offset-in float in 0",
            "pos float in 0",
            "fb float in 0",
            "offset-current float out 0",
            "pos-plusoffset float out 0",
            "fb-minusoffset float out 0",
            "offset-vel float in 10",
            "offset-accel float in 100",
            "offset-min float in -1e20",
            "offset-max float in 1e20",
        ] {
            let (name, rest) = p.split_once(' ').unwrap();
            want.push(format!("{name}-{m} {rest}"));
        }
    }
    let want: Vec<&str> = want.iter().map(String::as_str).collect();
    h.check_pins("mv", &want);
    h.check_params("mv", &[]);
    assert_eq!(h.functs(), ["mv.read-inputs", "mv.write-outputs"]);
    let h = TestHost::new("moveoff-default");
    h.load(&MODULE, &[]).unwrap();
    assert_eq!(
        h.items("moveoff.0.offset-in-2").len(),
        1,
        "3 joints by default"
    );
    assert!(h.items("moveoff.0.offset-in-3").is_empty());
    h.check_load_fails(&MODULE, &["names=x", "personality=10"]);
}

#[test]
fn runs_in_a_thread() {
    let mut h = TestHost::new("moveoff-run");
    h.load(&MODULE, &["names=mv"]).unwrap();
    h.thread(&["mv.read-inputs", "mv.write-outputs"]);
    for p in ["power-on", "move-enable", "apply-offsets"] {
        h.set(&format!("mv.{p}"), Bit(true));
    }
    h.set("mv.pos-1", Float(2.0));
    h.set("mv.offset-in-1", Float(0.001));
    h.run(50);
    let off = crate::testing::float(h.get("mv.offset-current-1"));
    assert!((off - 0.001).abs() < 1e-9, "{off}");
    assert_eq!(h.get("mv.pos-plusoffset-1"), Float(2.0 + off));
    assert_eq!(h.get("mv.offset-applied"), Bit(true));
    assert_eq!(h.get("mv.dbg-state"), S32(1));
}
