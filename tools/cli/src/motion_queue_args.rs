//! `motion-cmd`'s queueing and planner commands: parsing their arguments
//! into [`Command`]s. A move's end point is given as `AXIS=VALUE` words
//! (`X=10 Y=-2.5`); the axes left out stay where the last queued move
//! ends (the status snapshot's goal), so nothing moves by accident.

use motion::command::{Command, LineKind, ProbeType, TermCond};
use motion::kins::{Pose, AXIS_LETTERS};

/// What went wrong with the arguments (printed with a hint to --help).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArgError(pub String);

impl std::fmt::Display for ArgError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn num<T: std::str::FromStr>(s: Option<&String>, what: &str) -> Result<T, ArgError> {
    let s = s.ok_or_else(|| ArgError(format!("missing {what}")))?;
    s.parse()
        .map_err(|_| ArgError(format!("{what} must be a number, not '{s}'")))
}

fn flag(s: Option<&String>, what: &str) -> Result<bool, ArgError> {
    match s.map(String::as_str) {
        Some("1" | "on" | "yes") => Ok(true),
        Some("0" | "off" | "no") => Ok(false),
        Some(o) => Err(ArgError(format!("{what} must be 0 or 1, not '{o}'"))),
        None => Err(ArgError(format!("missing {what}"))),
    }
}

/// Three numbers separated by commas (`1,2.5,0`).
fn triple(s: &str, what: &str) -> Result<[f64; 3], ArgError> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(ArgError(format!(
            "{what} needs three numbers separated by commas, not '{s}'"
        )));
    }
    let mut out = [0.0; 3];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p
            .trim()
            .parse()
            .map_err(|_| ArgError(format!("{what}: '{p}' is not a number")))?;
    }
    Ok(out)
}

/// The words after a move's fixed arguments: `AXIS=VALUE` end
/// coordinates, plus the `extra` keys the command takes.
struct Words {
    end: Pose,
    extra: Vec<(String, String)>,
}

fn words(args: &[String], start: Pose, extra_keys: &[&str]) -> Result<Words, ArgError> {
    let mut end = start;
    let mut seen = [false; 9];
    let mut extra = Vec::new();
    for a in args {
        let (k, v) = a
            .split_once('=')
            .ok_or_else(|| ArgError(format!("'{a}' is not AXIS=VALUE")))?;
        let key = k.to_ascii_lowercase();
        let mut chars = key.chars();
        if let (Some(c), None) = (chars.next(), chars.next()) {
            if let Some(i) = AXIS_LETTERS.iter().position(|&l| l == c) {
                if seen[i] {
                    return Err(ArgError(format!(
                        "axis {} given twice",
                        c.to_ascii_uppercase()
                    )));
                }
                seen[i] = true;
                end.0[i] = v
                    .parse()
                    .map_err(|_| ArgError(format!("{k} must be a number, not '{v}'")))?;
                continue;
            }
        }
        if extra_keys.contains(&key.as_str()) {
            extra.push((key, v.to_string()));
        } else {
            return Err(ArgError(format!(
                "unknown word '{k}' (axes are X Y Z A B C U V W{})",
                if extra_keys.is_empty() {
                    String::new()
                } else {
                    format!("; also {}", extra_keys.join(", "))
                }
            )));
        }
    }
    Ok(Words { end, extra })
}

/// Whether `name` is one of this module's commands.
pub fn is_queue_command(name: &str) -> bool {
    NAMES.contains(&name)
}

const NAMES: &[&str] = &[
    "line",
    "rapid",
    "arc",
    "probe",
    "dwell",
    "clear-probe",
    "term-cond",
    "pause",
    "resume",
    "step",
    "feed-scale",
    "rapid-scale",
    "max-feed-override",
    "feed-scale-enable",
    "feed-hold-enable",
    "adaptive-feed-enable",
    "spindle-scale-enable",
    "set-traj-vel",
    "set-traj-acc",
    "set-traj-jerk",
    "planner-type",
    "set-jerk-limit",
    "set-axis-jerk-limit",
    "comp-entry",
    "clear-comp",
];

/// Parses one of the queueing or planner commands. `goal` is where the
/// last queued move ends (axes left out of an end point keep it).
pub fn parse(name: &str, a: &[String], goal: Pose) -> Result<Command, ArgError> {
    let count = |n: usize| {
        if a.len() == n {
            Ok(())
        } else {
            Err(ArgError(format!(
                "'{name}' takes {n} argument(s), {} given",
                a.len()
            )))
        }
    };
    let at_least = |n: usize| {
        if a.len() >= n {
            Ok(())
        } else {
            Err(ArgError(format!("'{name}' takes at least {n} arguments")))
        }
    };
    let cmd = match name {
        "line" => {
            at_least(2)?;
            let w = words(&a[2..], goal, &[])?;
            Command::Line {
                end: w.end,
                vel: num(a.get(1), "VEL")?,
                kind: LineKind::Feed,
                id: num(a.first(), "ID")?,
            }
        }
        "rapid" => {
            at_least(1)?;
            let w = words(&a[1..], goal, &[])?;
            Command::Line {
                end: w.end,
                vel: 0.0,
                kind: LineKind::Traverse,
                id: num(a.first(), "ID")?,
            }
        }
        "arc" => {
            at_least(2)?;
            let w = words(&a[2..], goal, &["center", "normal", "turns"])?;
            let mut center = None;
            let mut normal = [0.0, 0.0, 1.0];
            let mut turns = 0;
            for (k, v) in &w.extra {
                match k.as_str() {
                    "center" => center = Some(triple(v, "center")?),
                    "normal" => normal = triple(v, "normal")?,
                    _ => {
                        turns = v
                            .parse()
                            .map_err(|_| ArgError(format!("turns must be an integer, not '{v}'")))?
                    }
                }
            }
            Command::Circle {
                end: w.end,
                center: center.ok_or_else(|| ArgError("'arc' needs center=X,Y,Z".into()))?,
                normal,
                turns,
                vel: num(a.get(1), "VEL")?,
                id: num(a.first(), "ID")?,
            }
        }
        "probe" => {
            at_least(3)?;
            let probe = match a[2].to_ascii_uppercase().as_str() {
                "G38.2" => ProbeType::G38_2,
                "G38.3" => ProbeType::G38_3,
                "G38.4" => ProbeType::G38_4,
                "G38.5" => ProbeType::G38_5,
                o => {
                    return Err(ArgError(format!(
                        "probe TYPE must be G38.2, G38.3, G38.4 or G38.5, not '{o}'"
                    )))
                }
            };
            let w = words(&a[3..], goal, &[])?;
            Command::Probe {
                end: w.end,
                vel: num(a.get(1), "VEL")?,
                probe,
                id: num(a.first(), "ID")?,
            }
        }
        "dwell" => {
            count(2)?;
            Command::Dwell {
                seconds: num(a.get(1), "SECONDS")?,
                id: num(a.first(), "ID")?,
            }
        }
        "clear-probe" => {
            count(0)?;
            Command::ClearProbeFlags
        }
        "term-cond" => {
            let cond = match a.first().map(String::as_str) {
                Some("stop") => TermCond::Stop,
                Some("exact") => TermCond::ExactPath,
                Some("blend") => TermCond::Blend,
                o => {
                    return Err(ArgError(format!(
                        "term-cond needs stop, exact or blend, not {o:?}"
                    )))
                }
            };
            let tolerance = if cond == TermCond::Blend && a.len() == 2 {
                num(a.get(1), "TOLERANCE")?
            } else {
                count(1)?;
                0.0
            };
            Command::SetTermCond { cond, tolerance }
        }
        "pause" | "resume" | "step" => {
            count(0)?;
            match name {
                "pause" => Command::Pause,
                "resume" => Command::Resume,
                _ => Command::Step,
            }
        }
        "feed-scale" | "rapid-scale" | "max-feed-override" => {
            count(1)?;
            let scale = num(a.first(), "SCALE")?;
            match name {
                "feed-scale" => Command::FeedScale { scale },
                "rapid-scale" => Command::RapidScale { scale },
                _ => Command::SetMaxFeedOverride { scale },
            }
        }
        "feed-scale-enable"
        | "feed-hold-enable"
        | "adaptive-feed-enable"
        | "spindle-scale-enable" => {
            count(1)?;
            let on = flag(a.first(), "the enable")?;
            match name {
                "feed-scale-enable" => Command::FeedScaleEnable { on },
                "feed-hold-enable" => Command::FeedHoldEnable { on },
                "adaptive-feed-enable" => Command::AdaptiveFeedEnable { on },
                _ => Command::SpindleScaleEnable { on },
            }
        }
        "set-traj-vel" => {
            count(1)?;
            Command::SetVelLimit {
                vel: num(a.first(), "VEL")?,
            }
        }
        "set-traj-acc" => {
            count(1)?;
            Command::SetAccLimit {
                acc: num(a.first(), "ACC")?,
            }
        }
        "set-traj-jerk" => {
            count(1)?;
            Command::SetJerkLimit {
                jerk: num(a.first(), "JERK")?,
            }
        }
        "planner-type" => {
            count(1)?;
            Command::SetPlannerType {
                planner: num(a.first(), "TYPE")?,
            }
        }
        "set-jerk-limit" => {
            count(2)?;
            Command::SetJointJerkLimit {
                joint: num(a.first(), "JOINT")?,
                jerk: num(a.get(1), "JERK")?,
            }
        }
        "set-axis-jerk-limit" => {
            count(2)?;
            Command::SetAxisJerkLimit {
                axis: axis(a.first())?,
                jerk: num(a.get(1), "JERK")?,
            }
        }
        "comp-entry" => {
            count(4)?;
            Command::SetJointComp {
                joint: num(a.first(), "JOINT")?,
                nominal: num(a.get(1), "NOMINAL")?,
                forward: num(a.get(2), "FORWARD")?,
                reverse: num(a.get(3), "REVERSE")?,
            }
        }
        "clear-comp" => {
            count(1)?;
            Command::ClearJointComp {
                joint: num(a.first(), "JOINT")?,
            }
        }
        _ => return Err(ArgError(format!("unknown command '{name}'"))),
    };
    Ok(cmd)
}

/// An axis: its letter (either case) or its number. Numbers out of range
/// pass through, for the controller to refuse.
pub fn axis(s: Option<&String>) -> Result<i32, ArgError> {
    let s = s.ok_or_else(|| ArgError("missing AXIS".into()))?;
    let mut chars = s.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        let c = c.to_ascii_lowercase();
        if let Some(i) = AXIS_LETTERS.iter().position(|&l| l == c) {
            return Ok(i as i32);
        }
    }
    s.parse().map_err(|_| {
        ArgError(format!(
            "AXIS must be one of x y z a b c u v w or a number, not '{s}'"
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn moves_keep_the_axes_left_out() {
        let mut goal = Pose::ZERO;
        goal.0[2] = 5.0;
        let c = parse("line", &args("3 12.5 X=1 y=-2"), goal).unwrap();
        let mut end = goal;
        end.0[0] = 1.0;
        end.0[1] = -2.0;
        assert_eq!(
            c,
            Command::Line {
                end,
                vel: 12.5,
                kind: LineKind::Feed,
                id: 3
            }
        );
        let c = parse("arc", &args("4 2 X=1 center=0.5,0,5 turns=-1"), goal).unwrap();
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
            parse("term-cond", &args("blend 0.02"), goal).unwrap(),
            Command::SetTermCond {
                cond: TermCond::Blend,
                tolerance: 0.02
            }
        );
        assert!(matches!(
            parse("probe", &args("1 2 G38.3 Z=-1"), goal).unwrap(),
            Command::Probe {
                probe: ProbeType::G38_3,
                ..
            }
        ));
    }

    #[test]
    fn bad_words_say_what() {
        let g = Pose::ZERO;
        assert_eq!(
            parse("line", &args("1 5 X=1 X=2"), g).unwrap_err().0,
            "axis X given twice"
        );
        assert!(parse("line", &args("1 5 Q=1"), g)
            .unwrap_err()
            .0
            .starts_with("unknown word 'Q'"));
        assert_eq!(
            parse("arc", &args("1 5 X=1"), g).unwrap_err().0,
            "'arc' needs center=X,Y,Z"
        );
        assert_eq!(
            parse("probe", &args("1 5 G38.9"), g).unwrap_err().0,
            "probe TYPE must be G38.2, G38.3, G38.4 or G38.5, not 'G38.9'"
        );
        assert_eq!(
            parse("dwell", &args("1"), g).unwrap_err().0,
            "'dwell' takes 2 argument(s), 1 given"
        );
        assert!(parse("line", &args("x 5"), g).is_err());
    }
}
