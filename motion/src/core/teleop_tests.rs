//! Tests of the world modes: FREE/TELEOP/COORD requests and transitions,
//! axis jogs (compared step by step with a reference planner, since the
//! planner is deterministic), axis limits, kinematics faults, aborts and
//! jog stops, wheels, and entering coordinated mode. Each joint's motor
//! is looped back: its feedback is the previous cycle's motor command.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

use super::*;
use crate::axis::AxisStatus;
use crate::command::{Command, Direction, Quantity, Reject};
use crate::events::Event;
use crate::kins::trivkins::Trivkins;
use crate::kins::KinsError;
use crate::simple_tp::SimpleTp;
use crate::test_support::{Sim, T};

/// A machine of `n` joints on `kins`: joints active, limits ±100, 10 u/s,
/// 100 u/s²; every axis limited to ±50, 10 u/s, 100 u/s².
fn build(kins: Arc<dyn Kinematics>, n: usize) -> Sim {
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: n,
            ..MotionConfig::default()
        },
        kins,
    );
    crate::test_support::configure_test_joints(&mut m);
    crate::test_support::configure_test_axes(&mut m, 50.0);
    Sim::new(m)
}

/// A trivkins machine with one joint per letter of `coords`.
fn machine(coords: &str, kt: KinematicsType) -> Sim {
    let kins = Arc::new(Trivkins::new(coords, kt).unwrap());
    build(kins, coords.len())
}

fn xyz() -> Sim {
    machine("xyz", KinematicsType::Identity)
}

impl Sim {
    /// Enabled, in teleop mode.
    fn teleop(&mut self) {
        self.enable();
        self.cmd(Command::Teleop).unwrap();
        assert_eq!(self.m.state(), MotionState::Teleop);
    }

    fn x(&self, a: usize) -> AxisStatus {
        self.m.axis(a).unwrap()
    }

    fn pose(&self) -> [f64; NUM_AXES] {
        self.m.carte_pos_cmd().0 .0
    }

    /// Every axis's state, to show a refused command changed nothing.
    fn axes(&self) -> Vec<AxisStatus> {
        (0..NUM_AXES).map(|a| self.x(a)).collect()
    }

    /// Jogs joint `j` to `pos` in free mode and waits.
    fn joint_to(&mut self, j: i32, pos: f64) {
        self.cmd(Command::JogAbs {
            joint: j,
            vel: 10.0,
            pos,
        })
        .unwrap();
        self.settle(100_000);
    }
}

/// The planner an axis jog should follow, period by period.
fn reference(start: f64, target: f64, vel: f64, acc: f64) -> SimpleTp {
    SimpleTp {
        pos_cmd: target,
        max_vel: vel,
        max_acc: acc,
        enable: true,
        curr_pos: start,
        ..SimpleTp::default()
    }
}

/// Runs `s` and `r` side by side until both rest, checking that axis `a`
/// and joint `j` follow the reference exactly; returns the periods.
fn follow(s: &mut Sim, r: &mut SimpleTp, a: usize, j: usize) -> usize {
    for n in 0..1_000_000 {
        let prev = s.j(j).pos_cmd;
        s.cycle();
        r.update(T, 1.0);
        assert_eq!(s.pose()[a], r.curr_pos, "axis at period {n}");
        assert_eq!(s.j(j).pos_cmd, r.curr_pos, "joint at period {n}");
        assert_eq!(s.j(j).coarse_pos, r.curr_pos);
        assert_eq!(s.j(j).vel_cmd, (r.curr_pos - prev) / T);
        assert_eq!(s.x(a).teleop_vel_cmd, r.curr_vel);
        assert_eq!(s.m.in_position(), !r.active, "in position at period {n}");
        if !r.active {
            return n + 1;
        }
    }
    panic!("never came to rest");
}

// ------------------------------------------------------------------------
// Mode transitions

#[test]
fn a_mode_requested_while_disabled_is_entered_on_enable_and_kept_over_a_disable() {
    let mut s = xyz();
    s.run(2);
    assert_eq!(s.cmd(Command::Teleop), Ok(()));
    assert_eq!(s.m.state(), MotionState::Disabled, "still disabled");
    assert!(s.m.teleop_mode() && !s.m.coord_mode());
    s.cycle();
    assert_eq!(s.m.state(), MotionState::Disabled);
    s.enable();
    assert_eq!(s.m.state(), MotionState::Teleop);
    assert!(s.m.in_position());
    assert_eq!(s.m.carte_pos_cmd(), (Pose::ZERO, true));
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert_eq!(s.m.state(), MotionState::Disabled);
    assert!(s.m.teleop_mode(), "the mode survives a disable");
    s.enable();
    assert_eq!(s.m.state(), MotionState::Teleop);

    // Coordinated likewise, and free again.
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    s.cmd(Command::Coord).unwrap();
    assert!(s.m.coord_mode() && !s.m.teleop_mode());
    s.enable();
    assert_eq!(s.m.state(), MotionState::Coord);
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    s.cmd(Command::Free).unwrap();
    assert!(!s.m.coord_mode() && !s.m.teleop_mode());
    s.enable();
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(s.events().is_empty());
}

#[test]
fn entering_teleop_from_free_takes_the_pose_from_the_joints() {
    let mut s = xyz();
    s.enable();
    s.joint_to(0, 1.25);
    s.joint_to(2, -3.5);
    s.m.error = true;
    assert_eq!(s.cmd(Command::Teleop), Ok(()));
    // At once, not at the next cycle.
    assert_eq!(s.m.state(), MotionState::Teleop);
    assert!(s.m.teleop_mode());
    assert!(!s.m.error(), "entering a mode clears the motion error");
    let (pose, ok) = s.m.carte_pos_cmd();
    assert!(ok);
    assert_eq!(pose.0[..3], [s.j(0).pos_cmd, 0.0, s.j(2).pos_cmd]);
    for a in 0..NUM_AXES {
        let x = s.x(a);
        assert_eq!(x.teleop_pos, pose.0[a]);
        assert_eq!(x.teleop_pos_cmd, pose.0[a]);
        assert_eq!(x.teleop_vel_cmd, 0.0);
        assert!(!x.teleop_tp_enable && !x.teleop_tp_active && !x.kb_jog_active);
    }
    for j in 0..3 {
        assert!(!s.j(j).free_tp_enable, "free planners off in teleop");
    }
    let before: Vec<f64> = (0..3).map(|j| s.j(j).pos_cmd).collect();
    s.run(50);
    let after: Vec<f64> = (0..3).map(|j| s.j(j).pos_cmd).collect();
    assert_eq!(before, after, "nothing moves");
    assert!(s.m.in_position());
    assert!((0..3).all(|j| s.j(j).vel_cmd == 0.0));
}

#[test]
fn leaving_teleop_for_free_starts_the_joint_planners_at_rest() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogIncr {
        axis: 1,
        vel: 5.0,
        offset: 0.75,
    })
    .unwrap();
    s.settle(10_000);
    let y = s.j(1).pos_cmd;
    assert!((y - 0.75).abs() < 1e-6);
    s.cmd(Command::Free).unwrap();
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(!s.m.teleop_mode());
    for j in 0..3 {
        let js = s.j(j);
        assert_eq!(js.free_pos_cmd, js.pos_cmd);
        assert!(!js.free_tp_enable && !js.free_tp_active);
    }
    assert!(!s.x(1).teleop_tp_enable);
    s.run(20);
    assert_eq!(s.j(1).pos_cmd, y, "no jump, no drift");
    assert_eq!(s.pose()[1], y, "the pose is the forward kinematics again");
    // Joint jogs work again.
    s.cmd(Command::JogIncr {
        joint: 1,
        vel: 5.0,
        offset: 0.25,
    })
    .unwrap();
    s.settle(10_000);
    assert!((s.j(1).pos_cmd - 1.0).abs() < 1e-6);
}

#[test]
fn mode_changes_are_refused_while_anything_moves() {
    let mut s = xyz();
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 2.0 }).unwrap();
    // Refused even before the planner has run.
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotInPosition));
    s.run(10);
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotInPosition));
    assert_eq!(s.cmd(Command::Coord), Err(Reject::NotInPosition));
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(!s.m.teleop_mode() && !s.m.coord_mode());
    assert_eq!(s.cmd(Command::Free), Ok(()), "already there: nothing to do");
    // Still moving while braking after an abort.
    s.cmd(Command::JogAbort { joint: 0 }).unwrap();
    s.cycle();
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotInPosition));
    s.settle(10_000);
    s.cmd(Command::Teleop).unwrap();

    s.cmd(Command::AxisJogCont { axis: 2, vel: 1.0 }).unwrap();
    assert_eq!(s.cmd(Command::Free), Err(Reject::NotInPosition));
    s.run(5);
    let axes = s.axes();
    assert_eq!(s.cmd(Command::Free), Err(Reject::NotInPosition));
    assert_eq!(s.cmd(Command::Coord), Err(Reject::NotInPosition));
    assert_eq!(s.axes(), axes, "a refusal changes nothing");
    assert_eq!(s.cmd(Command::Teleop), Ok(()), "same mode: accepted");
    assert!(s.x(2).kb_jog_active, "and the jog goes on");
    s.cmd(Command::AxisJogAbort { axis: 2 }).unwrap();
    s.settle(10_000);
    s.cmd(Command::Coord).unwrap();
    assert_eq!(s.m.state(), MotionState::Coord);
}

#[test]
fn teleop_and_coord_need_homed_joints_unless_the_kinematics_are_identity() {
    let mut s = machine("xyz", KinematicsType::Both);
    s.run(2);
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotHomed));
    assert_eq!(s.cmd(Command::Coord), Err(Reject::NotHomed));
    assert!(!s.m.teleop_mode() && !s.m.coord_mode());
    s.enable();
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotHomed));
    assert_eq!(s.cmd(Command::Coord), Err(Reject::NotHomed));
    assert_eq!(s.m.state(), MotionState::Free);
    assert_eq!(
        Reject::NotHomed.to_string(),
        "all joints must be homed before going into teleop/coordinated mode"
    );
    s.m.set_homed(0, true);
    s.m.set_homed(1, true);
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotHomed));
    s.m.set_homed(2, true);
    s.cycle();
    assert_eq!(s.cmd(Command::Teleop), Ok(()));
    assert_eq!(s.cmd(Command::Coord), Ok(()));
    assert_eq!(s.cmd(Command::Free), Ok(()), "free mode needs nothing");
    // An inactive joint does not count.
    let mut s = machine("xyz", KinematicsType::Both);
    s.cmd(Command::JointDeactivate { joint: 2 }).unwrap();
    s.m.set_homed(0, true);
    s.m.set_homed(1, true);
    s.enable();
    assert_eq!(s.cmd(Command::Teleop), Ok(()));
    // Identity kinematics: no homing needed.
    let mut s = xyz();
    s.enable();
    assert_eq!(s.cmd(Command::Coord), Ok(()));
}

#[test]
fn forward_only_kinematics_cannot_enter_a_world_mode() {
    let mut s = machine("xyz", KinematicsType::ForwardOnly);
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.enable();
    for c in [Command::Teleop, Command::Coord] {
        assert!(matches!(s.cmd(c), Err(Reject::Unsupported { .. })));
    }
    assert_eq!(s.m.state(), MotionState::Free);
}

#[test]
fn inverse_only_kinematics_keep_no_world_mode_over_a_disable() {
    let mut s = machine("xyz", KinematicsType::InverseOnly);
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.run(2);
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::NotEnabled));
    assert!(!s.m.teleop_mode());
    s.enable();
    s.cmd(Command::Teleop).unwrap();
    s.cycle();
    assert_eq!(s.m.state(), MotionState::Teleop);
    // The world feedback is the world command here.
    assert_eq!(s.m.carte_pos_fb(), s.m.carte_pos_cmd());
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert!(!s.m.teleop_mode(), "forced to free mode");
    s.enable();
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(!s.m.carte_pos_fb().1);
}

#[test]
fn an_unsquared_gantry_is_refused_rather_than_snapped_square() {
    let mut s = machine("xyyz", KinematicsType::Identity);
    s.enable();
    s.joint_to(2, 0.5);
    let r = s.cmd(Command::Teleop);
    assert!(
        matches!(r, Err(Reject::ModeChangeJump { joint: 2, jump }) if (jump - 0.5).abs() < 1e-6),
        "{r:?}"
    );
    assert_eq!(s.cmd(Command::Coord), r);
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(r.unwrap_err().to_string().contains("joint 2"));
    // Squared: both Y joints follow the Y axis.
    s.joint_to(1, 0.5);
    s.cmd(Command::Teleop).unwrap();
    s.cmd(Command::AxisJogIncr {
        axis: 1,
        vel: 5.0,
        offset: 1.0,
    })
    .unwrap();
    s.settle(10_000);
    assert_eq!(s.j(1).pos_cmd, s.j(2).pos_cmd);
    assert!((s.j(2).pos_cmd - 1.5).abs() < 1e-6);
}

/// Identity kinematics over X Y Z that fail on demand.
struct TestKins {
    kins_type: KinematicsType,
    /// Inverse: no solution beyond X = this.
    fail_above: f64,
    /// Inverse: joint 1 is NaN beyond X = this.
    nan_above: f64,
    forward_fails: AtomicBool,
}

impl TestKins {
    fn new(kins_type: KinematicsType) -> TestKins {
        TestKins {
            kins_type,
            fail_above: f64::INFINITY,
            nan_above: f64::INFINITY,
            forward_fails: AtomicBool::new(false),
        }
    }
}

impl Kinematics for TestKins {
    fn name(&self) -> &str {
        "testkins"
    }

    fn kins_type(&self) -> KinematicsType {
        self.kins_type
    }

    fn forward(&self, joints: &[f64], pose: &mut Pose, _: &mut KinsFlags) -> Result<(), KinsError> {
        if self.forward_fails.load(Relaxed) {
            return Err(KinsError::NotConverged);
        }
        for (p, &q) in pose.0.iter_mut().zip(joints.iter().take(3)) {
            *p = q;
        }
        Ok(())
    }

    fn inverse(&self, pose: &Pose, joints: &mut [f64], _: &mut KinsFlags) -> Result<(), KinsError> {
        if pose.0[0] > self.fail_above {
            return Err(KinsError::NoSolution);
        }
        for (q, &p) in joints.iter_mut().zip(pose.0.iter().take(3)) {
            *q = p;
        }
        if pose.0[0] > self.nan_above {
            joints[1] = f64::NAN;
        }
        Ok(())
    }
}

#[test]
fn kinematics_failing_on_entry_refuse_the_mode() {
    let kins = Arc::new(TestKins::new(KinematicsType::Both));
    let mut s = build(kins.clone(), 3);
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.enable();
    kins.forward_fails.store(true, Relaxed);
    assert_eq!(s.cmd(Command::Teleop), Err(Reject::KinematicsFailed));
    assert_eq!(s.m.state(), MotionState::Free);
    kins.forward_fails.store(false, Relaxed);
    assert_eq!(s.cmd(Command::Teleop), Ok(()));
}

#[test]
fn a_remembered_mode_that_cannot_be_resumed_enables_in_free_mode() {
    let kins = Arc::new(TestKins::new(KinematicsType::Both));
    let mut s = build(kins.clone(), 3);
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.cmd(Command::Teleop).unwrap();
    // Unhomed while disabled.
    s.m.set_homed(1, false);
    s.enable();
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(!s.m.teleop_mode());
    assert_eq!(s.events(), [Event::WorldModeDropped]);
    // Forward kinematics failing at enable.
    s.m.set_homed(1, true);
    s.cmd(Command::Coord).unwrap();
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert!(s.m.coord_mode());
    kins.forward_fails.store(true, Relaxed);
    s.enable();
    assert_eq!(s.m.state(), MotionState::Free);
    assert_eq!(s.events(), [Event::WorldModeDropped]);
}

#[test]
fn enabling_in_teleop_starts_at_the_feedback_pose() {
    let mut s = xyz();
    s.cmd(Command::Teleop).unwrap();
    // The motors were moved by hand while disabled.
    s.m.joint_inputs[0].motor_pos_fb = 2.5;
    s.m.cycle(T);
    s.m.joint_inputs[0].motor_pos_fb = 2.5;
    s.m.cycle(T);
    s.cmd(Command::Enable).unwrap();
    s.cycle();
    assert_eq!(s.m.state(), MotionState::Teleop);
    assert_eq!(s.pose()[0], 2.5);
    assert_eq!(s.x(0).teleop_pos, 2.5);
    assert_eq!(s.x(0).teleop_pos_cmd, 2.5);
    s.run(10);
    assert_eq!(s.j(0).pos_cmd, 2.5, "no jump on enable");
}

// ------------------------------------------------------------------------
// Axis jogs

#[test]
fn a_continuous_axis_jog_follows_the_planner_exactly_to_the_axis_limit() {
    let mut s = xyz();
    s.cmd(Command::SetAxisPositionLimits {
        axis: 0,
        min: -2.0,
        max: 3.0,
    })
    .unwrap();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    let x = s.x(0);
    assert!(x.kb_jog_active && x.teleop_tp_enable);
    assert_eq!((x.teleop_pos_cmd, x.teleop_vel_lim), (3.0, 5.0));
    let mut r = reference(0.0, 3.0, 5.0, 100.0);
    let n = follow(&mut s, &mut r, 0, 0);
    // 0.6 s at 5 u/s plus the ramps.
    assert!((650..700).contains(&n), "{n}");
    assert!((s.j(0).pos_cmd - 3.0).abs() <= SimpleTp::tiny_dp(100.0, T));
    assert!(!s.x(0).kb_jog_active, "the jog ends with the motion");
    assert_eq!((s.j(1).pos_cmd, s.j(2).pos_cmd), (0.0, 0.0));
    // Negative: to the other limit.
    s.cmd(Command::AxisJogCont {
        axis: 0,
        vel: -20.0,
    })
    .unwrap();
    assert_eq!(s.x(0).teleop_vel_lim, 10.0, "capped at the axis limit");
    let mut r = reference(r.curr_pos, -2.0, 10.0, 100.0);
    follow(&mut s, &mut r, 0, 0);
}

#[test]
fn incremental_axis_jogs_accumulate_and_stop_exactly() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogIncr {
        axis: 2,
        vel: -4.0,
        offset: 0.5,
    })
    .unwrap();
    s.cmd(Command::AxisJogIncr {
        axis: 2,
        vel: -4.0,
        offset: 0.25,
    })
    .unwrap();
    assert_eq!(s.x(2).teleop_pos_cmd, -0.75);
    let mut r = reference(0.0, -0.75, 4.0, 100.0);
    let mut n = 0;
    // A third increment while moving adds to the target.
    while n < 100 {
        s.cycle();
        r.update(T, 1.0);
        assert_eq!(s.j(2).pos_cmd, r.curr_pos);
        n += 1;
    }
    s.cmd(Command::AxisJogIncr {
        axis: 2,
        vel: 4.0,
        offset: 1.0,
    })
    .unwrap();
    r.pos_cmd = 0.25;
    follow(&mut s, &mut r, 2, 2);
    assert!((s.j(2).pos_cmd - 0.25).abs() <= SimpleTp::tiny_dp(100.0, T));
    // After the planner stopped, the next increment starts from where it is.
    s.cmd(Command::AxisJogIncr {
        axis: 2,
        vel: 4.0,
        offset: 0.5,
    })
    .unwrap();
    let here = s.x(2).teleop_pos;
    assert_eq!(s.x(2).teleop_pos_cmd, r.pos_cmd + 0.5);
    let mut r = reference(here, r.pos_cmd + 0.5, 4.0, 100.0);
    r.curr_vel = 0.0;
    follow(&mut s, &mut r, 2, 2);
}

#[test]
fn absolute_axis_jogs_retarget_and_clamp_into_the_axis_limits() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogAbs {
        axis: 1,
        vel: 8.0,
        pos: 1.5,
    })
    .unwrap();
    let mut r = reference(0.0, 1.5, 8.0, 100.0);
    for _ in 0..200 {
        s.cycle();
        r.update(T, 1.0);
        assert_eq!(s.j(1).pos_cmd, r.curr_pos);
    }
    // Retarget while moving: the last target counts, not an increment.
    s.cmd(Command::AxisJogAbs {
        axis: 1,
        vel: 8.0,
        pos: -0.5,
    })
    .unwrap();
    r.pos_cmd = -0.5;
    follow(&mut s, &mut r, 1, 1);
    assert!((s.j(1).pos_cmd + 0.5).abs() <= SimpleTp::tiny_dp(100.0, T));
    // Beyond the limit: clamped onto it.
    s.cmd(Command::AxisJogAbs {
        axis: 1,
        vel: 10.0,
        pos: 1e6,
    })
    .unwrap();
    assert_eq!(s.x(1).teleop_pos_cmd, 50.0);
    let mut r = reference(s.x(1).teleop_pos, 50.0, 10.0, 100.0);
    follow(&mut s, &mut r, 1, 1);
    assert!((s.j(1).pos_cmd - 50.0).abs() <= SimpleTp::tiny_dp(100.0, T));
    assert!(s.j(1).pos_cmd <= 50.0);
}

#[test]
fn axis_jog_abort_brakes_at_the_acceleration_limit() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    s.run(300);
    assert_eq!(s.x(0).teleop_vel_cmd, 5.0);
    s.cmd(Command::AxisJogAbort { axis: 0 }).unwrap();
    assert!(!s.x(0).kb_jog_active);
    let mut v = 5.0;
    let mut n = 0;
    while s.x(0).teleop_tp_active || n == 0 {
        s.cycle();
        let now = s.x(0).teleop_vel_cmd;
        assert!(
            (v - now - 100.0 * T).abs() < 1e-9 || now == 0.0,
            "{v} -> {now}"
        );
        v = now;
        n += 1;
    }
    assert!((50..=51).contains(&n), "{n}");
    assert!(s.m.in_position());
    // Any axis number 0..8 in any mode; others refused.
    s.cmd(Command::Free).unwrap();
    assert_eq!(s.cmd(Command::AxisJogAbort { axis: 8 }), Ok(()));
    assert_eq!(
        s.cmd(Command::AxisJogAbort { axis: 9 }),
        Err(Reject::NoSuchAxis { axis: 9 })
    );
}

#[test]
fn scale_applies_to_axis_jogs() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::Scale { scale: 0.25 }).unwrap();
    s.cmd(Command::AxisJogCont { axis: 1, vel: 8.0 }).unwrap();
    s.run(500);
    assert_eq!(s.x(1).teleop_vel_cmd, 2.0);
    assert_eq!(s.m.current_vel(), 2.0);
    assert!(s.m.jog_is_active());
}

#[test]
fn refused_axis_jogs_say_why_and_change_nothing() {
    // Long: every refusal of an axis jog in turn, on one machine.
    let mut s = xyz();
    s.run(2);
    let jog = Command::AxisJogCont { axis: 0, vel: 1.0 };
    assert_eq!(s.cmd(jog), Err(Reject::NotEnabled));
    s.enable();
    assert_eq!(s.cmd(jog), Err(Reject::NotTeleopMode));
    assert_eq!(
        Reject::NotTeleopMode.to_string(),
        "motion is not in teleop mode; axes can only be jogged in teleop mode"
    );
    s.cmd(Command::Coord).unwrap();
    assert_eq!(s.cmd(jog), Err(Reject::NotTeleopMode));
    assert_eq!(
        s.cmd(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::NotFreeMode)
    );
    s.cmd(Command::Teleop).unwrap();
    // Joint jogs in teleop.
    for c in [
        Command::JogCont { joint: 0, vel: 1.0 },
        Command::JogIncr {
            joint: 0,
            vel: 1.0,
            offset: 1.0,
        },
        Command::JogAbs {
            joint: 0,
            vel: 1.0,
            pos: 1.0,
        },
    ] {
        assert_eq!(s.cmd(c), Err(Reject::JointJogInTeleop), "{c:?}");
    }
    let axes = s.axes();
    let cases = [
        (
            Command::AxisJogCont { axis: -1, vel: 1.0 },
            Reject::NoSuchAxis { axis: -1 },
        ),
        (
            Command::AxisJogIncr {
                axis: 9,
                vel: 1.0,
                offset: 1.0,
            },
            Reject::NoSuchAxis { axis: 9 },
        ),
        (
            Command::AxisJogCont { axis: 0, vel: 0.0 },
            Reject::BadVelocity { vel: 0.0 },
        ),
        (
            Command::AxisJogAbs {
                axis: 0,
                vel: f64::INFINITY,
                pos: 1.0,
            },
            Reject::BadVelocity { vel: f64::INFINITY },
        ),
        // Trivkins xyz has no A axis.
        (
            Command::AxisJogCont { axis: 3, vel: 1.0 },
            Reject::AxisNotInKinematics { axis: 3 },
        ),
        (
            Command::AxisJogIncr {
                axis: 0,
                vel: 1.0,
                offset: -1.0,
            },
            Reject::BadValue {
                what: Quantity::JogIncrement,
                value: -1.0,
            },
        ),
        (
            Command::AxisJogIncr {
                axis: 0,
                vel: -1.0,
                offset: 50.5,
            },
            Reject::AxisTargetOutsideLimits {
                axis: 0,
                target: -50.5,
                min: -50.0,
                max: 50.0,
            },
        ),
        (
            Command::AxisJogIncr {
                axis: 0,
                vel: 1.0,
                offset: f64::MAX,
            },
            Reject::AxisTargetOutsideLimits {
                axis: 0,
                target: f64::MAX,
                min: -50.0,
                max: 50.0,
            },
        ),
    ];
    for (c, want) in cases {
        assert_eq!(s.cmd(c), Err(want), "{c:?}");
    }
    let r = s.cmd(Command::AxisJogAbs {
        axis: 0,
        vel: 1.0,
        pos: f64::NAN,
    });
    assert!(
        matches!(r, Err(Reject::BadValue { what: Quantity::JogPosition, value }) if value.is_nan()),
        "{r:?}"
    );
    s.m.inputs.jog_inhibit = true;
    assert_eq!(s.cmd(jog), Err(Reject::JogInhibited));
    s.m.inputs.jog_inhibit = false;
    s.m.error = true;
    assert_eq!(s.cmd(jog), Err(Reject::MotionError));
    s.cmd(Command::Abort).unwrap();
    assert!(!s.m.error());
    assert_eq!(s.axes(), axes, "nothing changed");
    s.run(3);
    assert!(s.m.in_position());
    assert_eq!(s.cmd(jog), Ok(()));
}

#[test]
fn a_continuous_jog_from_beyond_a_limit_is_refused_but_back_in_is_fine() {
    let mut s = xyz();
    s.enable();
    s.joint_to(0, 60.0);
    s.cmd(Command::Teleop).unwrap();
    let x0 = s.x(0).teleop_pos;
    assert_eq!(x0, s.j(0).pos_cmd);
    assert!(x0 > 59.99);
    assert_eq!(
        s.cmd(Command::AxisJogCont { axis: 0, vel: 1.0 }),
        Err(Reject::AxisPastLimit {
            axis: 0,
            dir: Direction::Positive
        })
    );
    assert!(Reject::AxisPastLimit {
        axis: 0,
        dir: Direction::Positive
    }
    .to_string()
    .contains("axis X further past its positive limit"));
    // Inwards: to the other limit.
    s.cmd(Command::AxisJogCont {
        axis: 0,
        vel: -10.0,
    })
    .unwrap();
    s.run(100);
    assert!(s.x(0).teleop_pos < x0 - 0.1);
    s.cmd(Command::AxisJogAbort { axis: 0 }).unwrap();
    s.settle(10_000);
    // And the negative side.
    let mut s = xyz();
    s.enable();
    s.joint_to(1, -70.0);
    s.cmd(Command::Teleop).unwrap();
    assert_eq!(
        s.cmd(Command::AxisJogCont { axis: 1, vel: -1.0 }),
        Err(Reject::AxisPastLimit {
            axis: 1,
            dir: Direction::Negative
        })
    );
}

#[test]
fn an_axis_stops_hard_on_a_limit_lowered_under_it_while_jogging() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    while s.x(0).teleop_pos < 1.0 {
        s.cycle();
    }
    assert_eq!(s.x(0).teleop_vel_cmd, 5.0);
    s.cmd(Command::SetAxisPositionLimits {
        axis: 0,
        min: -50.0,
        max: 1.02,
    })
    .unwrap();
    let mut n = 0;
    while s.x(0).teleop_pos < 1.02 {
        s.cycle();
        assert!(s.x(0).teleop_pos <= 1.02);
        n += 1;
        assert!(n < 100);
    }
    // On the limit exactly, stopped, the jog over.
    assert_eq!(s.j(0).pos_cmd, 1.02);
    assert_eq!(s.x(0).teleop_vel_cmd, 0.0);
    assert!(!s.x(0).kb_jog_active && !s.x(0).teleop_tp_enable);
    assert!(s.m.in_position());
    s.run(10);
    assert_eq!(s.j(0).pos_cmd, 1.02);
    assert_eq!(s.j(0).vel_cmd, 0.0);
}

#[test]
fn abort_stops_every_axis_jog_at_its_own_acceleration() {
    let mut s = xyz();
    s.cmd(Command::SetAxisAccLimit { axis: 1, acc: 50.0 })
        .unwrap();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    s.cmd(Command::AxisJogCont { axis: 1, vel: -5.0 }).unwrap();
    s.run(300);
    assert_eq!((s.x(0).teleop_vel_cmd, s.x(1).teleop_vel_cmd), (5.0, -5.0));
    s.m.error = true;
    s.cmd(Command::Abort).unwrap();
    assert!(!s.m.error());
    assert!(!s.x(0).kb_jog_active && !s.x(1).kb_jog_active);
    s.cycle();
    // Each axis on its own: not a path-coordinated stop.
    assert!((s.x(0).teleop_vel_cmd - (5.0 - 100.0 * T)).abs() < 1e-9);
    assert!((s.x(1).teleop_vel_cmd - (-5.0 + 50.0 * T)).abs() < 1e-9);
    let n0 = (0..)
        .find(|_| {
            s.cycle();
            s.x(0).teleop_vel_cmd == 0.0
        })
        .unwrap();
    assert!(s.x(1).teleop_vel_cmd < 0.0, "Y brakes slower");
    s.settle(10_000);
    assert!((48..=50).contains(&n0), "{n0}");
    assert!(!s.m.jog_is_active());
}

#[test]
fn jog_stop_inputs_end_axis_jogs() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 2, vel: 5.0 }).unwrap();
    s.run(300);
    assert!(s.m.jog_is_active());
    s.m.inputs.jog_stop = true;
    s.cycle();
    s.m.inputs.jog_stop = false;
    assert_eq!(s.events(), [Event::JogStopped { immediate: false }]);
    assert!(!s.x(2).kb_jog_active);
    assert!((s.x(2).teleop_vel_cmd - (5.0 - 100.0 * T)).abs() < 1e-9);
    s.settle(10_000);

    s.cmd(Command::AxisJogCont { axis: 2, vel: 5.0 }).unwrap();
    s.run(300);
    s.m.inputs.jog_stop_immediate = true;
    s.cycle();
    s.m.inputs.jog_stop_immediate = false;
    assert_eq!(s.events(), [Event::JogStopped { immediate: true }]);
    assert_eq!(s.x(2).teleop_vel_cmd, 0.0);
    let here = s.j(2).pos_cmd;
    s.run(5);
    assert_eq!(s.j(2).pos_cmd, here);
    assert!(s.m.in_position());
}

#[test]
fn a_probe_contact_stops_axis_jogs_at_once() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    s.run(100);
    s.m.inputs.probe_input = true;
    s.cycle();
    assert_eq!(s.events(), [Event::ProbeTrippedDuringAxisJog]);
    assert_eq!(s.x(0).teleop_vel_cmd, 0.0);
    assert!(s.m.in_position());
    // Only the rising edge.
    s.run(3);
    assert!(s.events().is_empty());
}

#[test]
fn the_inverse_kinematics_failing_in_teleop_disables_at_once() {
    let mut kins = TestKins::new(KinematicsType::Identity);
    kins.fail_above = 0.5;
    let mut s = build(Arc::new(kins), 3);
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    let mut last_good = 0.0;
    for _ in 0..10_000 {
        s.cycle();
        if !s.m.is_enabled() {
            break;
        }
        last_good = s.j(0).pos_cmd;
    }
    assert!(!s.m.is_enabled(), "disabled in the failing cycle");
    assert_eq!(s.m.state(), MotionState::Disabled);
    assert!(s.m.error());
    assert!(s.m.teleop_mode(), "the mode is kept");
    assert_eq!(s.events(), [Event::InverseKinsFailed]);
    assert!(last_good <= 0.5);
    assert!(!s.j(0).enabled, "amplifiers off");
    assert!(!s.x(0).teleop_tp_enable && s.x(0).teleop_vel_cmd == 0.0);
    s.run(5);
    assert!(s.events().is_empty(), "reported once");
    // Enabling again resumes teleop at the feedback, inside the reach.
    s.enable();
    assert_eq!(s.m.state(), MotionState::Teleop);
    assert!(!s.m.error());
    assert!(s.x(0).teleop_pos <= 0.5);
}

#[test]
fn a_non_finite_joint_from_the_inverse_kinematics_disables() {
    let mut kins = TestKins::new(KinematicsType::Identity);
    kins.nan_above = 0.2;
    let mut s = build(Arc::new(kins), 3);
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    for _ in 0..10_000 {
        s.cycle();
        if !s.m.is_enabled() {
            break;
        }
        assert!(s.j(1).pos_cmd.is_finite());
    }
    assert!(!s.m.is_enabled());
    assert_eq!(s.events(), [Event::NonFiniteJoint { joint: 1 }]);
    assert!(s.j(1).pos_cmd.is_finite(), "the NaN never reached a joint");
    assert!(s.j(1).motor_pos_cmd.is_finite());
}

#[test]
fn disabling_while_jogging_stops_axes_at_once_and_enabling_does_not_move() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 1, vel: 5.0 }).unwrap();
    s.run(200);
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert!(!s.x(1).teleop_tp_enable && !s.x(1).kb_jog_active);
    assert_eq!(s.x(1).teleop_vel_cmd, 0.0);
    assert!(s.m.in_position());
    s.run(3);
    let y = s.j(1).pos_fb;
    s.enable();
    assert_eq!(s.x(1).teleop_pos, y);
    s.run(10);
    assert_eq!(s.j(1).pos_cmd, y);
    assert!(s.m.in_position());
}

#[test]
fn an_amp_fault_in_teleop_keeps_the_mode_for_the_next_enable() {
    let mut s = xyz();
    s.teleop();
    s.m.joint_inputs[2].amp_fault = true;
    s.m.cycle(T);
    assert!(!s.m.is_enabled());
    assert!(s.m.teleop_mode());
    s.m.joint_inputs[2].amp_fault = false;
    s.cmd(Command::Abort).unwrap();
    s.enable();
    assert_eq!(s.m.state(), MotionState::Teleop);
}

// ------------------------------------------------------------------------
// Wheels

#[test]
fn axis_wheels_move_counts_times_scale_in_teleop_only() {
    let mut s = xyz();
    s.enable();
    s.m.axis_inputs[0].jog_enable = true;
    s.m.axis_inputs[0].jog_scale = 0.01;
    s.cycle();
    // Free mode: counts are consumed but move nothing, now or later.
    s.m.axis_inputs[0].jog_counts = 100;
    s.run(5);
    s.cmd(Command::Teleop).unwrap();
    s.run(5);
    assert_eq!(s.j(0).pos_cmd, 0.0);
    assert!(s.m.in_position());
    s.m.axis_inputs[0].jog_counts = 150;
    s.cycle();
    assert!(s.x(0).wheel_jog_active);
    assert_eq!(s.x(0).teleop_pos_cmd, 0.5);
    assert_eq!(s.x(0).teleop_vel_lim, 10.0);
    assert!(s.m.jog_is_active());
    // A keyboard jog waits for the wheel.
    assert_eq!(
        s.cmd(Command::AxisJogCont { axis: 0, vel: 1.0 }),
        Err(Reject::AxisWheelJogActive { axis: 0 })
    );
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 0.5).abs() <= SimpleTp::tiny_dp(100.0, T));
    assert!(!s.x(0).wheel_jog_active);
    // Jog-inhibit: consumed, never applied.
    s.m.inputs.jog_inhibit = true;
    s.m.axis_inputs[0].jog_counts = 250;
    s.run(3);
    s.m.inputs.jog_inhibit = false;
    s.run(3);
    assert!(s.m.in_position());
    assert!((s.j(0).pos_cmd - 0.5).abs() <= SimpleTp::tiny_dp(100.0, T));
    // Beyond the limit: skipped; other axes still work.
    s.m.axis_inputs[0].jog_counts = 250 + 10_000;
    s.m.axis_inputs[1].jog_enable = true;
    s.m.axis_inputs[1].jog_scale = -0.001;
    s.m.axis_inputs[1].jog_counts = 100;
    s.cycle();
    assert_eq!(s.x(0).teleop_pos_cmd, 0.5, "target unchanged");
    assert!(!s.x(0).wheel_jog_active);
    assert_eq!(s.x(1).teleop_pos_cmd, -0.1);
    s.settle(10_000);
    // Not on an axis the kinematics lack.
    s.m.axis_inputs[4].jog_enable = true;
    s.m.axis_inputs[4].jog_scale = 1.0;
    s.m.axis_inputs[4].jog_counts = 3;
    s.cycle();
    assert!(!s.x(4).wheel_jog_active);
}

#[test]
fn velocity_mode_wheels_stay_within_a_stopping_distance() {
    let mut s = xyz();
    s.teleop();
    s.m.axis_inputs[1].jog_enable = true;
    s.m.axis_inputs[1].jog_scale = 1.0;
    s.m.axis_inputs[1].jog_vel_mode = true;
    s.m.axis_inputs[1].jog_accel_fraction = 0.5;
    s.cycle();
    s.m.axis_inputs[1].jog_counts = 20;
    s.cycle();
    // v² / (2 a) = 100 / (2 · 50) = 1 ahead of the axis (at 0) at most.
    let x = s.x(1);
    assert_eq!(x.teleop_pos_cmd, 1.0);
    // The planner ran with half the acceleration.
    assert_eq!(x.teleop_vel_cmd, 50.0 * T);
}

// ------------------------------------------------------------------------
// Coordinated mode, limits override, soft limits

#[test]
fn coordinated_mode_holds_the_pose() {
    let mut s = xyz();
    s.enable();
    s.joint_to(0, -4.0);
    s.joint_to(1, 2.0);
    s.cmd(Command::Coord).unwrap();
    assert_eq!(s.m.state(), MotionState::Coord);
    assert!(s.m.coord_mode() && !s.m.teleop_mode());
    let pose = s.pose();
    let (x, y) = (s.j(0).pos_cmd, s.j(1).pos_cmd);
    assert!((x + 4.0).abs() < 1e-6 && (y - 2.0).abs() < 1e-6);
    assert_eq!(pose[..3], [x, y, 0.0]);
    for _ in 0..500 {
        s.cycle();
        assert!(s.m.in_position());
        assert_eq!(s.pose(), pose);
        assert_eq!((s.j(0).pos_cmd, s.j(1).pos_cmd), (x, y));
        assert_eq!(s.j(0).coarse_pos, x);
        assert_eq!(s.j(0).vel_cmd, 0.0);
    }
    assert_eq!(s.m.current_vel(), 0.0);
    // Between the world modes the pose is kept.
    s.cmd(Command::Teleop).unwrap();
    assert_eq!(s.pose(), pose);
    assert_eq!(s.x(0).teleop_pos, x);
    s.cmd(Command::AxisJogIncr {
        axis: 0,
        vel: 5.0,
        offset: 1.0,
    })
    .unwrap();
    s.settle(10_000);
    s.cmd(Command::Coord).unwrap();
    let held = s.pose();
    assert!((held[0] + 3.0).abs() < 1e-6);
    s.run(50);
    assert_eq!(s.pose(), held);
    assert_eq!(s.j(0).pos_cmd, held[0]);
}

#[test]
fn entering_coord_ends_a_limit_override_and_axis_jogs_end_it_in_teleop() {
    let mut s = xyz();
    s.run(2);
    // A tripped switch while disabled, overridden, then enabled.
    s.m.joint_inputs[0].pos_lim_sw = true;
    s.cycle();
    s.cmd(Command::OverrideLimits { joint: 0 }).unwrap();
    assert_eq!(s.m.override_limit_mask(), 0b10);
    s.enable();
    s.cmd(Command::Teleop).unwrap();
    assert_eq!(s.m.override_limit_mask(), 0b10, "teleop keeps it");
    s.cycle();
    assert!(s.m.is_enabled());
    // The axis jog off the switch ends the override when it ends.
    s.cmd(Command::AxisJogIncr {
        axis: 0,
        vel: -5.0,
        offset: 0.5,
    })
    .unwrap();
    s.run(10);
    s.m.joint_inputs[0].pos_lim_sw = false;
    assert_eq!(s.m.override_limit_mask(), 0b10);
    s.settle(10_000);
    assert_eq!(s.m.override_limit_mask(), 0);

    // Coordinated mode clears it at once.
    s.m.joint_inputs[0].pos_lim_sw = true;
    s.cycle();
    assert!(!s.m.is_enabled());
    s.cmd(Command::OverrideLimits { joint: 0 }).unwrap();
    s.cmd(Command::Free).unwrap();
    s.enable();
    assert_eq!(s.m.override_limit_mask(), 0b10);
    s.cmd(Command::Coord).unwrap();
    assert_eq!(s.m.override_limit_mask(), 0);
    s.cycle();
    assert!(!s.m.is_enabled(), "the switch counts again");
}

#[test]
fn a_soft_limit_in_teleop_stops_axis_jogs_and_keeps_the_error_set() {
    let mut s = xyz();
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -1.0,
        max: 1.0,
    })
    .unwrap();
    for j in 0..3 {
        s.m.set_homed(j, true);
    }
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 5.0 }).unwrap();
    while !s.m.on_soft_limit() {
        s.cycle();
    }
    assert!(s.m.error());
    assert_eq!(
        s.events(),
        [Event::SoftLimitExceeded {
            joint: 0,
            dir: Direction::Positive
        }]
    );
    assert!(!s.x(0).kb_jog_active && !s.x(0).teleop_tp_enable);
    s.settle(10_000);
    assert_eq!(
        s.cmd(Command::AxisJogCont { axis: 0, vel: -5.0 }),
        Err(Reject::MotionError)
    );
    s.cmd(Command::Abort).unwrap();
    s.cycle();
    assert!(s.m.error(), "set again every cycle while on the limit");
    // Jog off in free mode.
    s.cmd(Command::Free).unwrap();
    s.cmd(Command::JogCont {
        joint: 0,
        vel: -5.0,
    })
    .unwrap();
    s.run(100);
    assert!(!s.m.on_soft_limit());
}

#[test]
fn axis_configuration_is_validated() {
    let mut s = xyz();
    let c = |axis, min, max| Command::SetAxisPositionLimits { axis, min, max };
    assert_eq!(
        s.cmd(c(0, 2.0, 1.0)),
        Err(Reject::LimitsReversed { min: 2.0, max: 1.0 })
    );
    assert!(matches!(
        s.cmd(c(0, f64::NAN, 1.0)),
        Err(Reject::BadValue {
            what: Quantity::MinimumLimit,
            ..
        })
    ));
    assert!(matches!(
        s.cmd(c(0, 0.0, f64::INFINITY)),
        Err(Reject::BadValue {
            what: Quantity::MaximumLimit,
            ..
        })
    ));
    assert_eq!(s.cmd(c(9, 0.0, 1.0)), Err(Reject::NoSuchAxis { axis: 9 }));
    assert_eq!(
        s.cmd(c(i32::MIN, 0.0, 1.0)),
        Err(Reject::NoSuchAxis { axis: i32::MIN })
    );
    for vel in [0.0, -1.0, f64::NAN] {
        assert!(s.cmd(Command::SetAxisVelLimit { axis: 0, vel }).is_err());
        assert!(s
            .cmd(Command::SetAxisAccLimit { axis: 0, acc: vel })
            .is_err());
    }
    assert_eq!(s.x(0).config.vel_limit, 10.0, "unchanged");
    s.cmd(c(8, 1.0, 1.0)).unwrap();
    s.cmd(Command::SetAxisVelLimit { axis: 8, vel: 3.0 })
        .unwrap();
    s.cmd(Command::SetAxisAccLimit { axis: 8, acc: 7.0 })
        .unwrap();
    let w = s.x(8).config;
    assert_eq!(
        (w.min_pos_limit, w.max_pos_limit, w.vel_limit, w.acc_limit),
        (1.0, 1.0, 3.0, 7.0)
    );
    assert!(s.m.axis(9).is_none());
    assert!(s.m.axis_in_kinematics(2) && !s.m.axis_in_kinematics(3));
}

#[test]
fn random_commands_never_panic() {
    // A small fuzz of the command path in every mode.
    let mut s = machine("xyyz", KinematicsType::Identity);
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let vals = [
        0.0,
        1.0,
        -1.0,
        0.5,
        60.0,
        -1e300,
        f64::NAN,
        f64::INFINITY,
        f64::MAX,
    ];
    for _ in 0..20_000 {
        let r = next();
        let a = (r % 12) as i32 - 1;
        let v = vals[(r >> 8) as usize % vals.len()];
        let w = vals[(r >> 16) as usize % vals.len()];
        let c = match (r >> 24) % 14 {
            0 => Command::AxisJogCont { axis: a, vel: v },
            1 => Command::AxisJogIncr {
                axis: a,
                vel: v,
                offset: w,
            },
            2 => Command::AxisJogAbs {
                axis: a,
                vel: v,
                pos: w,
            },
            3 => Command::AxisJogAbort { axis: a },
            4 => Command::SetAxisPositionLimits {
                axis: a,
                min: v.min(w),
                max: v.max(w),
            },
            5 => Command::SetAxisVelLimit { axis: a, vel: v },
            6 => Command::SetAxisAccLimit { axis: a, acc: v },
            7 => Command::Teleop,
            8 => Command::Coord,
            9 => Command::Free,
            10 => Command::Enable,
            11 => Command::Abort,
            12 => Command::JogCont { joint: a, vel: v },
            _ => Command::Disable,
        };
        let _ = s.cmd(c);
        s.m.axis_inputs[(r >> 40) as usize % NUM_AXES].jog_counts = (r >> 44) as i32;
        s.m.axis_inputs[(r >> 48) as usize % NUM_AXES].jog_enable = r & 1 != 0;
        s.m.axis_inputs[(r >> 52) as usize % NUM_AXES].jog_scale = w;
        s.cycle();
        for j in 0..s.m.num_joints() {
            assert!(s.j(j).pos_cmd.is_finite() || !s.m.is_enabled());
        }
    }
}

#[test]
fn a_joint_cannot_be_deactivated_while_teleop_moves_it() {
    let mut s = xyz();
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 1, vel: 2.0 }).unwrap();
    assert_eq!(
        s.cmd(Command::JointDeactivate { joint: 1 }),
        Err(Reject::JointMoving { joint: 1 })
    );
    s.run(10);
    assert_eq!(
        s.cmd(Command::JointDeactivate { joint: 0 }),
        Err(Reject::JointMoving { joint: 0 })
    );
    s.cmd(Command::AxisJogAbort { axis: 1 }).unwrap();
    s.settle(10_000);
    assert_eq!(s.cmd(Command::JointDeactivate { joint: 1 }), Ok(()));
}

/// Switchable identity kinematics: type 1 shifts X by +10 (joint 0 = X −
/// 10).
struct ShiftKins {
    shifted: AtomicBool,
}

impl Kinematics for ShiftKins {
    fn name(&self) -> &str {
        "shiftkins"
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Identity
    }

    fn forward(&self, joints: &[f64], pose: &mut Pose, _: &mut KinsFlags) -> Result<(), KinsError> {
        for (p, &q) in pose.0.iter_mut().zip(joints.iter().take(3)) {
            *p = q;
        }
        if self.shifted.load(Relaxed) {
            pose.0[0] += 10.0;
        }
        Ok(())
    }

    fn inverse(&self, pose: &Pose, joints: &mut [f64], _: &mut KinsFlags) -> Result<(), KinsError> {
        for (q, &p) in joints.iter_mut().zip(pose.0.iter().take(3)) {
            *q = p;
        }
        if self.shifted.load(Relaxed) {
            joints[0] -= 10.0;
        }
        Ok(())
    }

    fn is_switchable(&self) -> bool {
        true
    }

    fn switch_to(&self, kins_type: i32) -> Result<(), KinsError> {
        self.shifted.store(kins_type == 1, Relaxed);
        Ok(())
    }
}

#[test]
fn a_kinematics_switch_in_teleop_restarts_the_axes_without_a_jump() {
    let kins = Arc::new(ShiftKins {
        shifted: AtomicBool::new(false),
    });
    let mut s = build(kins, 3);
    s.teleop();
    s.cmd(Command::AxisJogCont { axis: 0, vel: 2.0 }).unwrap();
    s.run(100);
    let q0 = s.j(0).pos_cmd;
    assert!(q0 > 0.0);
    s.m.inputs.switchkins_type = 1.0;
    s.cycle();
    assert!(!s.x(0).kb_jog_active, "the jog ended");
    assert_eq!(
        s.x(0).teleop_pos,
        q0 + 10.0,
        "the pose in the new kinematics"
    );
    // Only the rounding of (q + 10) − 10.
    assert!(
        (s.j(0).pos_cmd - q0).abs() < 1e-12,
        "the joint did not jump"
    );
    let q = s.j(0).pos_cmd;
    s.run(10);
    assert_eq!(s.j(0).pos_cmd, q);
    assert!(s.m.in_position());
}
