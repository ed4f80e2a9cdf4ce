//! The servo cycle and the commands the realtime handler takes never
//! allocate: coordinated motion with blends, arcs, pauses and aborts on
//! both planners (the S-curve one calls Ruckig), with an external offset
//! turned in and cleared on Z, and a locking indexer's rapid (unlock,
//! move, relock), counted by a global allocator that tallies
//! allocations made by this thread while armed.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;

use motion::command::{LineKind, TermCond};
use motion::kins::trivkins::Trivkins;
use motion::{Command, EoffsetInputs, KinematicsType, MotionConfig, MotionCore, Pose};

struct Counting;

thread_local! {
    static ARMED: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: every call is passed to the system allocator unchanged; the
// counters are thread-local cells touched without allocating.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if ARMED.with(Cell::get) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        // SAFETY: the caller's layout, as GlobalAlloc requires.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc` above with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Runs `f` and returns how many allocations it made.
fn allocations(f: impl FnOnce()) -> u64 {
    COUNT.with(|c| c.set(0));
    ARMED.with(|a| a.set(true));
    f();
    ARMED.with(|a| a.set(false));
    COUNT.with(Cell::get)
}

fn machine() -> MotionCore {
    let kins = Arc::new(Trivkins::new("xyz", KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(MotionConfig::default(), kins);
    for j in 0..3 {
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
            Command::SetAxisVelLimit { axis: j, vel: 10.0 },
            Command::SetAxisAccLimit {
                axis: j,
                acc: 100.0,
            },
            Command::SetAxisJerkLimit { axis: j, jerk: 1e6 },
            Command::SetJointHomingParams {
                joint: j,
                config: motion::homing::HomingConfig {
                    sequence: 0,
                    ..Default::default()
                },
            },
        ] {
            m.command(&c).unwrap();
        }
    }
    m.command(&Command::SetJerkLimit { jerk: 1e6 }).unwrap();
    m.command(&Command::SetAxisEoffsetRatio {
        axis: 2,
        ratio: 0.2,
    })
    .unwrap();
    m
}

fn step(m: &mut MotionCore) {
    for j in 0..3 {
        m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
    }
    m.cycle(0.001);
}

#[test]
fn cycles_and_commands_do_not_allocate() {
    for planner in [0, 1] {
        let mut m = machine();
        m.command(&Command::SetPlannerType { planner }).unwrap();
        m.command(&Command::Enable).unwrap();
        step(&mut m);
        m.command(&Command::Home { joint: -1 }).unwrap();
        for _ in 0..1000 {
            step(&mut m);
            if m.is_all_homed() && m.command(&Command::Coord).is_ok() {
                break;
            }
        }
        assert!(m.coord_mode(), "homed and in coordinated mode");
        m.axis_inputs[2].eoffset = EoffsetInputs {
            enable: true,
            clear: false,
            counts: 0,
            scale: 0.001,
        };
        step(&mut m);
        let n = allocations(|| {
            m.command(&Command::SetTermCond {
                cond: TermCond::Blend,
                tolerance: 0.05,
            })
            .unwrap();
            for k in 0..40 {
                let mut end = Pose::ZERO;
                end.0[0] = k as f64;
                end.0[1] = (k % 2) as f64;
                let c = if k % 5 == 4 {
                    // A half circle from the last point.
                    Command::Circle {
                        end,
                        center: [k as f64 - 0.5, 0.5, 0.0],
                        normal: [0.0, 0.0, 1.0],
                        turns: 0,
                        vel: 5.0,
                        ini_maxvel: 0.0,
                        acc: 0.0,
                        id: k,
                    }
                } else {
                    Command::Line {
                        end,
                        vel: 8.0,
                        ini_maxvel: 0.0,
                        acc: 0.0,
                        kind: LineKind::Feed,
                        id: k,
                    }
                };
                let r = m.command(&c);
                assert_eq!(r, Ok(()), "move {k}");
            }
            for k in 0..3000 {
                let z = &mut m.axis_inputs[2].eoffset;
                z.counts = (k / 10).min(150);
                z.clear = k >= 2200;
                step(&mut m);
                match k {
                    800 => m.command(&Command::Pause).unwrap(),
                    1200 => m.command(&Command::Resume).unwrap(),
                    1300 => m.command(&Command::FeedScale { scale: 0.5 }).unwrap(),
                    2100 => assert!(m.axis(2).unwrap().eoffset > 0.1, "offset applied"),
                    2500 => m.command(&Command::Abort).unwrap(),
                    _ => {}
                }
            }
        });
        assert_eq!(
            n, 0,
            "planner {planner}: {n} allocations in the realtime path"
        );
        assert!(m.planner().exec_id > 5, "it moved: {:?}", m.planner());
        let z = m.axis(2).unwrap();
        assert_eq!(z.eoffset_request, 0.0, "cleared");
    }
}

/// Every kinematics module's forward and inverse calls, as `loadrt`
/// registers them with their default parameters, in every type of the
/// switchable ones, run without allocating, whether they succeed or
/// refuse the pose.
#[test]
fn kinematics_calls_do_not_allocate() {
    use hal_core::{Host, HostConfig};
    use motion::kins::kinematics_for;
    use motion::KinsFlags;

    for def in motion::modules() {
        if def.name == "motmod" {
            continue;
        }
        let host = Host::create(HostConfig::for_tests(&format!("mot-noalloc-{}", def.name)))
            .expect("host starts");
        host.loadrt::<&str>(def, &[]).unwrap();
        let (_, k) = kinematics_for(host.instance().name()).expect("registered");
        let mut joints = [0.0; 16];
        let mut flags = KinsFlags::default();
        let poses = [
            Pose([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 0.5, 0.25, 0.125]),
            Pose([1e9, -1e9, 1e9, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            Pose([f64::NAN; 9]),
        ];
        // Every type of a switchable module (the switch itself is not
        // counted: motion makes it outside the servo cycle's maths).
        let types = if k.is_switchable() { 3 } else { 1 };
        for t in 0..types {
            if k.is_switchable() && k.switch_to(t).is_err() {
                continue;
            }
            let n = allocations(|| {
                for p in &poses {
                    let mut pose = *p;
                    let _ = k.inverse(&pose, &mut joints, &mut flags);
                    let _ = k.forward(&joints, &mut pose, &mut flags);
                }
            });
            assert_eq!(
                n, 0,
                "{} type {t}: {n} allocations in kinematics calls",
                def.name
            );
        }
    }
}

#[test]
fn a_locking_indexer_rapid_does_not_allocate() {
    let kins = Arc::new(Trivkins::new("xyzb", KinematicsType::Identity).unwrap());
    let cfg = MotionConfig {
        num_joints: 4,
        unlock_joints_mask: 0x8,
        ..MotionConfig::default()
    };
    let mut m = MotionCore::new(cfg, kins);
    for j in 0..4 {
        for c in [
            Command::JointActivate { joint: j },
            Command::SetJointPositionLimits {
                joint: j,
                min: -1e6,
                max: 1e6,
            },
            Command::SetJointVelLimit {
                joint: j,
                vel: 100.0,
            },
            Command::SetJointAccLimit {
                joint: j,
                acc: 1000.0,
            },
            Command::SetJointHomingParams {
                joint: j,
                config: motion::homing::HomingConfig {
                    sequence: 0,
                    ..Default::default()
                },
            },
        ] {
            m.command(&c).unwrap();
        }
    }
    for c in [
        Command::SetAxisPositionLimits {
            axis: 4,
            min: -1e6,
            max: 1e6,
        },
        Command::SetAxisVelLimit {
            axis: 4,
            vel: 100.0,
        },
        Command::SetAxisAccLimit {
            axis: 4,
            acc: 1000.0,
        },
        Command::SetAxisLockingIndexer { axis: 4, joint: 3 },
    ] {
        m.command(&c).unwrap();
    }
    m.command(&Command::Enable).unwrap();
    step4(&mut m);
    m.command(&Command::Home { joint: -1 }).unwrap();
    for _ in 0..1000 {
        step4(&mut m);
        if m.is_all_homed() && m.command(&Command::Coord).is_ok() {
            break;
        }
    }
    assert!(m.coord_mode(), "homed and in coordinated mode");
    step4(&mut m);
    let mut seen_unlock = false;
    let n = allocations(|| {
        for (k, b) in [(1, 10.0), (2, 0.0)] {
            let mut end = Pose::ZERO;
            end.0[4] = b;
            m.command(&Command::Line {
                end,
                vel: 0.0,
                ini_maxvel: 0.0,
                acc: 0.0,
                kind: LineKind::Traverse,
                id: k,
            })
            .unwrap();
        }
        for _ in 0..3000 {
            step4(&mut m);
            seen_unlock |= m.unlock_output(3);
        }
    });
    assert_eq!(n, 0, "{n} allocations in the realtime path");
    assert!(seen_unlock && !m.unlock_output(3), "{:?}", m.planner());
    assert_eq!(m.planner().exec_id, 2, "{:?}", m.planner());
}

/// [`step`] for four joints; joint 3's clamp answers its unlock at once.
fn step4(m: &mut MotionCore) {
    for j in 0..4 {
        m.joint_inputs[j].motor_pos_fb = m.joint(j).motor_pos_cmd;
    }
    m.joint_inputs[3].is_unlocked = m.unlock_output(3);
    m.cycle(0.001);
}
