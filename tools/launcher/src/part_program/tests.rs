//! The interpreter against hand-worked programs, and its refusals.

use motion::command::{Command, LineKind, TermCond};
use motion::kins::Pose;
use proptest::prelude::*;

use super::interp::{interpret, Step, Units};
use super::*;

fn at(x: f64, y: f64, z: f64) -> Pose {
    let mut p = Pose::ZERO;
    p.0[0] = x;
    p.0[1] = y;
    p.0[2] = z;
    p
}

fn run(src: &str) -> Vec<Step> {
    interpret("p.ngc", src.as_bytes(), Pose::ZERO, Units::Mm).unwrap()
}

fn cmds(src: &str) -> Vec<Command> {
    run(src)
        .into_iter()
        .filter_map(|s| match s {
            Step::Send(c, _) => Some(c),
            _ => None,
        })
        .collect()
}

fn err(src: &str) -> String {
    interpret("p.ngc", src.as_bytes(), Pose::ZERO, Units::Mm)
        .unwrap_err()
        .to_string()
}

#[test]
fn lines_rapids_and_modes() {
    let c = cmds("G21 G90\nG0 X1 Y2\nG1 Z-1 F600\nX3\nG91 X1 Y1\n");
    assert_eq!(
        c,
        [
            Command::Line {
                end: at(1.0, 2.0, 0.0),
                vel: 0.0,
                ini_maxvel: 0.0,
                acc: 0.0,
                kind: LineKind::Traverse,
                id: 2
            },
            Command::Line {
                end: at(1.0, 2.0, -1.0),
                vel: 10.0,
                ini_maxvel: 0.0,
                acc: 0.0,
                kind: LineKind::Feed,
                id: 3
            },
            Command::Line {
                end: at(3.0, 2.0, -1.0),
                vel: 10.0,
                ini_maxvel: 0.0,
                acc: 0.0,
                kind: LineKind::Feed,
                id: 4
            },
            Command::Line {
                end: at(4.0, 3.0, -1.0),
                vel: 10.0,
                ini_maxvel: 0.0,
                acc: 0.0,
                kind: LineKind::Feed,
                id: 5
            },
        ]
    );
}

#[test]
fn inches_on_a_millimetre_machine_and_the_other_way() {
    let c = cmds("G20 G1 X1 F60\n");
    assert_eq!(
        c,
        [Command::Line {
            end: at(25.4, 0.0, 0.0),
            vel: 25.4,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Feed,
            id: 1
        }]
    );
    let c = interpret("p", b"G21 G1 X25.4 F25.4", Pose::ZERO, Units::Inch).unwrap();
    assert!(matches!(
        c[0],
        Step::Send(Command::Line { end, vel, .. }, _)
            if (end.0[0] - 1.0).abs() < 1e-12 && (vel - 1.0 / 60.0).abs() < 1e-12
    ));
}

#[test]
fn arcs_by_centre_and_radius_in_every_plane() {
    // A quarter, counter-clockwise, centre 5 above the start.
    let c = cmds("G1 X10 F60\nG3 X15 Y5 I0 J5\n");
    assert_eq!(
        c[1],
        Command::Circle {
            end: at(15.0, 5.0, 0.0),
            center: [10.0, 5.0, 0.0],
            normal: [0.0, 0.0, 1.0],
            turns: 0,
            vel: 1.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            id: 2
        }
    );
    // Clockwise by radius: the short way is the centre below the chord.
    let c = cmds("G2 X10 Y0 R5 F60\n");
    assert!(matches!(
        c[0],
        Command::Circle { center, turns: -1, .. } if center[0] == 5.0 && center[1].abs() < 1e-12
    ));
    let c = cmds("G2 X10 Y0 R-6 F60\n");
    let Command::Circle { center, .. } = c[0] else {
        panic!()
    };
    assert!(
        center[1] > 0.0,
        "the long way: the centre on the other side"
    );
    // G18: I and K, normal +Y; G19: J and K, normal +X; absolute centres.
    let c = cmds("G18 G90.1 G3 X2 Z0 I1 K0 F60\n");
    assert!(matches!(
        c[0],
        Command::Circle {
            center: [1.0, 0.0, 0.0],
            normal: [0.0, 1.0, 0.0],
            ..
        }
    ));
    let c = cmds("G19 G2 Y2 Z0 J1 F60 P3\n");
    assert!(matches!(
        c[0],
        Command::Circle {
            center: [0.0, 1.0, 0.0],
            normal: [1.0, 0.0, 0.0],
            turns: -3,
            ..
        }
    ));
    // A helix: the plane's third axis moves.
    let c = cmds("G3 X0 Y0 Z-2 I5 J0 F60 P2\n");
    assert!(matches!(
        c[0],
        Command::Circle { end, turns: 1, .. } if end.0[2] == -2.0
    ));
}

#[test]
fn termination_conditions_dwells_and_stops() {
    let s = run("G64 P0.05\nG61\nG61.1\nG4 P1.5\nM0\nM1\nM2\nG1 X1 F1\n");
    assert_eq!(
        s.iter()
            .filter_map(|s| match s {
                Step::Send(c, _) => Some(*c),
                _ => None,
            })
            .collect::<Vec<_>>(),
        [
            Command::SetTermCond {
                cond: TermCond::Blend,
                tolerance: 0.05
            },
            Command::SetTermCond {
                cond: TermCond::ExactPath,
                tolerance: 0.0
            },
            Command::SetTermCond {
                cond: TermCond::Stop,
                tolerance: 0.0
            },
            Command::Dwell {
                seconds: 1.5,
                id: 4
            },
        ]
    );
    assert!(matches!(s[4], Step::Pause(Loc { line: 5, column: 1 })));
    assert!(matches!(s[5], Step::OptionalPause(_)));
    assert!(matches!(s[6], Step::End(_)));
    assert_eq!(s.len(), 7, "nothing after M2");
}

#[test]
fn g64_q_merges_nearly_collinear_feed_moves() {
    let c = cmds("G64 P0 Q0.01\nG1 X1 Y0.001 F60\nX2 Y0\nX3 Y0.002\nX3 Y1\n");
    // Three moves within 0.01 of one line become one, then the turn.
    assert_eq!(c.len(), 3);
    assert!(matches!(c[1], Command::Line { end, id: 4, .. } if end.0[0] == 3.0));
    assert!(matches!(c[2], Command::Line { end, id: 5, .. } if end.0[1] == 1.0));
}

#[test]
fn refusals_name_the_place() {
    assert_eq!(
        err("G0 X1\n  G28\n"),
        "p.ngc:2:3: G28 is not supported (the runner knows G0 G1 G2 G3 G4 G17 G18 G19 G20 G21 \
         G61 G61.1 G64 G90 G91 G90.1 G91.1)"
    );
    assert_eq!(
        err("G1 X1\n"),
        "p.ngc:1:1: G1 with no feed rate: give an F word (units per minute)"
    );
    assert_eq!(
        err("M3 S1000\n"),
        "p.ngc:1:1: M3 is not supported (the runner knows M0 M1 M2 M30)"
    );
    assert_eq!(err("T1\n"), "p.ngc:1:1: T1 (tool change) is not supported");
    assert_eq!(
        err("X1\n"),
        "p.ngc:1:1: axis words with no motion mode (G0, G1, G2, G3)"
    );
    assert_eq!(
        err("G0 X1 X2\n"),
        "p.ngc:1:7: X word given twice on one line"
    );
    assert_eq!(
        err("G0 G1 X1\n"),
        "p.ngc:1:4: G1 conflicts with another code of its group on this line"
    );
    assert_eq!(
        err("G17 G2 X1 Y1 K1 F1\n"),
        "p.ngc:1:14: K word given for an arc in the G17 plane"
    );
    assert_eq!(
        err("G2 X1 Y0 I0.4 F60\n"),
        "p.ngc:1:1: radius to end of arc (0.600000) differs from radius to start (0.400000)"
    );
    assert_eq!(
        err("G2 X10 R2 F60\n"),
        "p.ngc:1:8: radius 2.000000 is too small for an arc ending 10.000000 away"
    );
    assert_eq!(err("G4\n"), "p.ngc:1:1: G4 needs P (seconds)");
    assert_eq!(
        err("G1 X1 P2 F1\n"),
        "p.ngc:1:7: P word with no code that takes it (G4, G64, G2, G3)"
    );
    assert_eq!(err("G1 X1 F0\n"), "p.ngc:1:7: F must be positive");
    assert!(err("G1 X#1 F1\n").starts_with("p.ngc:1:"));
    assert!(err("O100 sub\n").starts_with("p.ngc:1:"));
}

#[test]
fn non_utf8_is_refused_where_it_starts() {
    let e = interpret("p.ngc", b"G0 X1\nG0 Y\xff2\n", Pose::ZERO, Units::Mm).unwrap_err();
    assert_eq!(e.to_string(), "p.ngc:2:5: not UTF-8 text");
}

#[test]
fn huge_code_numbers_are_refused_not_wrapped() {
    // 4294967297 times ten wraps a u32 to a small, valid-looking code.
    assert_eq!(
        err("G0 X1\nG 4294967297 X2\n"),
        "p.ngc:2:1: G code number too large (at most 99999999)"
    );
    assert_eq!(
        err("m999999999999\n"),
        "p.ngc:1:1: M code number too large (at most 99999999)"
    );
    // Inside comments long numbers are text.
    assert!(interpret(
        "p.ngc",
        b"(G4294967297\n) ; M99999999999\nG0 X1\n",
        Pose::ZERO,
        Units::Mm
    )
    .is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100_000, ..ProptestConfig::default() })]

    /// The fuzz target (on stable, until the workspace's fuzz crate
    /// exists): random bytes from a G-code-ish alphabet.
    #[test]
    fn fuzz_program_never_panics(data in prop::collection::vec(
        prop::sample::select(b"GXYZIJKRPQFMN0123456789.-+ \n()#=;gxyzr\xc3\xff".to_vec()), 0..48)) {
        fuzz_program(&data);
    }
}
