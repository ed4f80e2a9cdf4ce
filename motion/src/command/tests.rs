//! The command line of every command: round trips through the words, and
//! the errors of bad words.

use super::*;
use crate::channel::{decode_command, encode_command};
use crate::kins::Pose;
use crate::vocab::{HomeFlags, HomingConfig};

fn args(s: &str) -> Vec<String> {
    s.split_whitespace().map(String::from).collect()
}

/// A command line's command, parsed against `goal`.
fn cmd(line: &str, goal: Pose) -> Result<Command, CliError> {
    let words = args(line);
    parse(&words[0], &words[1..], goal)
}

#[test]
fn every_command_round_trips_through_the_wire_and_the_command_line() {
    let mut goal = Pose::ZERO;
    goal.0[4] = 7.5;
    let mut said = std::collections::BTreeSet::new();
    for (i, c) in crate::channel::tests::all_commands()
        .into_iter()
        .enumerate()
    {
        let serial = 10 + i as u64;
        assert_eq!(decode_command(&encode_command(serial, &c)), Ok((serial, c)));
        let Some(line) = c.to_cli() else {
            // Only these cannot be said on the command line.
            assert!(
                matches!(c, Command::SetJointHomingParams { config, .. }
                    if config.flags.contains(HomeFlags::NO_REHOME)
                        && !config.flags.contains(HomeFlags::ABSOLUTE_ENCODER)),
                "{c:?}"
            );
            continue;
        };
        assert_eq!(line[0], c.name(), "{c:?}");
        assert_eq!(parse(&line[0], &line[1..], goal), Ok(c), "{line:?}");
        said.insert(line[0].clone());
    }
    // Every command line is some command's.
    let names: std::collections::BTreeSet<String> =
        CLI_NAMES.iter().map(|n| n.to_string()).collect();
    assert_eq!(said, names);
}

#[test]
fn a_form_says_only_the_values_it_can() {
    let rapid = |vel| Command::Line {
        end: Pose::ZERO,
        vel,
        ini_maxvel: 0.0,
        acc: 0.0,
        kind: LineKind::Traverse,
        id: 1,
    };
    assert_eq!(rapid(0.0).name(), "rapid");
    assert_eq!(rapid(2.0).to_cli(), None);
    assert_eq!(rapid(2.0).name(), "line");
    let stop = |tolerance| Command::SetTermCond {
        cond: TermCond::Stop,
        tolerance,
    };
    assert_eq!(stop(0.0).to_cli(), Some(args("term-cond stop")));
    assert_eq!(stop(0.1).to_cli(), None);
    let odd = Command::SetJointHomingParams {
        joint: 0,
        config: HomingConfig {
            flags: HomeFlags::NO_FINAL_MOVE,
            ..HomingConfig::default()
        },
    };
    assert_eq!(odd.to_cli(), None);
    assert_eq!(cli_group("line"), Some(CliGroup::Planner));
    assert_eq!(cli_group("jog-cont"), Some(CliGroup::Basic));
    assert_eq!(cli_group("status"), None);
}

#[test]
fn moves_keep_the_axes_left_out() {
    let mut goal = Pose::ZERO;
    goal.0[2] = 5.0;
    let c = cmd("line 3 12.5 X=1 y=-2", goal).unwrap();
    let mut end = goal;
    end.0[0] = 1.0;
    end.0[1] = -2.0;
    assert_eq!(
        c,
        Command::Line {
            end,
            vel: 12.5,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Feed,
            id: 3
        }
    );
    let c = cmd("arc 4 2 X=1 center=0.5,0,5 turns=-1", goal).unwrap();
    assert!(matches!(
        c,
        Command::Circle {
            center: [0.5, 0.0, 5.0],
            normal: [0.0, 0.0, 1.0],
            turns: -1,
            ..
        }
    ));
    assert_eq!(
        cmd("term-cond blend 0.02", goal).unwrap(),
        Command::SetTermCond {
            cond: TermCond::Blend,
            tolerance: 0.02
        }
    );
    assert!(matches!(
        cmd("probe 1 2 G38.3 Z=-1", goal).unwrap(),
        Command::Probe {
            probe: ProbeType::G38_3,
            ..
        }
    ));
}

#[test]
fn bad_words_say_what() {
    let g = Pose::ZERO;
    let err = |line| cmd(line, g).unwrap_err().to_string();
    assert_eq!(err("line 1 5 X=1 X=2"), "axis X given twice");
    assert!(err("line 1 5 Q=1").starts_with("unknown word 'Q'"));
    assert_eq!(
        err("arc 1 5 q=1"),
        "unknown word 'q' (axes are X Y Z A B C U V W; also center, normal, turns)"
    );
    assert_eq!(err("arc 1 5 X=1"), "'arc' needs center=X,Y,Z");
    assert_eq!(
        err("probe 1 5 G38.9"),
        "probe TYPE must be G38.2, G38.3, G38.4 or G38.5, not 'G38.9'"
    );
    assert_eq!(err("dwell 1"), "'dwell' takes 2 argument(s), 1 given");
    assert_eq!(err("line x 5"), "ID must be a number, not 'x'");
    assert_eq!(err("jog-cont x 1"), "JOINT must be an integer, not 'x'");
    assert_eq!(err("jog-cont 0"), "missing VEL");
    assert_eq!(
        err("jog-cont 0 1 2"),
        "'jog-cont' takes 2 argument(s), 3 given"
    );
    assert_eq!(err("rapid"), "'rapid' takes at least 1 arguments");
    assert_eq!(
        err("term-cond"),
        "term-cond needs stop, exact or blend, not None"
    );
    assert_eq!(
        err("term-cond stop 1"),
        "'term-cond' takes 1 argument(s), 2 given"
    );
    assert_eq!(
        err("axis-jog-cont q 1"),
        "AXIS must be one of x y z a b c u v w or a number, not 'q'"
    );
    assert_eq!(
        err("set-homing-params 0 HOME_ABSOLUTE_ENCODER=3"),
        "HOME_ABSOLUTE_ENCODER must be 0, 1 or 2, not '3'"
    );
    assert_eq!(err("set-homing-params 0 FOO=1"), "unknown homing key 'FOO'");
    assert_eq!(err("bogus"), "unknown command 'bogus'");
}

#[test]
fn homing_keys_take_the_ini_defaults_and_meanings() {
    let c = cmd(
        "set-homing-params 2 HOME_SEQUENCE=-1 home_use_index=yes HOME_ABSOLUTE_ENCODER=2",
        Pose::ZERO,
    )
    .unwrap();
    let Command::SetJointHomingParams { joint: 2, config } = c else {
        panic!("{c:?}");
    };
    assert_eq!((config.final_vel, config.sequence), (-1.0, -1));
    assert_eq!(
        config.flags,
        HomeFlags::USE_INDEX
            | HomeFlags::ABSOLUTE_ENCODER
            | HomeFlags::NO_REHOME
            | HomeFlags::NO_FINAL_MOVE
    );
    let c = cmd("set-homing-params 0", Pose::ZERO).unwrap();
    assert!(matches!(
        c,
        Command::SetJointHomingParams { config, .. } if config.sequence == 999
    ));
}
