//! Spindle-synchronised motion through task on a simulated lathe: the
//! spindle model of LinuxCNC's sim configurations (LIB:sim_spindle_encoder.hal:
//! `revs` ramping with the commanded speed, an index that restarts the
//! count) drives G33 passes and a G76 cycle. A sampler records X, Z and
//! the spindle's `revs` every servo period; every threading pass must
//! keep Z = Z_start − revs × pitch, with `revs` counted from the index,
//! so every pass cuts the same helix.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{Machine, Scratch};

/// Samples the sampler's FIFO holds at most.
const DEPTH: usize = 60_000;

const INI: &str = "\
[EMC]
VERSION = 1.1
MACHINE = threading lathe

[DISPLAY]
DISPLAY = axis
LATHE = 1

[TASK]
TASK = milltask
CYCLE_TIME = 0.010

[RS274NGC]
PARAMETER_FILE = sim.var

[EMCMOT]
EMCMOT = motmod
BASE_PERIOD = 0
SERVO_PERIOD = 1000000

[EMCIO]
TOOL_TABLE = lathe.tbl

[HAL]
HALFILE = lathe.hal
HALFILE = LIB:sim_spindle_encoder.hal
HALFILE = record.hal
HALCMD = setp motion.enable TRUE

[TRAJ]
COORDINATES = X Z
LINEAR_UNITS = mm
ANGULAR_UNITS = degree
MAX_LINEAR_VELOCITY = 40
NO_FORCE_HOMING = 1

[KINS]
KINEMATICS = trivkins coordinates=XZ
JOINTS = 2

[AXIS_X]
MAX_VELOCITY = 20
MAX_ACCELERATION = 400
MIN_LIMIT = -50
MAX_LIMIT = 50

[AXIS_Z]
MAX_VELOCITY = 20
MAX_ACCELERATION = 400
MIN_LIMIT = -100
MAX_LIMIT = 20

[JOINT_0]
TYPE = LINEAR
MAX_VELOCITY = 20
MAX_ACCELERATION = 400
MIN_LIMIT = -50
MAX_LIMIT = 50
FERROR = 1
MIN_FERROR = 1

[JOINT_1]
TYPE = LINEAR
MAX_VELOCITY = 20
MAX_ACCELERATION = 400
MIN_LIMIT = -100
MAX_LIMIT = 20
FERROR = 1
MIN_FERROR = 1
";

const LATHE_HAL: &str = "\
loadrt [KINS]KINEMATICS
loadrt [EMCMOT]EMCMOT base_period_nsec=[EMCMOT]BASE_PERIOD servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=[KINS]JOINTS
addf motion-command-handler servo-thread
addf motion-controller servo-thread
net Xpos joint.0.motor-pos-cmd => joint.0.motor-pos-fb
net Zpos joint.1.motor-pos-cmd => joint.1.motor-pos-fb
net estop-loop iocontrol.0.user-enable-out iocontrol.0.emc-enable-in
net tool-prep-loop iocontrol.0.tool-prepare iocontrol.0.tool-prepared
net tool-change-loop iocontrol.0.tool-change iocontrol.0.tool-changed
";

/// X, Z, the spindle's revs and `spindle.0.reverse` every servo
/// period, after the spindle model has run (sim_spindle_encoder.hal adds
/// it after motion).
fn record_hal() -> String {
    format!(
        "loadrt sampler depth={DEPTH} cfg=fffb
net Xpos => sampler.0.pin.0
net Zpos => sampler.0.pin.1
net spindle-pos => sampler.0.pin.2
net spindle-reverse spindle.0.reverse => sampler.0.pin.3
setp sampler.0.enable FALSE
addf sampler.0 servo-thread
"
    )
}

/// The lathe, on and in AUTO mode.
fn lathe(s: &Scratch, tag: &str) -> Machine {
    let ini = s.write("lathe.ini", INI);
    s.write("lathe.hal", LATHE_HAL);
    s.write("record.hal", &record_hal());
    s.write("lathe.tbl", "T1 P1 X0 Z0 D0.4 ;threading tool\n");
    let m = Machine::start(&ini, tag);
    assert!(m.threads_run(), "threads run");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.task_ok(&["mode", "auto"]);
    m
}

/// Runs `prog` with the sampler on; returns the samples (X, Z, revs,
/// reverse as 0 or 1).
fn run_recorded(m: &Machine, s: &Scratch, name: &str, prog: &str) -> Vec<[f64; 4]> {
    let path = s.write(name, prog);
    m.task_ok(&["open", path.to_str().unwrap()]);
    m.halcmd(&["setp", "sampler.0.enable", "TRUE"]);
    m.task_ok(&["run"]);
    let (ok, out, err) = m.task(&["-t", "120", "wait-done"]);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    m.halcmd(&["setp", "sampler.0.enable", "FALSE"]);
    let n: usize = m.getp("sampler.0.curr-depth").parse().unwrap();
    assert!(
        n > 0 && n < DEPTH,
        "{n} samples (the FIFO may have overrun)"
    );
    let out = machine::tool(
        env!("CARGO_BIN_EXE_halsampler"),
        &["-n", &n.to_string()],
        &m.instance,
        None,
    );
    let (ok, text, err) = machine::text(&out);
    assert!(ok, "{err}");
    text.lines()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}

/// The threading passes: runs of samples where Z goes down at X below
/// `x_clear` (the rapids back run at X = `x_clear`), each sample with
/// the revs motion read for it.
fn passes(samples: &[[f64; 4]], x_clear: f64) -> Vec<Vec<[f64; 3]>> {
    let mut out: Vec<Vec<[f64; 3]>> = Vec::new();
    let mut current: Vec<[f64; 3]> = Vec::new();
    for w in samples.windows(2) {
        let cutting = w[1][1] < w[0][1] && w[1][0] < x_clear - 1e-9;
        if cutting {
            // Motion computed this Z from the revs it read, the spindle
            // model's of the period before (it runs after motion).
            current.push([w[1][0], w[1][1], w[0][2]]);
        } else if !current.is_empty() {
            out.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// Every pass keeps Z = `z_start` − revs × `pitch` between `z_from` and
/// `z_to` (past the start's catching up, before the end's braking).
fn check_locked(passes: &[Vec<[f64; 3]>], pitch: f64, z_start: f64, z_from: f64, z_to: f64) {
    for (k, pass) in passes.iter().enumerate() {
        let locked: Vec<_> = pass
            .iter()
            .filter(|s| s[1] < z_from && s[1] > z_to)
            .collect();
        assert!(
            locked.len() > 100,
            "pass {k}: {} locked samples",
            locked.len()
        );
        for s in locked {
            let phase = s[1] + s[2] * pitch - z_start;
            // halsampler prints six decimals.
            assert!(
                phase.abs() < 5e-6,
                "pass {k}: Z {} at revs {}: off the helix by {phase}",
                s[1],
                s[2]
            );
        }
    }
}

#[test]
fn g33_passes_start_at_the_same_spindle_angle() {
    let s = Scratch::new("task-g33");
    let m = lathe(&s, "task-g33");
    // The spindle model reports its speed in revolutions per second, as
    // motion's speed-in takes it: 600 rpm is 10.
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "S600", "M3"]);
    m.wait_getp("spindle.0.at-speed", "TRUE");
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    let mut rps: f64 = 0.0;
    while std::time::Instant::now() < end && (rps - 10.0).abs() > 1e-3 {
        rps = m.getp("spindle.0.speed-in").parse().unwrap();
    }
    assert!((rps - 10.0).abs() <= 1e-3, "speed-in {rps}");
    m.task_ok(&["mdi", "M5"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    m.task_ok(&["mode", "auto"]);
    // Three passes deeper each time, 1.5 mm pitch at 300 rpm (7.5 mm/s).
    let prog = "G21 G18 G90 G8\nS300 M3\n\
        G0 X12 Z2\n\
        G0 X10\nG33 Z-30 K1.5\nG0 X12\nG0 Z2\n\
        G0 X9.8\nG33 Z-30 K1.5\nG0 X12\nG0 Z2\n\
        G0 X9.6\nG33 Z-30 K1.5\nG0 X12\nG0 Z2\n\
        M5\nM2\n";
    let samples = run_recorded(&m, &s, "g33.ngc", prog);
    let p = passes(&samples, 12.0);
    assert_eq!(p.len(), 3, "three passes");
    for pass in &p {
        assert!((pass.last().unwrap()[1] + 30.0).abs() < 1e-9, "to Z-30");
    }
    check_locked(&p, 1.5, 2.0, 0.0, -29.0);
    // The spindle's direction pins followed M3 and M5.
    assert_eq!(m.getp("spindle.0.forward"), "FALSE");
    m.stop();
}

#[test]
fn a_g76_cycle_cuts_every_pass_on_the_same_helix() {
    let s = Scratch::new("task-g76");
    let m = lathe(&s, "task-g76");
    // Drive line X10 (radius), thread crest 0.5 inside it, 1 mm deep,
    // first pass 0.3, 1.25 mm pitch, no compound angle: every pass starts
    // at Z2.
    let prog = "G21 G18 G90 G8\nS240 M3\nG0 X10 Z2\n\
        G76 P1.25 Z-20 I-0.5 J0.3 K1 R1.5 H1\n\
        M5\nM2\n";
    let samples = run_recorded(&m, &s, "g76.ngc", prog);
    let p = passes(&samples, 10.0);
    assert!(p.len() >= 4, "{} passes", p.len());
    for pass in &p {
        assert!((pass.last().unwrap()[1] + 20.0).abs() < 1e-9, "to Z-20");
    }
    check_locked(&p, 1.25, 2.0, 0.0, -19.0);
    // Deeper each pass, to the full depth (X 10 - 0.5 - 1).
    let depths: Vec<f64> = p.iter().map(|q| q[q.len() / 2][0]).collect();
    assert!(depths.windows(2).all(|w| w[1] <= w[0] + 1e-9), "{depths:?}");
    assert!((depths.last().unwrap() - 8.5).abs() < 1e-6, "{depths:?}");
    m.stop();
}

#[test]
fn a_rigid_tap_reverses_the_spindle_and_comes_back_to_its_start() {
    let s = Scratch::new("task-g33-1");
    let m = lathe(&s, "task-g33-1");
    // A 1 mm pitch tap 12 mm deep at 300 rpm, back at 1.5 times the
    // speed; then a move from where the tap started.
    let prog = "G21 G18 G90\nS300 M3\nG0 X0 Z5\nG33.1 Z-7 K1 I1.5\nG0 X3\nM2\n";
    let samples = run_recorded(&m, &s, "tap.ngc", prog);
    let deepest = samples.iter().fold(f64::INFINITY, |d, s| d.min(s[1]));
    assert!(deepest <= -7.0 && deepest > -8.0, "deepest Z {deepest}");
    // The spindle turned back (its count went down) and forward again.
    let revs: Vec<f64> = samples.iter().map(|s| s[2]).collect();
    // (Not the restart of the count at the index, a whole turn.)
    let turning_back = |w: &[f64]| w[1] < w[0] - 1e-9 && w[0] - w[1] < 0.5;
    let down = revs.windows(2).position(turning_back).unwrap();
    let up_again = revs[down..].windows(2).position(|w| w[1] > w[0] + 1e-9);
    assert!(up_again.is_some(), "the spindle turned forward again");
    // Back on the start, X untouched until the G0 after it.
    let at_x3 = samples.iter().position(|s| s[0] > 0.0).unwrap();
    assert_eq!(samples[at_x3 - 1][1], 5.0, "Z back at the start");
    assert!(samples[..at_x3].iter().all(|s| s[0] == 0.0));
    // spindle.0.reverse followed: on while the count went down, off
    // again before the tap ended.
    assert!(samples[down + 1][3] == 1.0 || samples[down][3] == 1.0);
    assert_eq!(samples[at_x3 - 1][3], 0.0);
    m.stop();
}
