//! The README's main job: configs/sim/sim.hal reaches its commanded
//! positions with exact step counts.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

#[test]
fn the_simulated_machine_reaches_its_targets() {
    // The shipped file runs its threads for two seconds of wall time; on a
    // loaded machine without realtime that is not always enough for the
    // moves to finish, so the test runs a copy that waits until the motor
    // model has counted every step (bounded at a minute), then settles.
    let src = common::root().join("configs/sim/sim.hal");
    let dir = std::env::temp_dir().join(format!("hal-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let halcmd = env!("CARGO_BIN_EXE_halcmd");
    // halcmd substitutes `$(NAME)` itself, so the loop lives in a script.
    let script = format!(
        "for i in $(seq 600); do\n\
         [ \"$({halcmd} getp updown.0.count)\" = 2000 ] &&\n\
         [ \"$({halcmd} getp updown.1.count)\" = -800 ] &&\n\
         [ \"$({halcmd} getp updown.2.count)\" = 500 ] && break\n\
         sleep 0.1\ndone\nsleep 0.2\n"
    );
    std::fs::write(dir.join("wait-steps.sh"), script).unwrap();
    let wait = "loadusr -w sh wait-steps.sh";
    let text = std::fs::read_to_string(&src).unwrap();
    assert!(
        text.contains("loadusr -w sleep 2"),
        "sim.hal still waits with sleep 2"
    );
    std::fs::write(
        dir.join("sim.hal"),
        text.replace("loadusr -w sleep 2", wait),
    )
    .unwrap();
    let out = common::halrun(&dir, &["-f", "sim.hal"], "sim");
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (axis, steps, pos) in [(0, "2000", "10"), (1, "-800", "-4"), (2, "500", "2.5")] {
        let counted = format!("{steps}  updown.{axis}.count");
        let reached = format!("{pos}  scale.{axis}.out");
        assert!(
            stdout.contains(&counted),
            "axis {axis}: no '{counted}' in\n{stdout}"
        );
        assert!(
            stdout.contains(&reached),
            "axis {axis}: no '{reached}' in\n{stdout}"
        );
        let generated = format!("{steps}  stepgen.{axis}.counts");
        assert!(
            stdout.contains(&generated),
            "axis {axis}: stepgen made other than {steps} steps\n{stdout}"
        );
    }
    assert!(stdout.contains("base-thread"), "thread timing shown");
}

/// The README's main job: configs/sim/mill.hal enables and homes the
/// simulated mill, runs pocket.ngc and writes the plot and the summary
/// (run on a copy of the folder, so the repository stays clean).
#[test]
fn the_simulated_mill_runs_the_pocket_and_plots_it() {
    let src = common::root().join("configs/sim");
    let dir = std::env::temp_dir().join(format!("hal-mill-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for f in ["mill.hal", "mill-machine.hal", "pocket.ngc"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(["-f", "mill.hal"])
        .current_dir(&dir)
        .env("HAL_INSTANCE", common::instance("mill"))
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (8u64 << 20).to_string())
        .output()
        .expect("halrun runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("pocket.ngc: done in"), "{stdout}");
    let summary = stdout
        .lines()
        .find(|l| l.contains("max following error"))
        .expect("the summary");
    assert!(summary.ends_with("plot pocket.png"), "{summary}");
    let png = std::fs::read(dir.join("pocket.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let _ = std::fs::remove_dir_all(&dir);
}
