//! Prints the cost of one forward and one inverse kinematics call of
//! every kinematics module, loaded into a HAL host as `loadrt` loads it
//! (so the geometry is read from its pins on every call). The calls
//! follow a small circle of poses, one step per call, each starting from
//! the previous result as the servo loop does (iterative solvers start
//! from there). Run with `cargo bench -p motion --bench kins`. It prints
//! figures; it checks nothing.

use std::hint::black_box;
use std::time::Instant;

use hal_core::{Host, HostConfig};
use motion::kins::{kinematics_for, Kinematics};
use motion::{KinsFlags, Pose};

const STEPS: usize = 64;
const CALLS: usize = 200_000;

/// A module, its arguments, its joints, and the centre of the circle of
/// poses (X Y Z A B C) the calls follow.
struct Case {
    module: &'static str,
    args: &'static [&'static str],
    joints: usize,
    centre: [f64; 6],
}

const CASES: &[Case] = &[
    Case {
        module: "trivkins",
        args: &["coordinates=xyz"],
        joints: 3,
        centre: [10.0, 20.0, 30.0, 0.0, 0.0, 0.0],
    },
    Case {
        module: "corexykins",
        args: &[],
        joints: 3,
        centre: [10.0, 20.0, 30.0, 0.0, 0.0, 0.0],
    },
    Case {
        module: "bipodkins",
        args: &[],
        joints: 2,
        centre: [0.5, 1.0, 0.0, 0.0, 0.0, 0.0],
    },
    Case {
        module: "scarakins",
        args: &[],
        joints: 6,
        centre: [300.0, 200.0, 100.0, 0.0, 0.0, 20.0],
    },
    Case {
        module: "pumakins",
        args: &[],
        joints: 6,
        centre: [300.0, 100.0, -300.0, 170.0, 10.0, 20.0],
    },
    Case {
        module: "genserkins",
        args: &[],
        joints: 6,
        centre: [300.0, 100.0, -300.0, 170.0, 10.0, 20.0],
    },
    Case {
        module: "lineardeltakins",
        args: &[],
        joints: 3,
        centre: [10.0, 20.0, 0.0, 0.0, 0.0, 0.0],
    },
    Case {
        module: "rotarydeltakins",
        args: &[],
        joints: 3,
        centre: [1.0, 1.0, -15.0, 0.0, 0.0, 0.0],
    },
    Case {
        module: "genhexkins",
        args: &[],
        joints: 6,
        centre: [1.0, 2.0, 20.0, 3.0, 4.0, 5.0],
    },
    Case {
        module: "xyzac-trt-kins",
        args: &[],
        joints: 5,
        centre: [10.0, 20.0, 30.0, 40.0, 0.0, 60.0],
    },
    Case {
        module: "xyzbc-trt-kins",
        args: &[],
        joints: 5,
        centre: [10.0, 20.0, 30.0, 0.0, 50.0, 60.0],
    },
];

/// Poses on a circle of radius `r` (in X and Y, and a degree in A B C)
/// around the centre.
fn poses(centre: [f64; 6], r: f64) -> Vec<Pose> {
    (0..STEPS)
        .map(|k| {
            let t = k as f64 / STEPS as f64 * std::f64::consts::TAU;
            let mut p = Pose::ZERO;
            p.0[..6].copy_from_slice(&centre);
            p.0[0] += r * t.cos();
            p.0[1] += r * t.sin();
            for (v, c) in p.0[3..6].iter_mut().zip(&centre[3..6]) {
                if *c != 0.0 {
                    *v += t.sin();
                }
            }
            p
        })
        .collect()
}

fn main() {
    let defs = motion::modules();
    println!("kinematics call cost (ns per call, geometry read from HAL pins)");
    println!("{:<18} {:>10} {:>10}", "module", "forward", "inverse");
    for case in CASES {
        let host = Host::create(HostConfig::for_tests(&format!("kbench-{}", case.module)))
            .expect("host starts");
        let def = defs
            .iter()
            .find(|d| d.name == case.module)
            .expect("module exists");
        host.loadrt(def, case.args).expect("module loads");
        let (_, kins) = kinematics_for(host.instance().name()).expect("kinematics registered");
        let k: &dyn Kinematics = &*kins;
        let r = if case.module == "bipodkins" { 0.1 } else { 1.0 };
        let poses = poses(case.centre, r);
        // The joints of every pose, each solved from the previous.
        let mut flags = KinsFlags::default();
        let mut joints = vec![[0.0; 9]; STEPS];
        let mut prev = [0.0; 9];
        if case.module == "genserkins" {
            // The iterative inverse needs a start near the arm's pose.
            prev[..6].copy_from_slice(&[15.0, -30.0, 10.0, 0.0, 40.0, 20.0]);
        }
        for _ in 0..2 {
            for (p, j) in poses.iter().zip(joints.iter_mut()) {
                let mut q = prev;
                k.inverse(p, &mut q[..case.joints], &mut flags)
                    .unwrap_or_else(|e| panic!("{}: {e} at {p:?}", case.module));
                *j = q;
                prev = q;
            }
        }

        let mut pose = poses[STEPS - 1];
        let start = Instant::now();
        for i in 0..CALLS {
            let j = &joints[i % STEPS];
            k.forward(black_box(&j[..case.joints]), &mut pose, &mut flags)
                .expect("forward");
        }
        let forward = start.elapsed().as_nanos() as f64 / CALLS as f64;

        let mut q = joints[STEPS - 1];
        let start = Instant::now();
        for i in 0..CALLS {
            k.inverse(
                black_box(&poses[i % STEPS]),
                &mut q[..case.joints],
                &mut flags,
            )
            .expect("inverse");
        }
        let inverse = start.elapsed().as_nanos() as f64 / CALLS as f64;
        black_box((pose, q));
        println!("{:<18} {:>10.0} {:>10.0}", case.module, forward, inverse);
    }
}
