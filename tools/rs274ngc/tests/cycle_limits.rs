//! A canned cycle whose L repeats or Q pecks would make an absurd number
//! of moves is refused before it drills, with the limit in the message;
//! so is a lathe cycle (G70-G72) whose I or P would, or whose profile
//! subroutine never returns. Ordinary cycles are untouched by the limit.

use std::io::Write;
use std::sync::{Arc, Mutex};

use rs274ngc::{Config, Interp, InterpError, PrintCanon, Status};

/// The canon output, shared with the test.
#[derive(Clone, Default)]
struct Captured(Arc<Mutex<Vec<u8>>>);

impl Write for Captured {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().expect("capture lock").extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Runs `program` (M2 is appended) to its end or first refusal: the
/// refusal (if any) and every canon line printed.
fn run(program: &str, config: Config) -> (Option<InterpError>, Vec<String>) {
    let captured = Captured::default();
    let mut canon = PrintCanon::new(Some(Box::new(captured.clone())), Vec::new());
    let mut interp = Interp::new(config);
    interp.init(&mut canon).expect("init");
    interp
        .open_bytes(
            std::path::Path::new("cycle.ngc"),
            format!("{program}M2\n").into_bytes(),
            &mut canon,
        )
        .expect("open");
    let mut refusal = None;
    loop {
        match interp.read(&mut canon) {
            Ok(Status::EndFile) => break,
            Ok(_) => {}
            Err(e) => {
                refusal = Some(e);
                break;
            }
        }
        match interp.execute(&mut canon) {
            Ok(Status::Exit) => break,
            Ok(_) => {}
            Err(e) => {
                refusal = Some(e);
                break;
            }
        }
    }
    canon.flush();
    let lines = String::from_utf8_lossy(&captured.0.lock().expect("capture lock"))
        .lines()
        .map(str::to_owned)
        .collect();
    (refusal, lines)
}

fn feeds(lines: &[String]) -> usize {
    lines.iter().filter(|l| l.contains("STRAIGHT_FEED")).count()
}

#[test]
fn an_ordinary_peck_cycle_drills_every_peck() {
    let (refusal, lines) = run(
        "G20 G17 G90 F10 S1000 M3\nG0 X0 Y0 Z1\nG83 X1 Y1 Z-1 R0.1 Q0.1\n",
        Config::default(),
    );
    assert!(refusal.is_none(), "refused: {refusal:?}");
    // From R 0.1 down in 0.1 pecks: feeds to 0.0, -0.1, ... and one that
    // the repeated subtraction leaves a hair above -1.0, then the feed to
    // the bottom, as LinuxCNC's interpreter does: 12 feeds.
    assert_eq!(feeds(&lines), 12, "{lines:#?}");
    assert!(lines
        .iter()
        .any(|l| l.contains("STRAIGHT_FEED(1.0000, 1.0000, -1.0000")));
}

#[test]
fn a_peck_too_small_to_deepen_the_hole_is_refused_before_it_drills() {
    let (refusal, lines) = run(
        "G20 G17 G90 F10\nG0 X0 Y0 Z1\nG83 X1 Y1 Z-1 R0.1 Q0.0000000000000000001\n",
        Config::default(),
    );
    let refusal = refusal.expect("the cycle was not refused");
    assert!(
        matches!(refusal, InterpError::CycleTooLong { code: 83, .. }),
        "{refusal:?}"
    );
    assert!(refusal.to_string().contains("1000000 allowed"), "{refusal}");
    assert_eq!(feeds(&lines), 0, "it drilled before refusing: {lines:#?}");
}

#[test]
fn repeats_beyond_the_limit_are_refused_and_the_limit_is_configurable() {
    let program = "G20 G17 G91 F10\nG0 X0 Y0 Z1\nG81 X0.1 Z-0.5 R0.1 L2000000000\n";
    let (refusal, lines) = run(program, Config::default());
    assert!(
        matches!(refusal, Some(InterpError::CycleTooLong { code: 81, .. })),
        "{refusal:?}"
    );
    assert_eq!(feeds(&lines), 0, "{lines:#?}");

    let small = Config {
        max_cycle_moves: 100,
        ..Config::default()
    };
    let (refusal, _) = run(
        "G20 G17 G91 F10\nG0 X0 Y0 Z1\nG81 X0.1 Z-0.5 R0.1 L20\n",
        small.clone(),
    );
    assert!(
        matches!(refusal, Some(InterpError::CycleTooLong { limit: 100, .. })),
        "{refusal:?}"
    );
    let (refusal, lines) = run(
        "G20 G17 G91 F10\nG0 X0 Y0 Z1\nG81 X0.1 Z-0.5 R0.1 L10\n",
        small,
    );
    assert!(refusal.is_none(), "{refusal:?}");
    assert_eq!(feeds(&lines), 10, "{lines:#?}");
}

/// A G71 profile (a shoulder) in subroutine 100, then `cycle`.
fn lathe_program(cycle: &str) -> String {
    format!(
        "G18 G21 G90 G8 F100\nG0 X12 Z2\no100 sub\nG1 X3 Z0\nG1 Z-12\nG1 X11\no100 endsub\n{cycle}\n"
    )
}

#[test]
fn an_ordinary_lathe_roughing_cycle_cuts_every_pass() {
    let (refusal, lines) = run(&lathe_program("G71 Q100 D0.2 I1"), Config::default());
    assert!(refusal.is_none(), "refused: {refusal:?}");
    // From X12 down to the 3.2 shoulder in 1 mm passes: 9 passes and
    // the cut along the finished profile.
    assert!(feeds(&lines) >= 9, "{lines:#?}");
}

#[test]
fn a_lathe_cut_increment_too_small_for_the_profile_is_refused_before_it_cuts() {
    let (refusal, lines) = run(
        &lathe_program("G71 Q100 D0.2 I0.000000001"),
        Config::default(),
    );
    let refusal = refusal.expect("the cycle was not refused");
    assert!(
        matches!(refusal, InterpError::G7xTooManyPasses { limit: 1_000_000 }),
        "{refusal:?}"
    );
    assert!(
        refusal.to_string().contains("more than 1000000 moves"),
        "{refusal}"
    );
    assert_eq!(feeds(&lines), 0, "it cut before refusing: {lines:#?}");
}

#[test]
fn finishing_passes_beyond_the_limit_are_refused() {
    let (refusal, lines) = run(&lathe_program("G70 Q100 P1000000000"), Config::default());
    assert!(
        matches!(refusal, Some(InterpError::G7xTooManyPasses { .. })),
        "{refusal:?}"
    );
    assert_eq!(feeds(&lines), 0, "{lines:#?}");
}

#[test]
fn a_profile_subroutine_that_never_returns_is_refused() {
    let program = "G18 G21 G90 G8 F100\nG0 X12 Z2\no100 sub\nG1 X3 Z0\n\
                   o101 while [1]\nG1 Z-12\no101 endwhile\no100 endsub\nG71 Q100 I1\n";
    let (refusal, lines) = run(program, Config::default());
    assert!(
        matches!(refusal, Some(InterpError::G7xProfileTooLong(_))),
        "{refusal:?}"
    );
    assert_eq!(feeds(&lines), 0, "{lines:#?}");
}

#[test]
fn a_profile_whose_passes_never_end_is_refused() {
    // On this profile (an arc bottoming out just under a pass) LinuxCNC
    // 2.9's G71 loops for ever without a move; ours stops at the limit.
    let program = "G18 G20 G90 G7 F5\nG0 X2 Z0.3\no100 sub\nG1 X0.205 Z0.000\n\
                   G2 X0.115 Z-0.100 I0.0645 K-0.1478\nG1 X0.235 Z-0.153\nG1 X0.361\n\
                   o100 endsub\nG71 Q100 D0.009 I0.069 R0.013\n";
    let small = Config {
        max_cycle_moves: 10_000,
        ..Config::default()
    };
    let (refusal, lines) = run(program, small);
    assert!(
        matches!(
            refusal,
            Some(InterpError::G7xTooManyPasses { limit: 10_000 })
        ),
        "{refusal:?}"
    );
    assert_eq!(feeds(&lines), 0, "{lines:#?}");
}
