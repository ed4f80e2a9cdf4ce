//! Canonical calls task carries out beyond moves, spindle and coolant,
//! run through task on the simulated mill: user M-codes M100 to M199,
//! G10 L0 (reload the tool table), M19 (spindle orientation) and G38.2 to
//! G38.5 (probing).

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use machine::{mill_copy, Machine, Scratch};

/// The machine on and homed, in AUTO mode.
fn auto(m: &Machine) {
    m.on_and_homed();
    m.task_ok(&["mode", "auto"]);
}

fn pos(m: &Machine, joint: usize) -> f64 {
    m.getp(&format!("joint.{joint}.pos-cmd")).parse().unwrap()
}

/// Writes an executable shell script `name` in `s`.
fn script(s: &Scratch, name: &str, body: &str) -> PathBuf {
    let p = s.write(name, &format!("#!/bin/sh\n{body}"));
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
    p
}

/// Adds `line` to section `[section]` of the INI file.
fn ini_add(ini: &Path, section: &str, line: &str) {
    let text = std::fs::read_to_string(ini).unwrap();
    let head = format!("[{section}]\n");
    assert!(text.contains(&head), "no [{section}] in {}", ini.display());
    std::fs::write(ini, text.replacen(&head, &format!("{head}{line}\n"), 1)).unwrap();
}

/// Runs `prog` in AUTO mode to its end: (success, stdout, stderr).
fn run(m: &Machine, prog: &Path) -> (bool, String, String) {
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    m.task(&["-t", "60", "wait-done"])
}

#[test]
fn user_m_codes_run_their_program_with_p_and_q_between_moves() {
    let s = Scratch::new("task-user-m");
    let ini = mill_copy(&s);
    // USER_M_PATH: the first directory with an executable M101 wins; the
    // program prefix (../../nc_files/ here, absent) comes first.
    ini_add(&ini, "RS274NGC", "USER_M_PATH = mfiles:more");
    let halcmd = env!("CARGO_BIN_EXE_halcmd");
    let log = s.0.join("m101.log");
    script(
        &s,
        "mfiles/M101",
        &format!(
            "echo \"args $1 $2\" >> {log}\n\
             echo \"x $({halcmd} getp joint.0.pos-cmd)\" >> {log}\n\
             sleep 0.3\n\
             echo \"x $({halcmd} getp joint.0.pos-cmd)\" >> {log}\n",
            log = log.display()
        ),
    );
    script(&s, "more/M101", "exit 9\n");
    script(&s, "more/M102", "exit 3\n");
    // Not executable: not a user M-code.
    s.write("mfiles/M103", "#!/bin/sh\n");
    let prog = s.write(
        "user-m.ngc",
        "G21 G90\nG0 X5\nM101 P1.5 Q-2\nG0 X7\nM101\nM2\n",
    );
    let m = Machine::start(&ini, "task-user-m");
    auto(&m);
    let (ok, out, err) = run(&m, &prog);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    assert!((pos(&m, 0) - 7.0).abs() < 1e-9);
    // P and Q as C's %f prints them, -1 when absent; the program ran once
    // X5 was reached, and X7 waited until it had exited.
    let text = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6, "{text}");
    assert_eq!(lines[0], "args 1.500000 -2.000000", "{text}");
    assert_eq!(lines[3], "args -1.000000 -1.000000", "{text}");
    for (i, want) in [(1, 5.0), (2, 5.0), (4, 7.0), (5, 7.0)] {
        let x: f64 = lines[i].trim_start_matches("x ").parse().unwrap();
        assert!((x - want).abs() < 1e-9, "line {i}: {text}");
    }

    // A program that exits with a non-zero status stops the run and
    // names the line and the file; the move after it does not run.
    let bad = s.write("bad.ngc", "G21 G90\nG0 X1\nM102 P3\nG0 X2\nM2\n");
    let (ok, out, err) = run(&m, &bad);
    assert!(!ok, "{out}");
    assert!(err.contains("bad.ngc:3: M102: "), "{err}");
    assert!(err.contains("more/M102 exited with status 3"), "{err}");
    assert!((pos(&m, 0) - 1.0).abs() < 1e-9);

    // No executable M103: the interpreter's error, with the place.
    let unknown = s.write("unknown.ngc", "G21 G90\nG0 X3\nM103\nM2\n");
    let (ok, _, err) = run(&m, &unknown);
    assert!(!ok);
    assert!(err.contains("unknown.ngc:3"), "{err}");
    assert!(err.contains("Unknown m code used: M103"), "{err}");

    // MDI runs them too.
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "M101", "P7"]);
    m.task_ok(&["-t", "60", "wait-done"]);
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(text.contains("args 7.000000 -1.000000"), "{text}");
    m.stop();
}

#[test]
fn g10_l0_reloads_the_tool_table_the_next_g43_uses() {
    let s = Scratch::new("task-g10l0");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-g10l0");
    auto(&m);
    // The file changes under the running machine: T2 becomes 7.5 long.
    let table = s.0.join("sim.tbl");
    let text = std::fs::read_to_string(&table).unwrap();
    std::fs::write(
        &table,
        text.replace("T2 P2 D6.0 Z+20.5", "T2 P2 D6.0 Z+7.5"),
    )
    .unwrap();
    let prog = s.write(
        "reload.ngc",
        "G21 G90\nG10 L0\nT2 M6\nG43\nG0 X1 Z-10\nM2\n",
    );
    let (ok, out, err) = run(&m, &prog);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    let status = m.task_ok(&["status"]);
    assert!(status.contains("tool 0.0000 0.0000 7.5000"), "{status}");
    assert!((pos(&m, 2) + 2.5).abs() < 1e-9, "{status}");
    // With a tool in the spindle the interpreter refuses it, as
    // LinuxCNC's does.
    let again = s.write("again.ngc", "G10 L0\nM2\n");
    let (ok, _, err) = run(&m, &again);
    assert!(!ok);
    assert!(err.contains("again.ngc:1"), "{err}");
    // A table that cannot be read fails the run at its line; the
    // table in use stays.
    let unload = s.write("unload.ngc", "G49\nT0 M6\nM2\n");
    let (ok, out, err) = run(&m, &unload);
    assert!(ok, "{out}{err}");
    std::fs::write(&table, "T1 P1 Z+1 junk here\nT3 P\n").unwrap();
    let bad = s.write("bad-table.ngc", "G21 G90\nG0 X2\nG10 L0\nG0 X3\nM2\n");
    let (ok, _, err) = run(&m, &bad);
    assert!(!ok);
    assert!(err.contains("line 3: G10 L0: "), "{err}");
    assert!(err.contains("sim.tbl"), "{err}");
    assert!((pos(&m, 0) - 2.0).abs() < 1e-9);
    m.stop();
}

/// Waits (up to 20 s) until `halcmd getp PIN` reads `want`.
fn wait_pin(m: &Machine, pin: &str, want: &str) {
    let got = m.wait_getp(pin, want);
    assert_eq!(got, want, "{pin}\n{}", m.task_ok(&["status"]));
}

#[test]
fn m19_orients_the_spindle_and_waits_for_is_oriented() {
    let s = Scratch::new("task-m19");
    let ini = mill_copy(&s);
    ini_add(&ini, "RS274NGC", "ORIENT_OFFSET = 5");
    let prog = s.write(
        "orient.ngc",
        "G21 G90\nM3 S1000\nG0 X1\nM19 R30 P1 Q5\nG0 X2\nM0\nM2\n",
    );
    let m = Machine::start(&ini, "task-m19");
    auto(&m);
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    // The spindle stops and the drive is asked for R plus ORIENT_OFFSET.
    wait_pin(&m, "spindle.0.orient", "TRUE");
    assert_eq!(m.getp("spindle.0.orient-angle"), "35");
    assert_eq!(m.getp("spindle.0.orient-mode"), "1");
    assert_eq!(m.getp("spindle.0.on"), "FALSE");
    assert_eq!(m.getp("spindle.0.locked"), "FALSE");
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(
        (pos(&m, 0) - 1.0).abs() < 1e-9,
        "X moved before is-oriented"
    );
    m.halcmd(&["setp", "spindle.0.is-oriented", "TRUE"]);
    // Oriented: locked with the brake on, and the program goes on to X2
    // and its M0.
    wait_pin(&m, "spindle.0.locked", "TRUE");
    assert_eq!(m.getp("spindle.0.orient"), "FALSE");
    assert_eq!(m.getp("spindle.0.brake"), "TRUE");
    let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while !m.task_ok(&["status"]).contains("interp: HELD") {
        assert!(
            std::time::Instant::now() < end,
            "{}",
            m.task_ok(&["status"])
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!((pos(&m, 0) - 2.0).abs() < 1e-9);
    // M2 stops the spindle, which ends the lock, as in LinuxCNC.
    m.task_ok(&["resume"]);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    assert_eq!(m.getp("spindle.0.locked"), "FALSE");
    m.halcmd(&["setp", "spindle.0.is-oriented", "FALSE"]);

    // No is-oriented within Q seconds: LinuxCNC's message, the line.
    let slow = s.write("slow.ngc", "G21 G90\nM19 R10 Q0.5\nG0 X3\nM2\n");
    let (ok, _, err) = run(&m, &slow);
    assert!(!ok);
    assert!(
        err.contains("line 2: wait for orient complete: TIMED OUT"),
        "{err}"
    );
    assert!((pos(&m, 0) - 2.0).abs() < 1e-9);

    // A fault code from the drive fails the orientation.
    let fault = s.write("fault.ngc", "G21 G90\nM19 R0 Q5\nG0 X3\nM2\n");
    m.task_ok(&["open", fault.to_str().unwrap()]);
    m.task_ok(&["run"]);
    wait_pin(&m, "spindle.0.orient", "TRUE");
    m.halcmd(&["setp", "spindle.0.orient-fault", "3"]);
    let (ok, _, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(!ok);
    assert!(
        err.contains("line 2: fault 3 during orient in progress"),
        "{err}"
    );
    assert_eq!(m.getp("spindle.0.orient"), "FALSE");
    assert!((pos(&m, 0) - 2.0).abs() < 1e-9);
    m.stop();
}

#[test]
fn g38_probes_stop_on_contact_and_hand_back_5061_to_5070() {
    let s = Scratch::new("task-probe");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-probe");
    auto(&m);
    let prog = s.write(
        "probe.ngc",
        "G21 G90\nG0 X0 Y0 Z0\nG38.2 X10 F300\nG0 Y#5061 Z[#5070 * -1]\nM2\n",
    );
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
    let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while pos(&m, 0) < 2.0 {
        assert!(
            std::time::Instant::now() < end,
            "{}",
            m.task_ok(&["status"])
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    m.halcmd(&["setp", "motion.probe-input", "TRUE"]);
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    assert!(ok, "{out}{err}\n--- linuxcnc:\n{}", m.stderr());
    // Stopped short of X10; #5061 is where the contact came, #5070 1.
    let (x, y) = (pos(&m, 0), pos(&m, 1));
    assert!(x > 2.0 && x < 9.0, "x {x}");
    assert!(y >= 2.0 && y <= x, "y {y} x {x}");
    assert!((pos(&m, 2) + 1.0).abs() < 1e-9, "#5070");

    // Still tripped: a G38.2 is refused with motion's message.
    let again = s.write("again.ngc", "G21 G90\nG38.2 X0 F300\nM2\n");
    let (ok, _, err) = run(&m, &again);
    assert!(!ok);
    assert!(
        err.contains("line 2: Probe is already tripped when starting G38.2 or G38.3 move"),
        "{err}"
    );
    m.halcmd(&["setp", "motion.probe-input", "FALSE"]);

    // No contact: G38.2 fails and names the line, G38.3 gives #5070 0.
    let miss = s.write("miss.ngc", "G21 G90\nG38.2 X1 F600\nG0 Z-5\nM2\n");
    let (ok, _, err) = run(&m, &miss);
    assert!(!ok);
    assert!(
        err.contains("line 2: G38.2 move finished without making contact"),
        "{err}"
    );
    assert!((pos(&m, 0) - 1.0).abs() < 1e-6);
    assert!((pos(&m, 2) + 1.0).abs() < 1e-9, "Z-5 did not run");
    let quiet = s.write("quiet.ngc", "G21 G90\nG38.3 X0 F600\nG0 Z[#5070 - 2]\nM2\n");
    let (ok, out, err) = run(&m, &quiet);
    assert!(ok, "{out}{err}");
    assert!(pos(&m, 0).abs() < 1e-6);
    assert!((pos(&m, 2) + 2.0).abs() < 1e-9);
    m.stop();
}

/// The value of `name` in task's `stat` snapshot.
fn stat_value(m: &Machine, name: &str) -> String {
    let text = m.task_ok(&["stat"]);
    let head = format!("{name}=");
    let line = text
        .lines()
        .find(|l| l.starts_with(&head))
        .unwrap_or_else(|| panic!("no {name} in stat:\n{text}"));
    line.split_once(':').unwrap().1.to_string()
}

#[test]
fn traj_mode_and_axis_limits_are_set_through_task() {
    let s = Scratch::new("task-traj");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-traj");
    m.on_and_homed();
    // Pause and resume are taken with nothing running, and say so.
    assert!(m.task_ok(&["pause"]).contains("nothing runs to pause"));
    assert!(m.task_ok(&["resume"]).contains("nothing paused to resume"));
    // LinuxCNC's traj_mode: free (1), teleop (3), coordinated (2).
    m.task_ok(&["traj-mode", "free"]);
    assert_eq!(stat_value(&m, "motion_mode"), "1");
    m.task_ok(&["traj-mode", "teleop"]);
    assert_eq!(stat_value(&m, "motion_mode"), "3");
    // One soft limit of world axis X changes, the other is kept.
    let min_before = stat_value(&m, "axis.0.min_position_limit");
    m.task_ok(&["axis-limit", "0", "max", "12.5"]);
    assert_eq!(stat_value(&m, "axis.0.max_position_limit"), "12.5");
    assert_eq!(stat_value(&m, "axis.0.min_position_limit"), min_before);
    // A lower limit above the upper one is refused and changes nothing.
    let (ok, _, err) = m.task(&["axis-limit", "0", "min", "20"]);
    assert!(!ok);
    assert!(err.contains("above the upper limit"), "{err}");
    assert_eq!(stat_value(&m, "axis.0.min_position_limit"), min_before);
    m.stop();
}

#[test]
fn tool_offset_sets_the_table_and_the_next_g43_uses_it() {
    let s = Scratch::new("task-tooloff");
    let ini = mill_copy(&s);
    let m = Machine::start(&ini, "task-tooloff");
    m.on_and_homed();
    m.task_ok(&["tool-offset", "2", "21.5", "0.5", "6.5", "0", "0", "0"]);
    let text = m.task_ok(&["stat"]);
    let slot = text
        .lines()
        .find_map(|l| {
            l.strip_suffix("=i:2")?
                .strip_prefix("tool_table.")?
                .strip_suffix(".id")
        })
        .unwrap_or_else(|| panic!("no tool 2 in stat:\n{text}"));
    let field = |name: &str| stat_value(&m, &format!("tool_table.{slot}.{name}"));
    assert_eq!(field("zoffset"), "21.5");
    assert_eq!(field("xoffset"), "0.5");
    assert_eq!(field("diameter"), "6.5");
    // Saved to the table file, and taken by the interpreter's next G43.
    let saved = std::fs::read_to_string(s.0.join("sim.tbl")).unwrap();
    assert!(saved.contains("21.5"), "{saved}");
    m.task_ok(&["mode", "mdi"]);
    m.task_ok(&["mdi", "T2 M6 G43"]);
    m.task_ok(&["-t", "30", "wait-done"]);
    let offset = stat_value(&m, "tool_offset");
    assert_eq!(offset.split_whitespace().nth(2), Some("21.5"), "{offset}");
    // A tool the table does not hold is refused.
    let (ok, _, err) = m.task(&["tool-offset", "77", "1", "0", "0", "0", "0", "0"]);
    assert!(!ok);
    assert!(err.contains("tool 77 is not in the tool table"), "{err}");
    m.stop();
}
