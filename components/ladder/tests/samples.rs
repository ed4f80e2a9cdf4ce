//! LinuxCNC's sample ClassicLadder projects, loaded with the sizes their
//! HAL files give `classicladder_rt`, and scanned against truth tables
//! read off their rungs (the rung drawings are in each test's comment).

use std::path::PathBuf;

use hal_ladder::clp;
use hal_ladder::compile::compile;
use hal_ladder::model::{Program, Sizes};
use hal_ladder::runtime::Engine;

fn sample(rel: &str) -> PathBuf {
    PathBuf::from(env!("HAL_PEER_SAMPLE_CONFIGS")).join(rel)
}

fn load(rel: &str, sizes: Sizes) -> (Program, Engine) {
    let text = std::fs::read_to_string(sample(rel)).expect(rel);
    let project = clp::parse(&text).unwrap_or_else(|e| panic!("{rel}: {e}"));
    let c = compile(&project, &sizes).unwrap_or_else(|e| panic!("{rel}: {e}"));
    let mut engine = Engine::new(&sizes);
    engine.install(&c.program);
    (c.program, engine)
}

/// demo_sim_cl.hal's and demo_step_cl.hal's `loadrt classicladder_rt`.
fn demo_sizes() -> Sizes {
    Sizes {
        rungs: 12,
        bits: 20,
        words: 4,
        timers: 5,
        monostables: 2,
        inputs: 10,
        outputs: 10,
        exprs: 4,
        sections: 4,
        ..Sizes::default()
    }
}

fn set(e: &mut Engine, inputs: &[(usize, bool)]) {
    for &(i, v) in inputs {
        e.vars.inputs[i] = v;
    }
}

/// Rung 1 of demo_sim_cl.clp (the estop chain; rows 0-2 start from an
/// empty cell in column 0 and carry no power):
/// ```text
/// --- | |I0 |/|I1 | |Q0 --- ... ( )Q0   (the coil joined by wires in column 9)
///                 ^| |I2 ^
/// ```
/// so Q0 = I0 and not I1 and (Q0 or I2): I2 (E-RESET) latches, I0 (the
/// GUI's estop) and I1 (external estop) break the latch.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn demo_sim_cl_estop_chain_latches() {
    for rel in [
        "sim/axis/classicladder/demo_sim_cl.clp",
        "by_interface/parport/classicladder/demo_step_cl/demo_step_cl.clp",
    ] {
        let (p, mut e) = load(rel, demo_sizes());
        let q0 = |e: &Engine| e.vars.outputs[0];
        // (I0, I1, I2) -> Q0, in sequence (the latch remembers).
        let steps = [
            ((true, false, false), false, "no reset yet"),
            ((true, false, true), true, "reset latches"),
            ((true, false, false), true, "held by its own contact"),
            ((true, true, false), false, "external estop breaks it"),
            ((true, false, false), false, "stays off"),
            ((false, false, true), false, "GUI estop off: no reset"),
            ((true, false, true), true, "reset again"),
            ((false, false, false), false, "GUI estop breaks it"),
        ];
        for ((i0, i1, i2), want, why) in steps {
            set(&mut e, &[(0, i0), (1, i1), (2, i2)]);
            e.scan(&p, 1);
            assert_eq!(q0(&e), want, "{rel}: {why}");
        }
    }
}

/// Rung 2 of demo_sim_cl.clp (intermittent lube):
/// ```text
/// --- | |I3 |/|B0  [T0 ] ---- (R)Q1      T0: 10 s, T1: 20 s, T2: 20 min
///           ^      [   ] ---- (S)Q1
///           ^|/|Q1 ---- [T1 ]
///           ^           [   ] ---- ( )B0
///           ^| |I4 [T2 ]
///                  [   ] -------- ( )Q2
/// ```
/// With I3 on, Q1 is set while T0 runs and reset when it is done; then
/// T1 (enabled by I3 and not Q1) runs and drives B0, which stops T0;
/// when T1 is done B0 drops and T0 starts over. Scanned once a second.
/// Columns run left to right, so a coil written in column 9 is seen by
/// a contact in column 2 only at the next scan: in the first scan T1
/// starts too (Q1 was still off in column 2), and its B0 stops T0 for
/// one scan.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn demo_sim_cl_lube_cycle_over_many_scans() {
    let (p, mut e) = load("sim/axis/classicladder/demo_sim_cl.clp", demo_sizes());
    set(&mut e, &[(3, true)]);
    let mut q1 = Vec::new();
    for _ in 0..40 {
        e.scan(&p, 1000);
        q1.push(e.vars.outputs[1]);
    }
    // Scan 1: T0 and T1 start, Q1 set, B0 on; 2: both stop (B0, Q1),
    // B0 off; 3-12: T0 runs its 10 s; 13: T0 done, Q1 reset; 14: T1
    // starts (B0 on); 14-33: T1 runs its 20 s; 34: T1 done, B0 off; 35:
    // T0 runs again and sets Q1.
    let on: Vec<usize> = (0..40).filter(|&i| q1[i]).map(|i| i + 1).collect();
    let want: Vec<usize> = (1..=12).chain(35..=40).collect();
    assert_eq!(on, want);
    assert!(!e.vars.bits[0], "B0 is off while T0 runs again");
    // Low lube warning: Q2 follows T2's running output while I3 and I4.
    set(&mut e, &[(4, true)]);
    e.scan(&p, 1000);
    assert!(e.vars.outputs[2], "T2 runs");
    for _ in 0..1199 {
        e.scan(&p, 1000);
    }
    assert!(e.vars.outputs[2], "still within 20 minutes");
    e.scan(&p, 1000);
    assert!(!e.vars.outputs[2], "T2 done after 20 minutes");
    set(&mut e, &[(4, false)]);
    e.scan(&p, 1000);
    assert!(!e.vars.outputs[2]);
}

/// cl-estop's estop.clp, rung 0:
/// ```text
/// | |I0 --- | |I1 --- | |I2 --- ... ( )Q0
///         ^       ^| |Q2 ^          ^( )Q1
///         ^       ^| |Q0 ^
///         ^| |I3 --- --- ^
/// ```
/// so Q0 = Q1 = I0 and ((I1 and (I2 or Q2 or Q0)) or I3).
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn cl_estop_truth_table() {
    let (p, mut e) = load(
        "by_interface/parport/classicladder/cl-estop/estop.clp",
        Sizes::default(),
    );
    for bits in 0..32u32 {
        let b = |k: u32| bits >> k & 1 == 1;
        let (i0, i1, i2, i3, q0_before) = (b(0), b(1), b(2), b(3), b(4));
        e.vars.outputs[0] = q0_before;
        set(&mut e, &[(0, i0), (1, i1), (2, i2), (3, i3)]);
        e.scan(&p, 1);
        let want = i0 && ((i1 && (i2 || q0_before)) || i3);
        assert_eq!(
            e.vars.outputs[0], want,
            "Q0 for I0-3 {i0} {i1} {i2} {i3}, Q0 was {q0_before}"
        );
        assert_eq!(e.vars.outputs[1], want, "Q1 follows Q0");
    }
}

/// Smithy's 924.clp, the turret tool changer. Sections: rung 2, 3, 1.
/// Rung 2: the sensors I1-I4 give the turret position in %W1 (one
/// sensor off: I1 -> 0, I2 -> 1, I3 -> 2, I4 -> 3, by operate blocks
/// when B3 is off); `(IW0-1)&3 = W1` or B3, and not B2, gives B0 (at the
/// requested tool). Rung 3: B2 = all four sensors on, B3 = (IW0 = 0),
/// Q3 = I5. Rung 1: Q1 (turn) = I0 and not B0 and not B3; monostable 0
/// (1 s) fires on Q1's falling edge or on I0 with B0 or B3, drives Q2
/// (lock), and Q2's falling edge sets Q0 (tool changed); I0's rising
/// edge resets Q0.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn smithy_turret_changes_tools() {
    let (p, mut e) = load("by_machine/smithy/924.clp", Sizes::default());
    // Turret at tool 1 (I1 off), tool 3 asked for, no change yet.
    e.vars.word_in[0] = 3;
    set(
        &mut e,
        &[
            (0, false),
            (1, false),
            (2, true),
            (3, true),
            (4, true),
            (5, true),
        ],
    );
    e.scan(&p, 100);
    assert_eq!(e.vars.words[1], 0, "W1 is the position of tool 1");
    assert!(!e.vars.bits[0], "not at the requested tool");
    assert!(e.vars.outputs[3], "Q3 follows I5");
    // The change starts: the turret turns.
    set(&mut e, &[(0, true)]);
    e.scan(&p, 100);
    assert!(e.vars.outputs[1], "Q1 turns the turret");
    assert!(!e.vars.outputs[0]);
    // It reaches tool 3 (I3 off): W1 = 2 = (3-1)&3 (the operate block
    // in column 9 runs after the compare in column 3, so B0 follows a
    // scan later), then Q1 stops, the monostable runs Q2 for a second,
    // and Q2's falling edge sets Q0 (tool changed) a scan after.
    set(&mut e, &[(1, true), (3, false)]);
    e.scan(&p, 100);
    assert_eq!(e.vars.words[1], 2);
    assert!(e.vars.outputs[1], "still turning for one scan");
    e.scan(&p, 100);
    assert!(e.vars.bits[0], "at the requested tool");
    assert!(!e.vars.outputs[1], "the turret stops");
    assert!(e.vars.outputs[2], "Q2 locks");
    for _ in 0..9 {
        e.scan(&p, 100);
    }
    assert!(e.vars.outputs[2], "the lock pulse lasts 1 s");
    e.scan(&p, 100);
    assert!(!e.vars.outputs[2], "and ends");
    assert!(!e.vars.outputs[0]);
    e.scan(&p, 100);
    assert!(e.vars.outputs[0], "Q0: tool changed");
    // A new change request resets Q0 at once.
    set(&mut e, &[(0, false)]);
    e.scan(&p, 100);
    assert!(e.vars.outputs[0], "Q0 stays until the next request");
    set(&mut e, &[(0, true)]);
    e.scan(&p, 100);
    assert!(!e.vars.outputs[0], "rising I0 resets Q0");
    // Tool 0 asked for: B3, no turning.
    e.vars.word_in[0] = 0;
    e.scan(&p, 100);
    assert!(e.vars.bits[3]);
    assert!(!e.vars.outputs[1]);
}

/// Every other .clp of the samples loads with the sizes its HAL file
/// gives (LinuxCNC's defaults where it gives none), and a size too small
/// is an error naming the parameter.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn every_sample_project_loads() {
    let mazak = Sizes {
        rungs: 50,
        bits: 50,
        words: 8,
        timers: 20,
        monostables: 10,
        inputs: 50,
        outputs: 40,
        exprs: 4,
        sections: 4,
        ..Sizes::default()
    };
    let dallur = Sizes {
        rungs: 10,
        inputs: 20,
        ..demo_sizes()
    };
    for (rel, sizes) in [
        ("attic/demo_mazak/demo_mazak.clp", mazak),
        ("attic/dallur-thc/dallur-advanced.clp", dallur),
        (
            "common/configurable_options/ladder/estop.clp",
            Sizes::default(),
        ),
        (
            "common/configurable_options/ladder/blank.clp",
            Sizes::default(),
        ),
        (
            "common/configurable_options/ladder/touchoff_z.clp",
            Sizes::default(),
        ),
        (
            "common/configurable_options/ladder/serialmodbus.clp",
            Sizes::default(),
        ),
    ] {
        let (p, mut e) = load(rel, sizes);
        for _ in 0..10 {
            e.scan(&p, 1);
        }
        assert_eq!(e.overruns, 0, "{rel}");
    }
    let text = std::fs::read_to_string(sample("attic/demo_mazak/demo_mazak.clp")).unwrap();
    let project = clp::parse(&text).unwrap();
    let small = Sizes {
        inputs: 10,
        ..mazak
    };
    let err = compile(&project, &small).unwrap_err().to_string();
    assert!(
        err.contains("numPhysInputs") && err.starts_with("line "),
        "{err}"
    );
}

/// dallur-advanced.clp's estop chain is demo_sim_cl's: the same latch.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn dallur_estop_latches() {
    let sizes = Sizes {
        rungs: 10,
        inputs: 20,
        ..demo_sizes()
    };
    let (p, mut e) = load("attic/dallur-thc/dallur-advanced.clp", sizes);
    set(&mut e, &[(0, true), (1, false), (2, true)]);
    e.scan(&p, 1);
    set(&mut e, &[(2, false)]);
    e.scan(&p, 1);
    assert!(e.vars.outputs[0], "latched");
    set(&mut e, &[(1, true)]);
    e.scan(&p, 1);
    assert!(!e.vars.outputs[0], "external estop");
}
