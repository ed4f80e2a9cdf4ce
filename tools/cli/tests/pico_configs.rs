//! LinuxCNC's Pico Systems sample configurations (by_interface/pico),
//! copied from the LinuxCNC peer with only the simulator word added to
//! their `loadrt hal_ppmc` line, run headless through `linuxcnc` on the
//! simulated boards: each starts, takes an e-stop reset (through its
//! estop_latch chain and the board's estop circuit) and machine-on, and
//! joint 0 follows a jog through the simulated motor and counter.
//!
//! univpwmv is left out: it also loads `scope_rt`, which this suite does
//! not have yet.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::path::Path;

use machine::{Machine, Scratch};

/// Copies `dir` of the peer's pico samples into a scratch directory of
/// its own, appends `word` to every `loadrt hal_ppmc` line of its HAL
/// files, and starts `ini` there, turned on.
fn pico_machine(dir: &str, ini: &str, word: &str) -> (Machine, Scratch) {
    let src = Path::new(env!("HAL_PEER_SAMPLE_CONFIGS"))
        .join("by_interface/pico")
        .join(dir);
    let tag = format!("pico-{}", dir.to_lowercase());
    let s = Scratch::new(&tag);
    let mut added = 0;
    for entry in std::fs::read_dir(&src).unwrap().flatten() {
        let to = s.0.join(entry.file_name());
        let text = std::fs::read(entry.path()).unwrap();
        let name = entry.file_name().to_string_lossy().to_string();
        if !name.ends_with(".hal") {
            std::fs::write(&to, text).unwrap();
            continue;
        }
        let text = String::from_utf8(text).unwrap();
        let edited: Vec<String> = text
            .lines()
            .map(|l| {
                if l.trim_start().starts_with("loadrt hal_ppmc") {
                    added += 1;
                    format!("{l} {word}")
                } else {
                    l.to_string()
                }
            })
            .collect();
        std::fs::write(&to, edited.join("\n") + "\n").unwrap();
    }
    assert_eq!(added, 1, "{dir}: one loadrt hal_ppmc line");
    let m = Machine::start(&s.0.join(ini), &tag);
    assert!(m.threads_run(), "{dir}: threads run\n{}", m.stderr());
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(
        m.getp("motion.motion-enabled"),
        "TRUE",
        "{dir}\n{}",
        m.stderr()
    );
    (m, s)
}

/// Jogs joint 0 by `step` and checks its feedback lands within `within`.
fn follows_a_jog(m: &Machine, dir: &str, step: f64, within: f64) {
    m.motion(&["jog-incr", "0", "0.5", &step.to_string()]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    let fb: f64 = m.getp("joint.0.pos-fb").parse().unwrap();
    assert!(
        (fb - step).abs() < within,
        "{dir}: joint 0 follows the jog to {step}: {fb}\n{}",
        m.stderr()
    );
}

/// The PPMC set (encoder, DAC and DIO boards): the DAC loop closes, the
/// DIO board's estop circuit is out of estop.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn ppmc_runs_on_a_simulated_ppmc_set() {
    let (m, _copy) = pico_machine("ppmc", "ppmc.ini", "sim=ppmc");
    assert_eq!(m.getp("ppmc.0.din.estop.in"), "FALSE");
    assert_eq!(m.getp("ppmc.0.dout.Estop.out"), "TRUE");
    follows_a_jog(&m, "ppmc", 0.1, 0.002);
    m.stop();
}

/// The PPMC set with timestamped encoder velocity (`timestamp=0x00`).
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn ppmc_vel_runs_with_timestamps() {
    let (m, _copy) = pico_machine("ppmc_vel", "ppmc.ini", "sim=ppmc");
    assert_eq!(m.getp("ppmc.0.encoder.00.min-speed-estimate"), "0.001");
    follows_a_jog(&m, "ppmc_vel", 0.1, 0.002);
    m.stop();
}

/// The UPC: PWM generators with bootstrap, the estop on input 15.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn univpwm_runs_on_a_simulated_upc() {
    let (m, _copy) = pico_machine("univpwm", "univpwm.ini", "sim=upc");
    assert_eq!(m.getp("ppmc.0.din.15.in"), "TRUE");
    assert_eq!(m.getp("ppmc.0.pwm.00-03.freq"), "50000");
    follows_a_jog(&m, "univpwm", 0.1, 0.002);
    m.stop();
}

/// The USC: step generators, counters counting the steps.
#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn univstep_and_usc_encod_run_on_a_simulated_usc() {
    for (dir, ini) in [("univstep", "univstep.ini"), ("USC_encod", "univstep.ini")] {
        let (m, _copy) = pico_machine(dir, ini, "sim=usc");
        assert_eq!(m.getp("ppmc.0.din.15.in"), "TRUE", "{dir}");
        follows_a_jog(&m, dir, 0.1, 0.002);
        m.stop();
    }
}
