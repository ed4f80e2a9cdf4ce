//! Prints the cost of one servo cycle of the motion controller core
//! (`motion-controller` without the HAL pin copies) for 3, 6 and 9 joints
//! with the motors looped back: every joint jogging in free mode, every
//! joint homing (switch search, all in one sequence), and every axis
//! jogging in teleop mode (inverse kinematics each cycle); and for 3 and 9
//! joints, coordinated motion along a zig-zag of short lines whose corners
//! are blended, with the queue kept full (2000 moves), with the
//! trapezoidal and the S-curve planner, and with the trapezoidal one
//! while an external offset on Z moves: mean and largest cycle (queueing
//! not included). Run with `cargo bench -p motion --bench servo_cycle`.
//! It prints figures; it checks nothing.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use motion::command::{LineKind, TermCond};
use motion::homing::HomingConfig;
use motion::kins::trivkins::Trivkins;
use motion::{Command, EoffsetInputs, KinematicsType, MotionConfig, MotionCore, Pose};

/// Applies `c`; a refusal is a bug of the scenario.
fn apply(m: &mut MotionCore, c: Command) {
    if let Err(r) = m.command(&c) {
        panic!("{c:?} refused: {r}");
    }
}

fn machine(n: usize) -> MotionCore {
    let kins = match Trivkins::new(&"XYZABCUVW"[..n], KinematicsType::Identity) {
        Ok(k) => Arc::new(k),
        Err(e) => panic!("trivkins: {e}"),
    };
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: n,
            ..MotionConfig::default()
        },
        kins,
    );
    for j in 0..n as i32 {
        for c in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -1e6,
                max: 1e6,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 10.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 100.0,
            },
            Command::SetJointBacklash {
                joint: j,
                backlash: 0.01,
            },
        ] {
            apply(&mut m, c);
        }
    }
    apply(&mut m, Command::Enable);
    m.cycle(0.001);
    m
}

fn main() {
    const CYCLES: u32 = 200_000;
    for n in [3, 6, 9] {
        let mut m = machine(n);
        for j in 0..n as i32 {
            let vel = if j % 2 == 0 { 5.0 } else { -5.0 };
            apply(&mut m, Command::JogCont { joint: j, vel });
        }
        let start = Instant::now();
        for k in 0..CYCLES {
            for j in 0..n {
                m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
            }
            // Reverse now and then so the planners and backlash keep working.
            if k % 20_000 == 0 {
                for j in 0..n as i32 {
                    let vel = if (j + (k / 20_000) as i32) % 2 == 0 {
                        5.0
                    } else {
                        -5.0
                    };
                    apply(&mut m, Command::JogCont { joint: j, vel });
                }
            }
            m.cycle(black_box(0.001));
        }
        let ns = start.elapsed().as_nanos() as f64 / f64::from(CYCLES);
        assert!(m.is_enabled());
        println!("motion servo cycle, {n} joints jogging (free): {ns:.0} ns");
    }
    for n in [3, 6, 9] {
        let mut m = machine(n);
        for j in 0..n as i32 {
            let config = HomingConfig {
                search_vel: 1.0,
                latch_vel: 0.1,
                sequence: 0,
                ..HomingConfig::default()
            };
            apply(&mut m, Command::SetJointHomingParams { joint: j, config });
        }
        apply(&mut m, Command::Home { joint: -1 });
        // The switch never closes within the measured cycles: a search.
        let start = Instant::now();
        for _ in 0..CYCLES {
            for j in 0..n {
                m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
            }
            m.cycle(black_box(0.001));
        }
        let ns = start.elapsed().as_nanos() as f64 / f64::from(CYCLES);
        assert!(m.homing_active());
        println!("motion servo cycle, {n} joints homing: {ns:.0} ns");
    }
    for n in [3, 6, 9] {
        let mut m = machine(n);
        apply(&mut m, Command::Teleop);
        for a in 0..n as i32 {
            apply(&mut m, Command::SetAxisVelLimit { axis: a, vel: 10.0 });
            apply(
                &mut m,
                Command::SetAxisAccLimit {
                    axis: a,
                    acc: 100.0,
                },
            );
        }
        let start = Instant::now();
        for k in 0..CYCLES {
            for j in 0..n {
                m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
            }
            if k % 20_000 == 0 {
                for a in 0..n as i32 {
                    let vel = if (a + (k / 20_000) as i32) % 2 == 0 {
                        5.0
                    } else {
                        -5.0
                    };
                    apply(&mut m, Command::AxisJogCont { axis: a, vel });
                }
            }
            m.cycle(black_box(0.001));
        }
        let ns = start.elapsed().as_nanos() as f64 / f64::from(CYCLES);
        assert!(m.is_enabled());
        println!("motion servo cycle, {n} axes jogging (teleop): {ns:.0} ns");
    }
    for scurve in [false, true] {
        for n in [3, 9] {
            coordinated(n, scurve, false);
        }
    }
    for n in [3, 9] {
        coordinated(n, false, true);
    }
}

/// Homes every joint (no switches: at once) and gives Z an external
/// offset's share of its limits (OFFSET_AV_RATIO 0.2), its offset enabled
/// at 0.001 per count.
fn with_z_offset(m: &mut MotionCore, n: usize) {
    apply(m, Command::Disable);
    m.cycle(0.001);
    apply(
        m,
        Command::SetAxisEoffsetRatio {
            axis: 2,
            ratio: 0.2,
        },
    );
    for j in 0..n as i32 {
        let config = HomingConfig {
            sequence: 0,
            ..HomingConfig::default()
        };
        apply(m, Command::SetJointHomingParams { joint: j, config });
    }
    apply(m, Command::Enable);
    m.cycle(0.001);
    apply(m, Command::Home { joint: -1 });
    for _ in 0..1000 {
        for j in 0..n {
            m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
        }
        m.cycle(0.001);
        if m.is_all_homed() && m.in_position() && m.teleop_mode() {
            break;
        }
    }
    assert!(m.is_all_homed(), "homed");
    m.axis_inputs[2].eoffset = EoffsetInputs {
        enable: true,
        clear: false,
        counts: 0,
        scale: 0.001,
    };
}

/// The coordinated scenario: a zig-zag in XY (every axis configured, the
/// kinematics computing all of them), corners blended within 0.01, the
/// queue topped up after every cycle; with `eoffset`, Z's external offset
/// follows a triangle wave of ±0.1 meanwhile.
fn coordinated(n: usize, scurve: bool, eoffset: bool) {
    const CYCLES: u32 = 100_000;
    let mut m = machine(n);
    if eoffset {
        with_z_offset(&mut m, n);
    }
    for a in 0..n as i32 {
        for c in [
            Command::SetAxisVelLimit { axis: a, vel: 10.0 },
            Command::SetAxisAccLimit {
                axis: a,
                acc: 100.0,
            },
            Command::SetAxisJerkLimit {
                axis: a,
                jerk: 10_000.0,
            },
        ] {
            apply(&mut m, c);
        }
    }
    if scurve {
        apply(&mut m, Command::SetJerkLimit { jerk: 10_000.0 });
        apply(&mut m, Command::SetPlannerType { planner: 1 });
    }
    apply(&mut m, Command::Coord);
    apply(
        &mut m,
        Command::SetTermCond {
            cond: TermCond::Blend,
            tolerance: 0.01,
        },
    );
    let mut k = 0;
    let mut queue_one = |m: &mut MotionCore| {
        k += 1;
        let mut end = Pose::ZERO;
        end.0[0] = k as f64 * 2.0;
        end.0[1] = if k % 2 == 0 { 0.0 } else { 1.0 };
        m.command(&Command::Line {
            end,
            vel: 8.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Feed,
            id: k,
        })
        .is_ok()
    };
    while queue_one(&mut m) {}
    let mut times = Vec::with_capacity(CYCLES as usize);
    for c in 0..CYCLES {
        for j in 0..n {
            m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
        }
        if eoffset {
            // 100 counts up and down every 2000 cycles.
            let t = (c / 10 % 200) as i32;
            m.axis_inputs[2].eoffset.counts = if t < 100 { t } else { 200 - t };
        }
        let start = Instant::now();
        m.cycle(black_box(0.001));
        times.push(start.elapsed().as_nanos() as f64);
        queue_one(&mut m);
    }
    // The machine must really have run the zig-zag.
    let id = m.planner().exec_id;
    assert!(
        m.is_enabled() && m.planner().depth > 1900 && id > 100,
        "at id {id}"
    );
    let with = if eoffset {
        assert!(m.eoffset_active(), "the offset was applied");
        ", an external offset on Z moving"
    } else {
        ""
    };
    times.sort_by(f64::total_cmp);
    let at = |q: usize| times[times.len() * q / 1000];
    // The largest includes the process being preempted on a busy machine.
    let planner = if scurve { "S-curve" } else { "trapezoidal" };
    println!(
        "motion servo cycle, {n} axes coordinated, blending, full queue, {planner}{with}: \
         median {:.0} ns, 99.9th percentile {:.0} ns, largest {:.0} ns ({id} lines run)",
        at(500),
        at(999),
        times[times.len() - 1]
    );
}
