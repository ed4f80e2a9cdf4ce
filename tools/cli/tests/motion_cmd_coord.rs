//! Coordinated motion from other processes: `motion-cmd` queues moves,
//! pauses and resumes, loads a compensation file (and refuses a broken
//! one with its file and line), and `gcode-run` runs a small program and
//! refuses an unsupported one before anything moves.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::{accepted, mcmd, run, start_motion_instance, wait_status};

fn gcode_run(args: &[&str], instance: &str) -> (i32, String, String) {
    let out = run(env!("CARGO_BIN_EXE_gcode-run"), args, instance);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn moves_are_queued_and_programs_run_from_other_processes() {
    let inst = common::instance("mcoord");
    let dir = std::env::temp_dir().join(format!("hal-mcoord-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();

    // Refusals that need no machine.
    let bad = dir.join("bad.ngc");
    std::fs::write(&bad, "G0 X1\nG1 Y2 F0\n  G43 H1\nM2\n").unwrap();
    let (code, _, err) = gcode_run(&["--check", bad.to_str().unwrap()], &inst);
    assert_eq!(code, 2);
    // Every refusal, earliest first, with its place and word.
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(
        lines[0].ends_with("bad.ngc:2:7: F0: Cannot do g1 with zero feed rate"),
        "{err}"
    );
    assert!(
        lines[1].ends_with("bad.ngc:3:7: H1: Requested tool 1 not found in the tool table"),
        "{err}"
    );
    let (code, _, err) = mcmd(&["line", "1", "5", "Q=1"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("unknown word 'Q'"), "{err}");

    let realtime = env!("CARGO_BIN_EXE_realtime");
    start_motion_instance(&inst);
    wait_status(&inst, "the first status", |s| s.contains("mode DISABLED"));
    for j in ["0", "1", "2"] {
        accepted(&["activate", j], &inst);
        accepted(&["set-limits", j, "-10", "10"], &inst);
        accepted(&["set-vel-limit", j, "20"], &inst);
        accepted(&["set-acc-limit", j, "500"], &inst);
    }
    for a in ["x", "y", "z"] {
        accepted(&["set-axis-limits", a, "-10", "10"], &inst);
        accepted(&["set-axis-vel-limit", a, "20"], &inst);
        accepted(&["set-axis-acc-limit", a, "500"], &inst);
    }

    // Compensation: a broken file names its line; a good one loads.
    let comp = dir.join("x.comp");
    std::fs::write(&comp, "-1 0.01 -0.01\n1 0.02\n").unwrap();
    let (code, _, err) = mcmd(&["load-comp", "0", comp.to_str().unwrap(), "1"], &inst);
    assert_eq!(code, 2);
    assert!(err.contains("x.comp:2: expected three numbers"), "{err}");
    std::fs::write(&comp, "-1 0.01 -0.01\n1 0.02 -0.02\n").unwrap();
    let (code, out, _) = mcmd(&["load-comp", "0", comp.to_str().unwrap(), "1"], &inst);
    assert_eq!(code, 0, "{out}");
    assert_eq!(
        out.matches("accepted").count(),
        3,
        "clear and two entries: {out}"
    );

    accepted(&["enable"], &inst);
    let (code, out, _) = mcmd(&["line", "1", "5", "X=1"], &inst);
    assert_eq!(code, 1);
    assert!(out.contains("not in coordinated mode"), "{out}");
    accepted(&["coord"], &inst);
    accepted(&["term-cond", "blend", "0.01"], &inst);
    accepted(&["line", "7", "5", "X=1"], &inst);
    accepted(&["line", "8", "5", "Y=1"], &inst);
    accepted(&["pause"], &inst);
    let s = wait_status(&inst, "the pause", |s| {
        s.contains("paused") && s.contains("speed 0.000000")
    });
    // Paused on the path: in line 7, or (on a loaded machine, where the
    // pause can come late) in line 8, never past the queue's end.
    assert!(s.contains("line 7") || s.contains("line 8"), "{s}");
    let (code, out, _) = mcmd(&["line", "9", "5", "X=20"], &inst);
    assert_eq!(code, 1);
    assert!(out.contains("outside its limits"), "{out}");
    accepted(&["resume"], &inst);
    let (code, _, _) = mcmd(&["wait", "queue-done"], &inst);
    assert_eq!(code, 0);
    let s = wait_status(&inst, "the end", |s| s.contains("line 8  queued 0"));
    assert!(
        s.lines()
            .any(|l| l.starts_with("0 ") && l.contains("1.000000")),
        "{s}"
    );

    // A program from there.
    let prog = dir.join("square.ngc");
    std::fs::write(
        &prog,
        "G21 G90 G64 P0.01\nG1 X2 Y1 F600\nG3 X3 Y2 I0 J1\nG1 Y3\nG0 X0 Y0\nM2\n",
    )
    .unwrap();
    let (code, out, err) = gcode_run(&["--no-keys", prog.to_str().unwrap()], &inst);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("square.ngc: done in"), "{out}");
    let s = wait_status(&inst, "the program's end", |s| {
        s.contains("line 5  queued 0")
    });
    assert!(s.contains("in-position yes"), "{s}");

    assert!(run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}
