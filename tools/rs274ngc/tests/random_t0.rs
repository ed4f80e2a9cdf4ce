//! T0 and H0: on a non-random tool changer T0 is the empty spindle and
//! G43 H0 takes the spindle's entry; on a random changer T0 is an
//! ordinary tool, found in the table or refused when it has none
//! (LinuxCNC's tests/t0 cases).

use rs274ngc::{Config, Interp, InterpError, Pose, PrintCanon, Status, ToolEntry};

fn tool(toolno: i32, pocketno: i32, z: f64) -> ToolEntry {
    ToolEntry {
        toolno,
        pocketno,
        offset: Pose { z, ..Pose::ZERO },
        ..ToolEntry::EMPTY
    }
}

/// Runs `program` (in inches, the table's units here) on a changer of the kind given with `tools`; the first
/// refusal, if any, and the Z tool length offset in effect at the end.
fn run(program: &str, random: bool, tools: Vec<ToolEntry>) -> (Option<InterpError>, f64) {
    let mut canon = PrintCanon::new(None, tools);
    if random {
        canon.random_toolchanger_spindle();
    }
    let mut interp = Interp::new(Config {
        random_toolchanger: random,
        ..Config::default()
    });
    interp.init(&mut canon).expect("init");
    interp
        .open_bytes(
            std::path::Path::new("t0.ngc"),
            format!("G20\n{program}\nM2\n").into_bytes(),
            &mut canon,
        )
        .expect("open");
    let refusal = loop {
        match interp.read(&mut canon) {
            Ok(Status::EndFile) => break None,
            Ok(_) => {}
            Err(e) => break Some(e),
        }
        match interp.execute(&mut canon) {
            Ok(Status::Exit) => break None,
            Ok(_) => {}
            Err(e) => break Some(e),
        }
    };
    (refusal, interp.settings().tool_offset.z)
}

#[test]
fn h0_on_a_random_changer_is_tool_zero_of_the_table() {
    let with_t0 = vec![tool(1, 1, 1.0), tool(0, 2, 0.5)];
    let (refusal, z) = run("G43 H1\nG43 H0", true, with_t0);
    assert!(refusal.is_none(), "{refusal:?}");
    assert!((z - 0.5).abs() < 1e-9, "{z}");
    let (refusal, z) = run("G43 H1\nG43 H0", true, vec![tool(1, 1, 1.0)]);
    assert!(
        matches!(refusal, Some(InterpError::ToolNotFound(0))),
        "{refusal:?}"
    );
    assert!(
        (z - 1.0).abs() < 1e-9,
        "the refused G43 H0 left the offset: {z}"
    );
}

#[test]
fn h0_on_a_non_random_changer_is_the_spindle() {
    let (refusal, z) = run(
        "G43 H1\nG43 H0",
        false,
        vec![tool(1, 1, 1.0), tool(0, 2, 0.5)],
    );
    assert!(refusal.is_none(), "{refusal:?}");
    assert!(z.abs() < 1e-9, "{z}");
}
