//! The README's main job: configs/sim/sim.hal reaches its commanded
//! positions with exact step counts.

mod common;

#[test]
fn the_simulated_machine_reaches_its_targets() {
    let dir = common::root().join("configs/sim");
    let out = common::halrun(&dir, &["-f", "sim.hal"], "sim");
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
