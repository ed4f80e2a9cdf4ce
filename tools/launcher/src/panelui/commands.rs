//! The built-in commands a panelui button may name in `TRUE_COMMAND` or
//! `FALSE_COMMAND` (`NAME, ARGUMENT` or `NAME, ARG1, ARG2...`), with
//! LinuxCNC's names (compared without case), read and checked when the
//! panel file is read: an unknown name or an argument of the wrong kind
//! stops panelui at start, not when the button is pressed.

/// A command with its arguments read.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `mist_on`, `mist_off`.
    Mist(bool),
    /// `flood_on`, `flood_off`.
    Flood(bool),
    /// `estop`.
    Estop,
    /// `estop_reset`.
    EstopReset,
    /// `machine_on`.
    MachineOn,
    /// `machine_off`.
    MachineOff,
    /// `home_all`: MANUAL mode, every joint.
    HomeAll,
    /// `unhome_all`.
    UnhomeAll,
    /// `home_selected, JOINT`.
    Home(i32),
    /// `unhome_selected, JOINT`.
    Unhome(i32),
    /// `jogging`: MANUAL mode.
    Jogging,
    /// `override_limits`: MANUAL mode, then the joints' hard limits are
    /// overridden until the next jog ends.
    OverrideLimits,
    /// `spindle_forward_adjust, RPM`: start forward if stopped, else
    /// faster when turning forward and slower when turning in reverse.
    SpindleForwardAdjust(f64),
    /// `spindle_reverse_adjust, RPM`: the mirror of the above.
    SpindleReverseAdjust(f64),
    /// `spindle_forward, RPM`: MANUAL mode; start forward if stopped.
    SpindleForward(f64),
    /// `spindle_reverse, RPM`.
    SpindleReverse(f64),
    /// `spindle_stop`.
    SpindleStop,
    /// `spindle_faster`.
    SpindleFaster,
    /// `spindle_slower`.
    SpindleSlower,
    /// `set_linear_jog_velocity, UNITS_PER_MINUTE`: the speed of the
    /// linear continuous jogs (X Y Z U V W), also of those running.
    LinearJogVelocity(f64),
    /// `set_angular_jog_velocity, DEGREES_PER_MINUTE` (A B C).
    AngularJogVelocity(f64),
    /// `continuous_jog, AXIS, DIRECTION`: AXIS 0..8 (X Y Z A B C U V W),
    /// DIRECTION 1, -1, or 0 to stop.
    ContinuousJog {
        /// The axis number.
        axis: usize,
        /// 1, -1 or 0.
        direction: i32,
    },
    /// `incremental_jog, AXIS, DIRECTION, DISTANCE`.
    IncrementalJog {
        /// The axis number.
        axis: usize,
        /// 1 or -1 (0 moves nothing).
        direction: i32,
        /// The distance.
        distance: f64,
    },
    /// `quill_up, Z`: `G53 G0 Z` in MDI mode.
    QuillUp(f64),
    /// `feed_hold, 0|1`: whether `motion.feed-hold` applies.
    FeedHold(bool),
    /// `feed_override, SCALE`.
    FeedOverride(f64),
    /// `rapid_override, SCALE`.
    RapidOverride(f64),
    /// `spindle_override, SCALE`.
    SpindleOverride(f64),
    /// `max_velocity, VEL` (units per second).
    MaxVelocity(f64),
    /// `reload_tooltable`.
    ReloadToolTable,
    /// `optional_stop, 0|1`.
    OptionalStop(bool),
    /// `block_delete, 0|1`.
    BlockDelete(bool),
    /// `abort`.
    Abort,
    /// `pause`.
    Pause,
    /// `resume`.
    Resume,
    /// `single_block, 0|1`: while a program runs or is paused, pause
    /// (1) or resume (0).
    SingleBlock(bool),
    /// `smart_cycle_start`: AUTO mode; step when paused, else run from
    /// the restart line when idle.
    SmartCycleStart,
    /// `re_start, LINE`: AUTO mode and run from LINE.
    Restart(i32),
    /// `set_restart_line, LINE`: the line the next cycle start runs from.
    SetRestartLine(i32),
    /// `mdi, LINE...`: MDI mode and the lines.
    Mdi(Vec<String>),
    /// `mdi_and_return, LINE...`: the same when the machine is on and
    /// idle, then back to the mode before once they ran.
    MdiAndReturn(Vec<String>),
    /// `mdi_active, VALUE`: LinuxCNC keeps the value and nothing reads
    /// it; accepted so its panels read, and it does nothing.
    MdiActive,
    /// A function of the configuration's `panelui_handler.py`: Python,
    /// which this panelui does not run (it says so when pressed).
    Handler(String),
}

/// The names of the built-in commands, as LinuxCNC spells them.
pub const NAMES: &[&str] = &[
    "mist_on",
    "mist_off",
    "flood_on",
    "flood_off",
    "estop",
    "estop_reset",
    "machine_on",
    "machine_off",
    "home_all",
    "unhome_all",
    "home_selected",
    "unhome_selected",
    "jogging",
    "override_limits",
    "spindle_forward_adjust",
    "spindle_reverse_adjust",
    "spindle_forward",
    "spindle_reverse",
    "spindle_stop",
    "spindle_faster",
    "spindle_slower",
    "set_linear_jog_velocity",
    "set_angular_jog_velocity",
    "continuous_jog",
    "incremental_jog",
    "quill_up",
    "feed_hold",
    "feed_override",
    "rapid_override",
    "spindle_override",
    "max_velocity",
    "reload_tooltable",
    "optional_stop",
    "block_delete",
    "abort",
    "pause",
    "resume",
    "single_block",
    "smart_cycle_start",
    "re_start",
    "set_restart_line",
    "mdi",
    "mdi_and_return",
    "mdi_active",
];

/// The RPM of a spindle command given no number (`NONE`), as LinuxCNC's.
const DEFAULT_RPM: f64 = 100.0;

/// Why a command value was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommandProblem {
    /// A name that is neither a command nor a handler function.
    #[error("unknown command {name:?} (panelui's commands: {known}{handlers})")]
    Unknown {
        /// The name as written.
        name: String,
        /// panelui's command names, comma-separated.
        known: String,
        /// `; panelui_handler.py defines: ...`, or nothing.
        handlers: String,
    },
    /// A command's argument is wrong.
    #[error("{command}: {problem}")]
    Argument {
        /// The command as written.
        command: String,
        /// What is wrong with its argument.
        problem: ArgProblem,
    },
}

/// What is wrong with a command's argument.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ArgProblem {
    /// The argument is missing (or NONE).
    #[error("needs {0}")]
    Missing(&'static str),
    /// Not a finite number.
    #[error("{what} must be a number, not {text:?}")]
    NotANumber {
        /// What the argument is.
        what: &'static str,
        /// As written.
        text: String,
    },
    /// Not a whole number.
    #[error("{what} must be a whole number, not {text:?}")]
    NotAnInteger {
        /// What the argument is.
        what: &'static str,
        /// As written.
        text: String,
    },
    /// A number outside what the argument allows.
    #[error("{what} must be {allowed}, not {value}")]
    OutOfRange {
        /// What the argument is.
        what: &'static str,
        /// The values allowed.
        allowed: &'static str,
        /// The value given.
        value: f64,
    },
}

/// Reads a command value: `None` for `NONE`/`CLEAR` (no command), else
/// the command. `handlers` are the function names of the configuration's
/// handler file.
pub fn parse(items: &[&str], handlers: &[String]) -> Result<Option<Command>, CommandProblem> {
    let Some((name, args)) = items.split_first() else {
        return Ok(None);
    };
    let lower = name.to_ascii_lowercase();
    if lower == "none" || lower == "clear" || lower.is_empty() {
        return Ok(None);
    }
    let unknown = || CommandProblem::Unknown {
        name: name.to_string(),
        known: NAMES.join(", "),
        handlers: if handlers.is_empty() {
            String::new()
        } else {
            format!("; panelui_handler.py defines: {}", handlers.join(", "))
        },
    };
    if !NAMES.contains(&lower.as_str()) {
        if handlers.iter().any(|h| h.eq_ignore_ascii_case(name)) {
            return Ok(Some(Command::Handler(name.to_string())));
        }
        return Err(unknown());
    }
    match with_args(&lower, args) {
        Ok(Some(c)) => Ok(Some(c)),
        Ok(None) => Err(unknown()),
        Err(problem) => Err(CommandProblem::Argument {
            command: name.to_string(),
            problem,
        }),
    }
}

/// A value that stands for "no argument".
fn absent(a: Option<&&str>) -> bool {
    a.is_none_or(|a| a.eq_ignore_ascii_case("none") || a.is_empty())
}

fn number(a: Option<&&str>, what: &'static str) -> Result<f64, ArgProblem> {
    let Some(a) = a.filter(|_| !absent(a)) else {
        return Err(ArgProblem::Missing(what));
    };
    a.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ArgProblem::NotANumber {
            what,
            text: a.to_string(),
        })
}

fn integer(a: Option<&&str>, what: &'static str) -> Result<i32, ArgProblem> {
    let Some(a) = a.filter(|_| !absent(a)) else {
        return Err(ArgProblem::Missing(what));
    };
    a.parse::<i32>().map_err(|_| ArgProblem::NotAnInteger {
        what,
        text: a.to_string(),
    })
}

/// An integer that must lie in `range` (`allowed` says so in words).
fn ranged(
    a: Option<&&str>,
    what: &'static str,
    range: std::ops::RangeInclusive<i32>,
    allowed: &'static str,
) -> Result<i32, ArgProblem> {
    let n = integer(a, what)?;
    if range.contains(&n) {
        Ok(n)
    } else {
        Err(ArgProblem::OutOfRange {
            what,
            allowed,
            value: f64::from(n),
        })
    }
}

fn flag(a: Option<&&str>) -> Result<bool, ArgProblem> {
    Ok(ranged(a, "the flag", 0..=1, "0 or 1")? == 1)
}

fn rpm(a: Option<&&str>) -> Result<f64, ArgProblem> {
    if absent(a) {
        return Ok(DEFAULT_RPM);
    }
    non_negative(number(a, "the RPM")?, "the RPM")
}

fn axis(a: Option<&&str>) -> Result<usize, ArgProblem> {
    let n = ranged(a, "the axis number", 0..=8, "0..8 (X Y Z A B C U V W)")?;
    Ok(n as usize)
}

fn direction(a: Option<&&str>) -> Result<i32, ArgProblem> {
    ranged(a, "the direction", -1..=1, "1, -1 or 0")
}

fn lines(args: &[&str]) -> Result<Vec<String>, ArgProblem> {
    let v: Vec<String> = args
        .iter()
        .filter(|a| !absent(Some(a)))
        .map(|a| a.to_string())
        .collect();
    if v.is_empty() {
        return Err(ArgProblem::Missing("a line of G-code"));
    }
    Ok(v)
}

/// A non-negative number argument.
fn amount(a: Option<&&str>, what: &'static str) -> Result<f64, ArgProblem> {
    non_negative(number(a, what)?, what)
}

/// The command `name` (lower case) with its arguments; `None` for a name
/// that is no command.
fn with_args(name: &str, args: &[&str]) -> Result<Option<Command>, ArgProblem> {
    let a0 = args.first();
    let a1 = args.get(1);
    Ok(Some(match name {
        "mist_on" => Command::Mist(true),
        "mist_off" => Command::Mist(false),
        "flood_on" => Command::Flood(true),
        "flood_off" => Command::Flood(false),
        "estop" => Command::Estop,
        "estop_reset" => Command::EstopReset,
        "machine_on" => Command::MachineOn,
        "machine_off" => Command::MachineOff,
        "home_all" => Command::HomeAll,
        "unhome_all" => Command::UnhomeAll,
        "home_selected" => Command::Home(joint(a0)?),
        "unhome_selected" => Command::Unhome(joint(a0)?),
        "jogging" => Command::Jogging,
        "override_limits" => Command::OverrideLimits,
        "spindle_forward_adjust" => Command::SpindleForwardAdjust(rpm(a0)?),
        "spindle_reverse_adjust" => Command::SpindleReverseAdjust(rpm(a0)?),
        "spindle_forward" => Command::SpindleForward(rpm(a0)?),
        "spindle_reverse" => Command::SpindleReverse(rpm(a0)?),
        "spindle_stop" => Command::SpindleStop,
        "spindle_faster" => Command::SpindleFaster,
        "spindle_slower" => Command::SpindleSlower,
        "set_linear_jog_velocity" => Command::LinearJogVelocity(amount(a0, "the speed")?),
        "set_angular_jog_velocity" => Command::AngularJogVelocity(amount(a0, "the speed")?),
        "continuous_jog" => Command::ContinuousJog {
            axis: axis(a0)?,
            direction: direction(a1)?,
        },
        "incremental_jog" => Command::IncrementalJog {
            axis: axis(a0)?,
            direction: direction(a1)?,
            distance: amount(args.get(2), "the distance")?,
        },
        "quill_up" => Command::QuillUp(number(a0, "the Z position")?),
        "feed_hold" => Command::FeedHold(flag(a0)?),
        "feed_override" => Command::FeedOverride(amount(a0, "the scale")?),
        "rapid_override" => Command::RapidOverride(amount(a0, "the scale")?),
        "spindle_override" => Command::SpindleOverride(amount(a0, "the scale")?),
        "max_velocity" => Command::MaxVelocity(amount(a0, "the speed")?),
        "reload_tooltable" => Command::ReloadToolTable,
        "optional_stop" => Command::OptionalStop(flag(a0)?),
        "block_delete" => Command::BlockDelete(flag(a0)?),
        "abort" => Command::Abort,
        "pause" => Command::Pause,
        "resume" => Command::Resume,
        "single_block" => Command::SingleBlock(flag(a0)?),
        "smart_cycle_start" => Command::SmartCycleStart,
        "re_start" => Command::Restart(line_number(a0)?),
        "set_restart_line" => Command::SetRestartLine(line_number(a0)?),
        "mdi" => Command::Mdi(lines(args)?),
        "mdi_and_return" => Command::MdiAndReturn(lines(args)?),
        "mdi_active" => Command::MdiActive,
        _ => return Ok(None),
    }))
}

fn joint(a: Option<&&str>) -> Result<i32, ArgProblem> {
    ranged(a, "the joint number", 0..=15, "0..15")
}

fn line_number(a: Option<&&str>) -> Result<i32, ArgProblem> {
    ranged(a, "the line number", 0..=i32::MAX, "0 or more")
}

fn non_negative(x: f64, what: &'static str) -> Result<f64, ArgProblem> {
    if x < 0.0 {
        Err(ArgProblem::OutOfRange {
            what,
            allowed: "0 or more",
            value: x,
        })
    } else {
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(items: &[&str]) -> Result<Option<Command>, CommandProblem> {
        parse(items, &["hello_world".to_string()])
    }

    #[test]
    fn names_are_read_without_case_and_none_is_no_command() {
        assert_eq!(p(&["NONE", "NONE"]).unwrap(), None);
        assert_eq!(p(&["none"]).unwrap(), None);
        assert_eq!(
            p(&["ESTOP_reset", "NONE"]).unwrap(),
            Some(Command::EstopReset)
        );
        assert_eq!(
            p(&["SPINDLE_FORWARD_ADJUST", "200"]).unwrap(),
            Some(Command::SpindleForwardAdjust(200.0))
        );
        assert_eq!(
            p(&["spindle_forward", "NONE"]).unwrap(),
            Some(Command::SpindleForward(100.0))
        );
        assert_eq!(
            p(&["continuous_jog", "2", "-1"]).unwrap(),
            Some(Command::ContinuousJog {
                axis: 2,
                direction: -1
            })
        );
        assert_eq!(
            p(&["mdi", "g53 g0 z0", "g53 g0 x2"]).unwrap(),
            Some(Command::Mdi(vec!["g53 g0 z0".into(), "g53 g0 x2".into()]))
        );
        assert_eq!(
            p(&["Hello_World", "1", "2"]).unwrap(),
            Some(Command::Handler("Hello_World".into()))
        );
    }

    #[test]
    fn unknown_names_and_bad_arguments_are_refused() {
        let e = p(&["spindle_sideways", "1"]).unwrap_err().to_string();
        assert!(e.contains("unknown command \"spindle_sideways\""), "{e}");
        assert!(e.contains("hello_world"), "{e}");
        let cases = [
            (&["feed_hold", "2"][..], "the flag must be 0 or 1, not 2"),
            (
                &["continuous_jog", "9", "1"][..],
                "axis number must be 0..8",
            ),
            (&["continuous_jog", "0", "2"][..], "direction must be"),
            (&["continuous_jog", "0"][..], "needs the direction"),
            (&["set_linear_jog_velocity", "fast"][..], "must be a number"),
            (&["home_selected", "NONE"][..], "needs the joint number"),
            (&["mdi", "NONE"][..], "needs a line of G-code"),
            (&["feed_override", "-1"][..], "must be 0 or more, not -1"),
        ];
        for (items, why) in cases {
            let e = p(items).unwrap_err().to_string();
            assert!(e.contains(why), "{items:?}: {e}");
        }
    }
}
