//! The status values `get` answers from task's snapshot, and the task
//! requests a `set` becomes.

use super::session::Session;
use super::stat::Snapshot;
use super::vocab::Sub;

/// The axes LinuxCNC's position replies list: X Y Z A B C.
const POSITION_AXES: usize = 6;

fn six(v: &[f64]) -> Vec<f64> {
    (0..POSITION_AXES)
        .map(|i| v.get(i).copied().unwrap_or(0.0))
        .collect()
}

/// `v` as `%f` numbers; one of them when `arg` picks an index (or an
/// axis letter), `None` for an index out of range.
fn pick(v: &[f64], arg: Option<&&str>) -> Option<String> {
    match arg {
        None => Some(
            v.iter()
                .map(|x| format!("{x:.6}"))
                .collect::<Vec<_>>()
                .join(" "),
        ),
        Some(w) => {
            let i = w.parse::<usize>().ok().or_else(|| {
                "XYZABCUVW"
                    .find(w.to_ascii_uppercase().as_str())
                    .filter(|_| w.len() == 1)
            })?;
            v.get(i).map(|x| format!("{x:.6}"))
        }
    }
}

/// The joints LinuxCNC's per-joint replies list: the configured ones,
/// and at least six.
fn listed_joints(s: &Snapshot) -> Option<usize> {
    Some(usize::try_from(s.int("joints")?).ok()?.max(POSITION_AXES))
}

/// Per-joint words (`OK`, `FAULT`, ...) for the joints asked about.
fn per_joint(s: &Snapshot, arg: Option<&&str>, f: impl Fn(usize) -> String) -> Option<String> {
    let joints = listed_joints(s)?;
    match arg {
        None => Some((0..joints).map(f).collect::<Vec<_>>().join(" ")),
        Some(w) => {
            let j = w.parse::<usize>().ok().filter(|j| *j < joints)?;
            Some(f(j))
        }
    }
}

fn on(b: bool) -> String {
    if b { "ON" } else { "OFF" }.to_string()
}

/// Linear units per millimetre as LinuxCNC names them.
fn linear_name(per_mm: f64) -> &'static str {
    let near = |a: f64, b: f64| (a - b).abs() < 1e-4;
    if near(per_mm, 1.0 / 25.4) {
        "INCH"
    } else if near(per_mm, 1.0) {
        "MM"
    } else if near(per_mm, 0.1) {
        "CM"
    } else {
        "CUSTOM"
    }
}

/// Angular units per degree as LinuxCNC names them.
fn angular_name(per_deg: f64) -> &'static str {
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    if near(per_deg, 1.0) {
        "DEG"
    } else if near(per_deg, std::f64::consts::PI / 180.0) {
        "RAD"
    } else if near(per_deg, 100.0 / 90.0) {
        "GRAD"
    } else {
        "CUSTOM"
    }
}

fn program_units(s: &Snapshot) -> &'static str {
    match s.int("program_units") {
        Some(1) => "INCH",
        Some(2) => "MM",
        Some(3) => "CM",
        _ => "NONE",
    }
}

/// The active G codes, feed and speed as LinuxCNC's `program_codes`.
fn program_codes(s: &Snapshot) -> String {
    let mut out: Vec<String> = s
        .nums("gcodes")
        .iter()
        .skip(1)
        .map(|g| *g as i32)
        .filter(|g| *g >= 0)
        .map(rs274ngc::g_text)
        .collect();
    let settings = s.nums("settings");
    out.push(format!("F{}", settings.get(1).copied().unwrap_or(0.0)));
    out.push(format!("S{}", settings.get(2).copied().unwrap_or(0.0)));
    out.join(" ")
}

/// Position minus the offsets: the program's coordinates.
fn relative(s: &Snapshot, pos: &str) -> Vec<f64> {
    let (p, a, b, t) = (
        s.nums(pos),
        s.nums("g5x_offset"),
        s.nums("g92_offset"),
        s.nums("tool_offset"),
    );
    (0..POSITION_AXES)
        .map(|i| {
            let at = |v: &[f64]| v.get(i).copied().unwrap_or(0.0);
            at(&p) - at(&a) - at(&b) - at(&t)
        })
        .collect()
}

/// The value text of a `get` answered from the snapshot `s`.
pub fn value(sub: Sub, args: &[&str], s: &Snapshot, session: &Session) -> Option<String> {
    let arg = args.first();
    Some(match sub {
        Sub::Estop => on(s.flag("estop")),
        Sub::Machine => on(s.int("task_state")? == 4),
        Sub::Mode => match s.int("task_mode")? {
            1 => "MANUAL",
            2 => "AUTO",
            _ => "MDI",
        }
        .to_string(),
        Sub::Mist => on(s.flag("mist")),
        Sub::Flood => on(s.flag("flood")),
        Sub::Lube => on(s.flag("lube")),
        Sub::LubeLevel => if s.flag("lube_level") { "OK" } else { "LOW" }.to_string(),
        Sub::Tool => s.int("tool_in_spindle")?.to_string(),
        Sub::ToolOffset => format!(
            "{:.6}",
            s.nums("tool_offset").get(2).copied().unwrap_or(0.0)
        ),
        Sub::AbsCmdPos => pick(&six(&s.nums("position")), arg)?,
        Sub::AbsActPos => pick(&six(&s.nums("actual_position")), arg)?,
        Sub::RelCmdPos => pick(&relative(s, "position"), arg)?,
        Sub::RelActPos => pick(&relative(s, "actual_position"), arg)?,
        Sub::PosOffset => {
            let (a, b) = (s.nums("g5x_offset"), s.nums("g92_offset"));
            let sum: Vec<f64> = (0..POSITION_AXES)
                .map(|i| a.get(i).copied().unwrap_or(0.0) + b.get(i).copied().unwrap_or(0.0))
                .collect();
            pick(&sum, arg)?
        }
        Sub::JointPos => {
            let joints = listed_joints(s)?;
            let mut v: Vec<f64> = s
                .nums("joint_actual_position")
                .into_iter()
                .take(joints)
                .collect();
            v.resize(joints, 0.0);
            pick(&v, arg)?
        }
        Sub::JointFault => per_joint(s, arg, |j| {
            if s.flag(&format!("joint.{j}.fault")) {
                "FAULT"
            } else {
                "OK"
            }
            .to_string()
        })?,
        Sub::JointHomed => per_joint(s, arg, |j| {
            let homed = s.nums("homed").get(j).is_some_and(|h| *h != 0.0);
            if homed { "HOMED" } else { "NOT" }.to_string()
        })?,
        Sub::JointLimit => per_joint(s, arg, |j| {
            let bits = s.nums("limit").get(j).copied().unwrap_or(0.0) as i64;
            match bits {
                b if b & 1 != 0 => "MINHARD",
                b if b & 2 != 0 => "MAXHARD",
                b if b & 4 != 0 => "MINSOFT",
                b if b & 8 != 0 => "MAXSOFT",
                _ => "OK",
            }
            .to_string()
        })?,
        Sub::JointType => per_joint(s, arg, |j| {
            let angular = session.joint_is_angular(j).unwrap_or(false);
            if angular { "ANGULAR" } else { "LINEAR" }.to_string()
        })?,
        // A joint that is not configured has units 1 (LinuxCNC's MM).
        Sub::JointUnits => {
            let linear = linear_name(s.num("linear_units")?);
            let angular = angular_name(s.num("angular_units")?);
            per_joint(s, arg, |j| {
                match session.joint_is_angular(j) {
                    Some(true) => angular,
                    Some(false) => linear,
                    None => "MM",
                }
                .to_string()
            })?
        }
        Sub::FeedOverride => format!("{}", (s.num("feedrate")? * 100.0).round() as i64),
        Sub::SpindleOverride => {
            format!("{}", (s.num("spindle.0.override")? * 100.0).round() as i64)
        }
        Sub::Program => match s.text("file")? {
            "" => "NONE".to_string(),
            f => f.to_string(),
        },
        Sub::ProgramLine => s
            .int("current_line")
            .or_else(|| s.int("read_line"))?
            .to_string(),
        Sub::ProgramStatus => match s.int("interp_state")? {
            1 => "IDLE",
            3 => "PAUSED",
            _ => "RUNNING",
        }
        .to_string(),
        Sub::ProgramCodes => program_codes(s),
        Sub::ProgramUnits | Sub::ProgramLinearUnits => program_units(s).to_string(),
        Sub::ProgramAngularUnits => "DEG".to_string(),
        Sub::UserLinearUnits => linear_name(s.num("linear_units")?).to_string(),
        Sub::UserAngularUnits => angular_name(s.num("angular_units")?).to_string(),
        Sub::DisplayLinearUnits => match session.linear_conversion() {
            "AUTO" => program_units(s).to_string(),
            other => other.to_string(),
        },
        Sub::DisplayAngularUnits => match session.angular_conversion() {
            "AUTO" => "DEG".to_string(),
            other => other.to_string(),
        },
        Sub::ProbeTripped => (s.flag("probe_tripped") as i32).to_string(),
        Sub::ProbeValue => s.int("probe_val").unwrap_or(0).to_string(),
        Sub::OptionalStop => (s.flag("optional_stop") as i32).to_string(),
        Sub::OverrideLimits => (s.flag("override_limits") as i32).to_string(),
        Sub::TeleopEnable => if s.int("motion_mode") == Some(3) {
            "YES"
        } else {
            "NO"
        }
        .to_string(),
        _ => return None,
    })
}

fn w(words: &[&str]) -> Vec<String> {
    words.iter().map(|s| (*s).to_string()).collect()
}

/// The task requests of a `set` (its arguments in `args`, the G-code of
/// `set mdi` in `mdi`); `None` for bad arguments or no such set.
pub fn requests(sub: Sub, args: &[&str], mdi: &str, wait_done: bool) -> Option<Vec<Vec<String>>> {
    let first = args.first().map(|a| a.to_ascii_lowercase());
    let flag = first.as_deref().and_then(|f| match f {
        "on" | "1" => Some("on"),
        "off" | "0" => Some("off"),
        _ => None,
    });
    let one = |v: Vec<String>| Some(vec![v]);
    match sub {
        Sub::Estop => one(w(&[if flag? == "on" {
            "estop"
        } else {
            "estop-reset"
        }])),
        Sub::Machine => one(w(&[if flag? == "on" {
            "machine-on"
        } else {
            "machine-off"
        }])),
        Sub::Mode => match first.as_deref()? {
            m @ ("manual" | "auto" | "mdi") => one(w(&["mode", m])),
            _ => None,
        },
        Sub::Mist => one(w(&["coolant", "mist", flag?])),
        Sub::Flood => one(w(&["coolant", "flood", flag?])),
        Sub::Lube => one(w(&["lube", flag?])),
        Sub::Home => {
            let j = args.first()?.parse::<i64>().ok().filter(|j| *j >= -1)?;
            let j = if j == -1 {
                "all".to_string()
            } else {
                j.to_string()
            };
            one(vec!["home".to_string(), j])
        }
        Sub::Jog => match args {
            [j, v] => one(w(&["jog-cont", j, v])),
            _ => None,
        },
        Sub::JogIncr => match args {
            [j, v, d] => one(w(&["jog-incr", j, v, d])),
            _ => None,
        },
        Sub::JogStop => match args {
            [j] => one(w(&["jog-stop", j])),
            _ => None,
        },
        Sub::FeedOverride | Sub::SpindleOverride => {
            let p = args
                .first()?
                .parse::<f64>()
                .ok()
                .filter(|p| p.is_finite() && *p >= 0.0)?;
            let scale = (p / 100.0).to_string();
            if sub == Sub::FeedOverride {
                one(vec!["feed-override".to_string(), scale])
            } else {
                one(vec!["spindle".into(), "0".into(), "override".into(), scale])
            }
        }
        Sub::Mdi if !mdi.is_empty() => {
            let mut r = vec![vec!["mdi".to_string(), mdi.to_string()]];
            if wait_done {
                r.push(w(&["wait-done"]));
            }
            Some(r)
        }
        Sub::TaskPlanInit => one(w(&["reset-interpreter"])),
        Sub::Open => match args {
            [f] => one(w(&["open", f])),
            _ => None,
        },
        Sub::Run => match args {
            [] => one(w(&["run"])),
            [n] if n.parse::<u32>().is_ok() => one(w(&["run", n])),
            _ => None,
        },
        Sub::ProbeClear => one(w(&["clear-probe"])),
        // LinuxCNC's is a mill-style entry: length and diameter, with X,
        // the angles and the orientation 0.
        Sub::ToolOffset => match args {
            [t, l, d] => one(w(&["tool-offset", t, l, "0", d, "0", "0", "0"])),
            _ => None,
        },
        Sub::Pause => one(w(&["pause"])),
        Sub::Resume => one(w(&["resume"])),
        Sub::Step => one(w(&["step"])),
        Sub::Abort => one(w(&["abort"])),
        Sub::OptionalStop => one(w(&["optional-stop", flag?])),
        Sub::TeleopEnable => one(w(&["teleop", flag?])),
        Sub::OverrideLimits => one(w(&["override-limits", flag?])),
        Sub::Wait => match first.as_deref()? {
            "done" => one(w(&["wait-done"])),
            "received" => Some(vec![]),
            _ => None,
        },
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_named_as_linuxcnc_names_them() {
        assert_eq!(linear_name(1.0 / 25.4), "INCH");
        assert_eq!(linear_name(1.0), "MM");
        assert_eq!(linear_name(0.5), "CUSTOM");
        assert_eq!(angular_name(1.0), "DEG");
    }

    #[test]
    fn positions_pick_an_index_or_a_letter() {
        let v = [1.0, 2.0, 3.0];
        assert_eq!(pick(&v, None).unwrap(), "1.000000 2.000000 3.000000");
        assert_eq!(pick(&v, Some(&"1")).unwrap(), "2.000000");
        assert_eq!(pick(&v, Some(&"z")).unwrap(), "3.000000");
        assert_eq!(pick(&v, Some(&"7")), None);
        assert_eq!(pick(&v, Some(&"xy")), None);
    }

    #[test]
    fn sets_become_task_requests() {
        assert_eq!(
            requests(Sub::Estop, &["off"], "", false).unwrap(),
            [w(&["estop-reset"])]
        );
        assert_eq!(
            requests(Sub::Home, &["-1"], "", false).unwrap(),
            [w(&["home", "all"])]
        );
        assert_eq!(
            requests(Sub::Mdi, &["g0", "x1"], "g0 x1", true).unwrap(),
            [w(&["mdi", "g0 x1"]), w(&["wait-done"])]
        );
        assert_eq!(requests(Sub::Mode, &["sideways"], "", false), None);
        assert_eq!(requests(Sub::Home, &["-2"], "", false), None);
        assert_eq!(requests(Sub::Plat, &[], "", false), None);
    }
}
