//! LinuxCNC's QtPlasmaC sim configuration run unchanged (from a copy)
//! through `linuxcnc`: plasmac from qtplasmac_comp.hal in the hallib,
//! sim-torch, and QtPlasmaC's GUI panel skipped. A torch pulse lights
//! sim-torch; a probe test drives Z down through motion's external
//! offsets, finds the (simulated) float switch, holds at the pierce
//! height and takes the offset back.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{Machine, Scratch};

/// Copies the directory `from` into `to`, recursively.
fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

/// Waits (up to 10 s) for `pin` to read `want`, failing with the
/// machine's stderr.
fn wait(m: &Machine, pin: &str, want: &str) {
    let got = m.wait_getp(pin, want);
    assert_eq!(got, want, "{pin}\n{}", m.stderr());
}

/// Reads `pin` as a number until `holds` says yes or 20 s pass; the last
/// value read. (The torch and the offset move in their own processes and
/// threads: a fixed pause is too short on a loaded machine.)
fn wait_value(m: &Machine, pin: &str, holds: impl Fn(f64) -> bool) -> f64 {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
    loop {
        let v: f64 = m.getp(pin).parse().unwrap();
        if holds(v) || std::time::Instant::now() > end {
            return v;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_qtplasmac_probes_through_external_offsets() {
    let src = std::path::Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join("sim/qtplasmac");
    let s = Scratch::new("pqtplasma");
    copy_dir(&src, &s.0);
    let m = Machine::start(&s.0.join("qtplasmac_l_metric.ini"), "pqtplasma");
    m.on_and_homed();
    assert_eq!(m.getp("plasmac.offset-scale"), "1e-05");
    assert_eq!(m.getp("plasmac.homed"), "TRUE");
    assert_eq!(m.getp("sim-torch.voltage-in"), "100");

    // A torch pulse: plasmac.torch-on starts sim-torch.
    for (pin, v) in [
        ("torch-enable", "1"),
        ("torch-pulse-time", "0.5"),
        ("torch-pulse-start", "1"),
    ] {
        m.halcmd(&["setp", &format!("plasmac.{pin}"), v]);
    }
    wait(&m, "plasmac.state-out", "18");
    let volts = wait_value(&m, "sim-torch.voltage-out", |v| v > 0.0);
    assert!(volts > 0.0, "sim-torch lit: {volts}");
    m.halcmd(&["setp", "plasmac.torch-pulse-start", "0"]);
    wait(&m, "plasmac.state-out", "0");
    wait(&m, "sim-torch.voltage-out", "0");

    // What QtPlasmaC's panel would set.
    for (pin, v) in [
        ("axis-z-min-limit", "-150"),
        ("axis-z-max-limit", "15"),
        ("setup-feed-rate", "3000"),
        ("probe-feed-rate", "600"),
        ("probe-start-height", "140"),
        ("probe-final-speed", "100"),
        ("pierce-height", "3"),
    ] {
        m.halcmd(&["setp", &format!("plasmac.{pin}"), v]);
    }
    // A probe test: fast to -10, then slowly down until the float switch
    // (the signal the GUI panel would drive) trips.
    m.halcmd(&["setp", "plasmac.probe-test", "1"]);
    wait(&m, "plasmac.state-out", "2");
    assert_eq!(m.getp("axis.z.eoffset-enable"), "TRUE");
    // Trip the switch once Z is well into the slow part (below -10): the
    // pierce height is about 2.8 above where it trips.
    wait_value(&m, "joint.3.pos-fb", |z| z < -13.5);
    m.halcmd(&["sets", "sim:float", "1"]);
    wait(&m, "plasmac.state-out", "3");
    m.halcmd(&["sets", "sim:float", "0"]);
    wait(&m, "plasmac.state-out", "21");
    let z: f64 = m.getp("joint.3.pos-fb").parse().unwrap();
    let offset: f64 = m.getp("axis.z.eoffset").parse().unwrap();
    assert!(z < -10.0 && z > -20.0, "Z at the pierce height: {z}");
    assert!(
        (z - offset).abs() < 1e-6,
        "Z moved by the offset alone: {z} {offset}"
    );
    // Test over: the offset goes back and plasmac is idle.
    m.halcmd(&["setp", "plasmac.probe-test", "0"]);
    wait(&m, "plasmac.state-out", "0");
    wait(&m, "plasmac.z-offset-counts", "0");
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    // Motion's offset planner is LinuxCNC's simple_tp, operation for
    // operation: braking in whole periods, it comes to rest a little off a
    // zero request (up to 1.9e-5 mm seen here, as LinuxCNC would), so the
    // test allows a tenth of a micron rather than one count.
    const SETTLED_MM: f64 = 1e-4;
    let mut offset: f64 = m.getp("axis.z.eoffset").parse().unwrap();
    while offset.abs() > SETTLED_MM && std::time::Instant::now() < end {
        std::thread::sleep(std::time::Duration::from_millis(20));
        offset = m.getp("axis.z.eoffset").parse().unwrap();
    }
    assert!(offset.abs() <= SETTLED_MM, "offset taken back: {offset}");
    m.stop();
}
