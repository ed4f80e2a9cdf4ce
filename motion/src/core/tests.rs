//! Tests of the controller core with simulated joints: each joint's motor
//! follows its command through a delay line of a few servo periods (a
//! motor with lag), and switches and fault inputs are set by the test.

use super::*;
use crate::command::{Command, Direction, Reject};
use crate::events::Event;
use crate::kins::trivkins::Trivkins;
use crate::simple_tp::SimpleTp;
use crate::test_support::{Sim, T};

/// A machine of `n` trivkins joints (X, Y, Z, ...), all active, with limits
/// ±100, 10 u/s, 100 u/s², following error 0.01..1.
fn machine(n: usize, kt: KinematicsType) -> Sim {
    let kins = Arc::new(Trivkins::new(&"XYZABCUVW"[..n], kt).unwrap());
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: n,
            num_misc_error: 2,
            ..MotionConfig::default()
        },
        kins,
    );
    crate::test_support::configure_test_joints(&mut m);
    Sim::new(m)
}

#[test]
fn starts_disabled_with_commands_tracking_feedback() {
    let mut s = machine(3, KinematicsType::Identity);
    s.stuck = vec![Some(1.5), Some(-2.0), Some(0.25)];
    s.run(3);
    assert_eq!(s.m.state(), MotionState::Disabled);
    assert!(!s.m.is_enabled());
    for (j, fb) in [1.5, -2.0, 0.25].into_iter().enumerate() {
        let js = s.j(j);
        assert_eq!(js.pos_fb, fb);
        assert_eq!(js.pos_cmd, fb, "disabled: the command follows feedback");
        assert_eq!(js.motor_pos_cmd, fb);
        assert!(!js.enabled);
        assert_eq!(
            js.ferror, 0.0,
            "the previous cycle's command was the feedback"
        );
    }
    assert_eq!(s.m.carte_pos_fb().0 .0[..3], [1.5, -2.0, 0.25]);
    assert_eq!(s.m.carte_pos_cmd().0, s.m.carte_pos_fb().0);
    assert!(s.m.is_all_homed() || !s.m.carte_pos_fb().1);
}

#[test]
fn enable_needs_the_enable_input_and_switches_active_amps_on() {
    let mut s = machine(2, KinematicsType::Identity);
    s.cmd(Command::JointDeactivate { joint: 1 }).unwrap();
    s.m.inputs.enable = false;
    assert_eq!(s.cmd(Command::Enable), Err(Reject::EnableInputFalse));
    s.cycle();
    assert!(!s.m.is_enabled());
    s.m.inputs.enable = true;
    s.stuck[0] = Some(3.0);
    s.run(2);
    s.stuck[0] = None;
    s.enable();
    assert_eq!(s.m.state(), MotionState::Free);
    assert!(s.j(0).enabled, "active joint: amp on");
    assert!(!s.j(1).enabled, "inactive joint: amp stays off");
    // No jump: the planner starts where the command was.
    s.run(5);
    assert_eq!(s.j(0).pos_cmd, 3.0);
    assert_eq!(s.j(0).motor_pos_cmd, 3.0);
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    assert!(!s.m.is_enabled() && !s.j(0).enabled);
    assert_eq!(s.m.state(), MotionState::Disabled);
}

#[test]
fn the_seven_positions_in_cycle_order() {
    let mut s = machine(1, KinematicsType::Identity);
    s.cmd(Command::SetJointMotorOffset {
        joint: 0,
        offset: 0.5,
    })
    .unwrap();
    s.cmd(Command::SetJointBacklash {
        joint: 0,
        backlash: 0.02,
    })
    .unwrap();
    s.run(2);
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 2.0 }).unwrap();
    for _ in 0..200 {
        let prev = s.j(0);
        let motor_fb = prev.motor_pos_cmd - 0.001;
        s.m.joint_inputs[0].motor_pos_fb = motor_fb;
        s.m.cycle(T);
        let now = s.j(0);
        // (5) read, (6) = (5) − (previous filt + offset).
        assert_eq!(now.motor_pos_fb, motor_fb);
        assert_eq!(now.pos_fb, motor_fb - (prev.backlash_filt + 0.5));
        // Following error against the previous cycle's command.
        assert_eq!(now.ferror, prev.pos_cmd - now.pos_fb);
        // (7) forward kins of (6).
        assert_eq!(s.m.carte_pos_fb().0 .0[0], now.pos_fb);
        // (2) = (3) from the free planner; (1) = kins of the previous (2).
        assert_eq!(now.coarse_pos, now.pos_cmd);
        assert_eq!(s.m.carte_pos_cmd().0 .0[0], prev.coarse_pos);
        // (4) = (3) + filt + offset, with this cycle's filt.
        assert_eq!(
            now.motor_pos_cmd,
            now.pos_cmd + now.backlash_filt + now.motor_offset
        );
        assert_eq!(now.acc_cmd, 0.0);
    }
    assert_eq!(s.j(0).backlash_filt, 0.01, "moving positive: +backlash/2");
}

#[test]
fn continuous_jog_runs_to_the_jog_limit_and_jog_abort_brakes() {
    let mut s = machine(1, KinematicsType::Identity);
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -1.0,
        max: 1.0,
    })
    .unwrap();
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    s.cycle();
    let js = s.j(0);
    assert!(js.kb_jog_active && js.free_tp_enable && !js.in_position);
    // Unhomed: one full travel (2) from the feedback (0).
    assert_eq!(js.free_pos_cmd, 2.0);
    assert_eq!(js.free_vel_lim, 5.0);
    assert!(s.m.jog_is_active() && !s.m.in_position());
    s.settle(10_000);
    let js = s.j(0);
    assert!((js.pos_cmd - 2.0).abs() <= SimpleTp::tiny_dp(100.0, T));
    assert!(!js.kb_jog_active && js.in_position && !s.m.jog_is_active());

    // Back the other way, then abort mid-move: braking at 100 u/s².
    s.cmd(Command::JogCont {
        joint: 0,
        vel: -5.0,
    })
    .unwrap();
    s.run(100);
    assert_eq!(s.j(0).vel_cmd, -5.0);
    assert_eq!(s.m.current_vel(), 5.0);
    s.cmd(Command::JogAbort { joint: 0 }).unwrap();
    let mut prev = s.j(0).vel_cmd;
    let mut n = 0;
    while s.j(0).vel_cmd != 0.0 {
        s.cycle();
        let v = s.j(0).vel_cmd;
        assert!(v - prev <= 100.0 * T * (1.0 + 1e-9) && v >= prev);
        prev = v;
        n += 1;
    }
    assert!((50..=51).contains(&n), "{n}");
    s.cycle();
    assert!(s.m.in_position());
    assert_eq!(s.m.current_vel(), 0.0);
}

#[test]
fn jog_velocity_is_capped_at_the_joint_limit_and_scaled() {
    let mut s = machine(1, KinematicsType::Identity);
    s.enable();
    s.cmd(Command::JogCont {
        joint: 0,
        vel: 50.0,
    })
    .unwrap();
    s.run(300);
    assert_eq!(s.j(0).vel_cmd, 10.0, "capped at vel_limit");
    s.cmd(Command::Scale { scale: 0.25 }).unwrap();
    s.run(300);
    assert_eq!(s.j(0).vel_cmd, 2.5);
    s.cmd(Command::Scale { scale: 7.0 }).unwrap();
    assert_eq!(s.m.scale(), 1.0, "clamped to 1");
    s.cmd(Command::Scale { scale: -1.0 }).unwrap();
    assert_eq!(s.m.scale(), 0.0);
    s.run(300);
    assert_eq!(s.j(0).vel_cmd, 0.0, "zero scale holds the jog");
    assert!(s.j(0).kb_jog_active, "held, not ended");
    assert!(matches!(
        s.cmd(Command::Scale { scale: f64::NAN }),
        Err(Reject::BadValue { .. })
    ));
}

#[test]
fn incremental_jogs_accumulate_and_stop_exactly_at_the_sum() {
    let mut s = machine(1, KinematicsType::Identity);
    s.enable();
    for _ in 0..3 {
        s.cmd(Command::JogIncr {
            joint: 0,
            vel: 4.0,
            offset: 0.5,
        })
        .unwrap();
        s.run(20);
    }
    assert_eq!(s.j(0).free_pos_cmd, 1.5);
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 1.5).abs() <= SimpleTp::tiny_dp(100.0, T));
    s.cmd(Command::JogIncr {
        joint: 0,
        vel: -4.0,
        offset: 0.25,
    })
    .unwrap();
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 1.25).abs() <= SimpleTp::tiny_dp(100.0, T));
    // Outside the jog limits: refused, nothing changes.
    let before = s.j(0);
    assert!(matches!(
        s.cmd(Command::JogIncr {
            joint: 0,
            vel: 4.0,
            offset: 500.0
        }),
        Err(Reject::TargetOutsideLimits { joint: 0, .. })
    ));
    assert_eq!(s.j(0), before);
    assert!(matches!(
        s.cmd(Command::JogIncr {
            joint: 0,
            vel: 4.0,
            offset: -1.0
        }),
        Err(Reject::BadValue { .. })
    ));
}

#[test]
fn absolute_jogs_retarget_and_clamp_into_the_jog_limits() {
    let mut s = machine(1, KinematicsType::Identity);
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -1.0,
        max: 1.0,
    })
    .unwrap();
    s.enable();
    s.cmd(Command::JogAbs {
        joint: 0,
        vel: 5.0,
        pos: 0.7,
    })
    .unwrap();
    s.run(50);
    // A new absolute jog retargets the moving planner.
    s.cmd(Command::JogAbs {
        joint: 0,
        vel: 5.0,
        pos: -0.3,
    })
    .unwrap();
    s.settle(10_000);
    assert!((s.j(0).pos_cmd + 0.3).abs() <= SimpleTp::tiny_dp(100.0, T));
    // Beyond the jog limits (unhomed: feedback ± 2): clamped.
    s.cmd(Command::JogAbs {
        joint: 0,
        vel: 5.0,
        pos: -10.0,
    })
    .unwrap();
    assert_eq!(s.j(0).free_pos_cmd, s.j(0).pos_fb - 2.0);
}

#[test]
fn refused_jogs_change_nothing_and_raise_no_error() {
    let mut s = machine(2, KinematicsType::Identity);
    let jog = Command::JogCont { joint: 0, vel: 1.0 };
    assert_eq!(s.cmd(jog), Err(Reject::NotEnabled));
    s.enable();
    assert_eq!(
        s.cmd(Command::JogCont { joint: 2, vel: 1.0 }),
        Err(Reject::NoSuchJoint {
            joint: 2,
            num_joints: 2
        })
    );
    assert_eq!(
        s.cmd(Command::JogCont { joint: 0, vel: 0.0 }),
        Err(Reject::BadVelocity { vel: 0.0 })
    );
    s.m.inputs.jog_inhibit = true;
    assert_eq!(s.cmd(jog), Err(Reject::JogInhibited));
    s.m.inputs.jog_inhibit = false;
    s.cmd(Command::JointDeactivate { joint: 1 }).unwrap();
    assert_eq!(
        s.cmd(Command::JogCont { joint: 1, vel: 1.0 }),
        Err(Reject::JointInactive { joint: 1 })
    );
    for j in 0..2 {
        assert!(!s.j(j).error && !s.j(j).kb_jog_active && !s.j(j).free_tp_enable);
    }
    assert!(!s.m.error());
    assert!(s.events().is_empty());
}

#[test]
fn hard_limit_trips_and_override_lets_the_joint_jog_off() {
    let mut s = machine(2, KinematicsType::Identity);
    s.enable();
    s.m.joint_inputs[0].pos_lim_sw = true;
    s.cycle();
    assert!(
        !s.m.is_enabled(),
        "a tripped limit disables in the same cycle"
    );
    let js = s.j(0);
    assert!(js.pos_hard_limit && js.error && !js.enabled);
    assert_eq!(s.events(), [Event::JointOnLimit { joint: 0 }]);
    // Still on the switch: re-enabling trips again at once.
    s.cmd(Command::Enable).unwrap();
    s.run(2);
    assert!(!s.m.is_enabled());
    assert_eq!(s.events(), [Event::JointOnLimit { joint: 0 }]);

    // Override the tripped limit, then jog away from it (only away).
    s.cmd(Command::OverrideLimits { joint: 0 }).unwrap();
    assert_eq!(s.m.override_limit_mask(), 0b10);
    assert!(!s.j(0).error);
    s.enable();
    s.run(5);
    assert!(s.m.is_enabled(), "overridden limit does not trip");
    assert_eq!(
        s.cmd(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::OnHardLimit {
            joint: 0,
            dir: Direction::Positive
        })
    );
    s.cmd(Command::JogIncr {
        joint: 0,
        vel: -2.0,
        offset: 0.2,
    })
    .unwrap();
    s.run(50);
    s.m.joint_inputs[0].pos_lim_sw = false;
    assert_eq!(s.m.override_limit_mask(), 0b10, "kept while the jog runs");
    s.settle(10_000);
    assert_eq!(s.m.override_limit_mask(), 0, "ends with the jog");
    // The limit is live again.
    s.m.joint_inputs[0].pos_lim_sw = true;
    s.cycle();
    assert!(!s.m.is_enabled());
    assert_eq!(s.events(), [Event::JointOnLimit { joint: 0 }]);
    // OverrideLimits with joint < 0 clears the mask.
    s.cmd(Command::OverrideLimits { joint: 0 }).unwrap();
    s.cmd(Command::OverrideLimits { joint: -1 }).unwrap();
    assert_eq!(s.m.override_limit_mask(), 0);
}

#[test]
fn a_shared_limit_switch_overridden_both_ways_jogs_either_way() {
    let mut s = machine(1, KinematicsType::Identity);
    s.m.joint_inputs[0].pos_lim_sw = true;
    s.m.joint_inputs[0].neg_lim_sw = true;
    s.cycle();
    s.cmd(Command::OverrideLimits { joint: 0 }).unwrap();
    assert_eq!(s.m.override_limit_mask(), 0b11);
    s.enable();
    s.cmd(Command::JogIncr {
        joint: 0,
        vel: 1.0,
        offset: 0.01,
    })
    .unwrap();
    s.cmd(Command::JogIncr {
        joint: 0,
        vel: -1.0,
        offset: 0.02,
    })
    .unwrap();
    s.run(3);
    assert!(s.m.is_enabled());
}

#[test]
fn inactive_joints_are_not_checked() {
    let mut s = machine(2, KinematicsType::Identity);
    s.cmd(Command::JointDeactivate { joint: 1 }).unwrap();
    s.enable();
    s.m.joint_inputs[1].pos_lim_sw = true;
    s.m.joint_inputs[1].amp_fault = true;
    s.stuck[1] = Some(50.0);
    s.run(10);
    assert!(s.m.is_enabled());
    let js = s.j(1);
    assert!(
        !js.pos_hard_limit && !js.faulted && js.pos_fb == 0.0,
        "inputs not read"
    );
}

#[test]
fn following_error_limit_scales_with_speed() {
    let mut s = machine(1, KinematicsType::Identity);
    s.lag = 5;
    s.enable();
    s.cmd(Command::JogCont {
        joint: 0,
        vel: 10.0,
    })
    .unwrap();
    s.run(400);
    let js = s.j(0);
    assert_eq!(js.vel_cmd, 10.0);
    // At full speed the limit is max_ferror.
    assert_eq!(js.ferror_limit, 1.0);
    assert!(
        js.ferror > 0.03 && js.ferror < 0.06,
        "lag of 4-5 periods: {}",
        js.ferror
    );
    s.cmd(Command::JogAbort { joint: 0 }).unwrap();
    s.settle(10_000);
    s.run(10);
    let js = s.j(0);
    assert_eq!(js.ferror_limit, 0.01, "at rest: min_ferror");
    assert!(
        s.m.is_enabled(),
        "a lagging but following motor does not trip"
    );
    assert!(js.ferror_high_mark > 0.03);
    assert!(s.events().is_empty());
}

#[test]
fn a_stuck_motor_trips_following_error_once() {
    let mut s = machine(2, KinematicsType::Identity);
    s.enable();
    s.stuck[0] = Some(0.0);
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    let mut n = 0;
    while s.m.is_enabled() {
        s.cycle();
        n += 1;
        assert!(n < 1000);
    }
    let js = s.j(0);
    assert!(js.following_error && js.error && !js.enabled && !s.j(1).enabled);
    assert!(js.ferror.abs() > js.ferror_limit);
    // The limit grows with speed (max_ferror·v/vmax, 0.5 at 5 u/s), so the
    // trip comes once the command is 0.5 ahead: 50 periods of ramp
    // (0.125) and 75 at 5 u/s.
    assert!((120..=130).contains(&n), "{n}");
    s.run(100);
    assert_eq!(
        s.events(),
        [Event::JointFollowingError { joint: 0 }],
        "reported once: a disabled joint is not checked again"
    );
    // Re-enabling clears the error flags.
    s.stuck[0] = None;
    s.enable();
    assert!(!s.j(0).error);
    s.run(5);
    assert!(s.m.is_enabled());
}

#[test]
fn amp_fault_disables_and_abort_clears_the_flags() {
    let mut s = machine(2, KinematicsType::Identity);
    s.enable();
    s.cmd(Command::JogCont { joint: 1, vel: 1.0 }).unwrap();
    s.run(10);
    s.m.joint_inputs[0].amp_fault = true;
    s.cycle();
    assert!(!s.m.is_enabled());
    let js = s.j(0);
    assert!(js.faulted && js.error && !js.enabled);
    assert!(
        !s.j(1).enabled && !s.j(1).free_tp_enable,
        "every amp off, planners stopped"
    );
    assert_eq!(s.j(1).vel_cmd, 0.0, "no controlled stop on a fault");
    assert_eq!(s.events(), [Event::JointAmpFault { joint: 0 }]);
    // While the fault persists, nothing floods.
    s.run(50);
    assert!(s.events().is_empty());
    assert!(s.j(0).faulted, "the flag follows the input");
    s.cmd(Command::Abort).unwrap();
    assert!(!s.j(0).error && !s.j(0).faulted && !s.m.error());
    s.cycle();
    assert!(s.j(0).faulted, "re-read from the pin");
    assert!(!s.j(0).error, "not an error while disabled");
    s.m.joint_inputs[0].amp_fault = false;
    s.cycle();
    assert!(!s.j(0).faulted);
    s.enable();
    s.run(3);
    assert!(s.m.is_enabled());
}

#[test]
fn enable_input_misc_errors_and_spindle_faults_disable() {
    let mut s = machine(1, KinematicsType::Identity);
    s.enable();
    s.m.inputs.enable = false;
    s.cycle();
    assert!(!s.m.is_enabled());
    assert_eq!(s.events(), [Event::EnableInputStopped]);
    s.m.inputs.enable = true;
    s.enable();
    s.m.inputs.misc_error[1] = true;
    s.cycle();
    assert!(!s.m.is_enabled());
    assert_eq!(s.events(), [Event::MiscError { input: 1 }]);
    s.m.inputs.misc_error[1] = false;
    s.enable();
    s.m.inputs.spindle_amp_fault[0] = true;
    s.cycle();
    assert!(!s.m.is_enabled());
    assert_eq!(s.events(), [Event::SpindleAmpFault { spindle: 0 }]);
}

#[test]
fn homed_joints_jog_within_soft_limits_and_the_backup_check_reports_once() {
    let mut s = machine(1, KinematicsType::Identity);
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -1.0,
        max: 1.0,
    })
    .unwrap();
    s.m.set_homed(0, true);
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    assert_eq!(s.j(0).free_pos_cmd, 1.0, "homed: the soft limit");
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 1.0).abs() <= SimpleTp::tiny_dp(100.0, T));
    // Past the soft limit: further jogs that way are refused.
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: -1.0,
        max: 0.5,
    })
    .unwrap();
    assert_eq!(
        s.cmd(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::PastSoftLimit {
            joint: 0,
            dir: Direction::Positive
        })
    );
    s.run(5);
    assert!(s.m.on_soft_limit() && s.m.error());
    assert_eq!(
        s.events(),
        [Event::SoftLimitExceeded {
            joint: 0,
            dir: Direction::Positive
        }]
    );
    // Jogging back inside is allowed and ends the condition.
    s.cmd(Command::JogAbs {
        joint: 0,
        vel: 5.0,
        pos: 0.0,
    })
    .unwrap();
    s.settle(10_000);
    assert!(!s.m.on_soft_limit());
    assert!(s.events().is_empty());
    // An unhomed joint is never soft-limit checked.
    s.m.set_homed(0, false);
    s.cmd(Command::SetJointPositionLimits {
        joint: 0,
        min: 5.0,
        max: 6.0,
    })
    .unwrap();
    s.run(3);
    assert!(!s.m.on_soft_limit());
}

#[test]
fn deactivation_is_refused_while_moving_and_drops_the_amp() {
    let mut s = machine(1, KinematicsType::Identity);
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 1.0 }).unwrap();
    s.run(5);
    assert_eq!(
        s.cmd(Command::JointDeactivate { joint: 0 }),
        Err(Reject::JointMoving { joint: 0 })
    );
    s.cmd(Command::JogAbort { joint: 0 }).unwrap();
    s.settle(1000);
    s.cmd(Command::JointDeactivate { joint: 0 }).unwrap();
    assert!(!s.j(0).enabled && !s.j(0).active);
}

#[test]
fn jog_stop_inputs_end_jogs() {
    let mut s = machine(2, KinematicsType::Identity);
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    s.cmd(Command::JogCont {
        joint: 1,
        vel: -5.0,
    })
    .unwrap();
    s.run(100);
    s.m.inputs.jog_stop = true;
    s.cycle();
    assert_eq!(s.events(), [Event::JogStopped { immediate: false }]);
    assert!(!s.j(0).free_tp_enable && !s.m.jog_is_active());
    assert!(s.j(0).vel_cmd > 0.0, "a controlled stop");
    s.settle(1000);
    s.m.inputs.jog_stop = false;
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    s.run(100);
    s.m.inputs.jog_stop_immediate = true;
    s.cycle();
    assert_eq!(s.events(), [Event::JogStopped { immediate: true }]);
    assert_eq!(s.j(0).vel_cmd, 0.0, "stopped at once");
    s.cycle();
    assert!(s.m.in_position());
}

#[test]
fn a_probe_contact_stops_jogs() {
    let mut s = machine(1, KinematicsType::Identity);
    s.enable();
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    s.run(20);
    s.m.inputs.probe_input = true;
    s.cycle();
    assert!(!s.j(0).free_tp_enable);
    assert_eq!(s.events(), [Event::ProbeTrippedDuringJog]);
    s.settle(1000);
    // Only the rising edge counts.
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    s.run(20);
    assert!(s.j(0).free_tp_enable);
    // NO_PROBE_JOG_ERROR: the jog goes on through a contact.
    s.m.inputs.probe_input = false;
    s.cycle();
    s.cmd(Command::SetProbeErrInhibit {
        jog: true,
        home: false,
    })
    .unwrap();
    s.m.inputs.probe_input = true;
    s.cycle();
    assert!(s.j(0).free_tp_enable);
    assert_eq!(s.events(), []);
}

#[test]
fn jog_wheel_moves_counts_times_scale() {
    let mut s = machine(1, KinematicsType::Identity);
    s.m.joint_inputs[0].jog_counts = 40;
    s.m.joint_inputs[0].jog_enable = true;
    s.m.joint_inputs[0].jog_scale = 0.01;
    s.cycle(); // the first pass only takes the counts
    s.enable();
    assert_eq!(s.j(0).free_pos_cmd, 0.0);
    s.m.joint_inputs[0].jog_counts = 140;
    s.cycle();
    assert!(s.j(0).wheel_jog_active);
    assert_eq!(s.j(0).free_pos_cmd, 1.0);
    assert_eq!(
        s.cmd(Command::JogCont { joint: 0, vel: 1.0 }),
        Err(Reject::WheelJogActive { joint: 0 })
    );
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 1.0).abs() <= SimpleTp::tiny_dp(100.0, T));
    assert!(!s.j(0).wheel_jog_active);
    // Disabled jog-enable: counts are consumed but ignored.
    s.m.joint_inputs[0].jog_enable = false;
    s.m.joint_inputs[0].jog_counts = 240;
    s.cycle();
    s.m.joint_inputs[0].jog_enable = true;
    s.cycle();
    assert!(!s.j(0).wheel_jog_active);
    // Velocity mode drops what cannot be reached in one stopping distance:
    // v²/(2a) = 100/200 = 0.5.
    s.m.joint_inputs[0].jog_vel_mode = true;
    s.m.joint_inputs[0].jog_counts = 1240;
    s.cycle();
    let js = s.j(0);
    assert!((js.free_pos_cmd - (js.pos_cmd + 0.5)).abs() < 0.02);
    // Accel fraction halves the wheel's acceleration.
    s.settle(10_000);
    s.m.joint_inputs[0].jog_vel_mode = false;
    s.m.joint_inputs[0].jog_accel_fraction = 0.5;
    s.m.joint_inputs[0].jog_counts = 1340;
    s.run(2);
    assert_eq!(s.j(0).vel_cmd, 2.0 * 50.0 * T);
}

#[test]
fn forward_kinematics_per_type() {
    // BOTH: no world position until every active joint is homed.
    let mut s = machine(2, KinematicsType::Both);
    s.stuck = vec![Some(1.0), Some(2.0)];
    s.run(2);
    assert!(!s.m.carte_pos_fb().1);
    s.m.set_homed(0, true);
    s.m.set_homed(1, true);
    s.run(2);
    let (fb, ok) = s.m.carte_pos_fb();
    assert!(ok);
    assert_eq!(fb.0[..2], [1.0, 2.0]);
    // IDENTITY: always computed, valid once homed.
    let mut s = machine(2, KinematicsType::Identity);
    s.stuck = vec![Some(1.0), Some(2.0)];
    s.run(2);
    assert_eq!(s.m.carte_pos_fb().0 .0[..2], [1.0, 2.0]);
    assert!(!s.m.carte_pos_fb().1);
    // INVERSE_ONLY: never from the joints; jogging unhomes the joint.
    let mut s = machine(1, KinematicsType::InverseOnly);
    s.m.set_homed(0, true);
    s.enable();
    assert!(!s.m.carte_pos_fb().1);
    s.cmd(Command::JogIncr {
        joint: 0,
        vel: 1.0,
        offset: 0.1,
    })
    .unwrap();
    assert!(!s.j(0).homed);
}

#[test]
fn configuration_commands_are_validated() {
    let mut s = machine(1, KinematicsType::Identity);
    let before = s.j(0).config;
    for c in [
        Command::SetJointPositionLimits {
            joint: 0,
            min: 2.0,
            max: 1.0,
        },
        Command::SetJointPositionLimits {
            joint: 0,
            min: f64::NAN,
            max: 1.0,
        },
        Command::SetJointVelLimit { joint: 0, vel: 0.0 },
        Command::SetJointAccLimit {
            joint: 0,
            acc: -1.0,
        },
        Command::SetJointMinFerror {
            joint: 0,
            ferror: -0.1,
        },
        Command::SetJointMaxFerror {
            joint: 0,
            ferror: f64::INFINITY,
        },
        Command::SetJointBacklash {
            joint: 0,
            backlash: -0.1,
        },
        Command::SetJointVelLimit { joint: 3, vel: 1.0 },
        Command::JointActivate { joint: -1 },
    ] {
        assert!(s.cmd(c).is_err(), "{c:?}");
    }
    assert_eq!(s.j(0).config, before);
    s.cmd(Command::SetJointBacklash {
        joint: 0,
        backlash: 0.1,
    })
    .unwrap();
    assert_eq!(s.j(0).config.backlash, 0.1);
    let mut home = Pose::ZERO;
    home.0[8] = f64::NAN;
    assert!(s.cmd(Command::SetWorldHome { pose: home }).is_err());
}

#[test]
fn motor_offset_shifts_motor_but_not_joint_positions() {
    let mut s = machine(1, KinematicsType::Identity);
    s.stuck[0] = Some(10.0);
    s.cmd(Command::SetJointMotorOffset {
        joint: 0,
        offset: 7.5,
    })
    .unwrap();
    s.run(2);
    let js = s.j(0);
    assert_eq!(js.pos_fb, 2.5);
    assert_eq!(js.pos_cmd, 2.5);
    assert_eq!(js.motor_pos_cmd, 10.0);
}

#[test]
fn a_zero_jog_accel_fraction_still_stops_the_wheel_jog() {
    let mut s = machine(1, KinematicsType::Identity);
    s.m.joint_inputs[0].jog_enable = true;
    s.m.joint_inputs[0].jog_scale = 0.01;
    s.m.joint_inputs[0].jog_accel_fraction = 0.0;
    s.cycle();
    s.enable();
    s.m.joint_inputs[0].jog_counts = 200; // 2 units
    s.cycle();
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 2.0).abs() <= SimpleTp::tiny_dp(100.0, T));
    assert!(s.m.is_enabled());
}

#[test]
fn a_joint_cannot_be_activated_while_enabled() {
    let mut s = machine(2, KinematicsType::Identity);
    s.cmd(Command::JointDeactivate { joint: 1 }).unwrap();
    s.enable();
    assert_eq!(
        s.cmd(Command::JointActivate { joint: 1 }),
        Err(Reject::ActivateWhileEnabled { joint: 1 })
    );
    // An active joint may be "activated" again; disabled, any may be.
    s.cmd(Command::JointActivate { joint: 0 }).unwrap();
    s.cmd(Command::Disable).unwrap();
    s.cycle();
    s.cmd(Command::JointActivate { joint: 1 }).unwrap();
}

#[test]
fn a_nan_feedback_trips_following_error() {
    let mut s = machine(1, KinematicsType::Identity);
    s.enable();
    s.stuck[0] = Some(f64::NAN);
    s.run(3);
    assert!(s.j(0).following_error);
    assert!(!s.m.is_enabled());
}

#[test]
fn a_nan_jog_scale_moves_nothing_and_breaks_nothing() {
    let mut s = machine(1, KinematicsType::Identity);
    s.m.joint_inputs[0].jog_enable = true;
    s.m.joint_inputs[0].jog_scale = f64::NAN;
    s.cycle();
    s.enable();
    s.m.joint_inputs[0].jog_counts = 100;
    s.run(5);
    assert!(s.j(0).free_pos_cmd.is_finite());
    s.cmd(Command::JogIncr {
        joint: 0,
        vel: 1.0,
        offset: 0.5,
    })
    .unwrap();
    s.settle(10_000);
    assert!((s.j(0).pos_cmd - 0.5).abs() <= SimpleTp::tiny_dp(100.0, T));
}
