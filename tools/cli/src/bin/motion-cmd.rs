//! `motion-cmd`: send commands to the motion controller (`motmod`) of a
//! running HAL instance through its shared-memory command channel, and
//! show its status. Exit status: 0 accepted, 1 rejected, 2 usage or
//! connection error.

use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hal_tools::motion_queue_args;
use hal_tools::tool_args::motion_cmd::Cli;
use motion::comp_file::{read_comp_file, CompFileType};
use motion::homing::{HomeFlags, HomingConfig};
use motion::kins::Pose;
use motion::{Command, MotionClient};

/// A usage error, printed with a hint to --help.
struct Usage(String);

fn int(s: Option<&String>, what: &str) -> Result<i32, Usage> {
    let s = s.ok_or_else(|| Usage(format!("missing {what}")))?;
    s.parse()
        .map_err(|_| Usage(format!("{what} must be an integer, not '{s}'")))
}

fn float(s: Option<&String>, what: &str) -> Result<f64, Usage> {
    let s = s.ok_or_else(|| Usage(format!("missing {what}")))?;
    s.parse()
        .map_err(|_| Usage(format!("{what} must be a number, not '{s}'")))
}

/// An INI-style yes/no value.
fn yes_no(key: &str, v: &str) -> Result<bool, Usage> {
    match v.to_ascii_uppercase().as_str() {
        "YES" | "TRUE" | "1" => Ok(true),
        "NO" | "FALSE" | "0" => Ok(false),
        _ => Err(Usage(format!("{key} must be YES or NO, not '{v}'"))),
    }
}

/// `set-homing-params JOINT KEY=VALUE...`, with the INI defaults for the
/// keys left out.
fn homing_params(a: &[String]) -> Result<Command, Usage> {
    let joint = int(a.first(), "JOINT")?;
    let mut config = HomingConfig {
        final_vel: -1.0,
        sequence: 999,
        ..HomingConfig::default()
    };
    for arg in &a[1..] {
        let (key, v) = arg
            .split_once('=')
            .ok_or_else(|| Usage(format!("'{arg}' is not KEY=VALUE")))?;
        let key = key.to_ascii_uppercase();
        let num = || {
            v.parse::<f64>()
                .map_err(|_| Usage(format!("{key} must be a number, not '{v}'")))
        };
        let flags = &mut config.flags;
        match key.as_str() {
            "HOME_OFFSET" => config.offset = num()?,
            "HOME" => config.home = num()?,
            "HOME_SEARCH_VEL" => config.search_vel = num()?,
            "HOME_LATCH_VEL" => config.latch_vel = num()?,
            "HOME_FINAL_VEL" => config.final_vel = num()?,
            "HOME_SEQUENCE" => {
                config.sequence = v
                    .parse()
                    .map_err(|_| Usage(format!("HOME_SEQUENCE must be an integer, not '{v}'")))?
            }
            "VOLATILE_HOME" => config.volatile_home = yes_no(&key, v)?,
            "HOME_USE_INDEX" => flags.set(HomeFlags::USE_INDEX, yes_no(&key, v)?),
            "HOME_INDEX_NO_ENCODER_RESET" => {
                flags.set(HomeFlags::INDEX_NO_ENCODER_RESET, yes_no(&key, v)?)
            }
            "HOME_IGNORE_LIMITS" => flags.set(HomeFlags::IGNORE_LIMITS, yes_no(&key, v)?),
            "HOME_IS_SHARED" => flags.set(HomeFlags::IS_SHARED, yes_no(&key, v)?),
            "LOCKING_INDEXER" => flags.set(HomeFlags::UNLOCK_FIRST, yes_no(&key, v)?),
            "HOME_ABSOLUTE_ENCODER" => {
                let (abs, no_final) = match v {
                    "0" => (false, false),
                    "1" => (true, false),
                    "2" => (true, true),
                    _ => {
                        return Err(Usage(format!(
                            "HOME_ABSOLUTE_ENCODER must be 0, 1 or 2, not '{v}'"
                        )))
                    }
                };
                flags.set(HomeFlags::ABSOLUTE_ENCODER | HomeFlags::NO_REHOME, abs);
                flags.set(HomeFlags::NO_FINAL_MOVE, no_final);
            }
            _ => return Err(Usage(format!("unknown homing key '{key}'"))),
        }
    }
    Ok(Command::SetJointHomingParams { joint, config })
}

/// A status condition `wait` waits for.
#[derive(Debug, Clone, Copy)]
enum Condition {
    Enabled,
    Disabled,
    InPosition,
    HomingDone,
    AllHomed,
    Homed(usize),
    QueueDone,
    Paused,
}

impl Condition {
    fn parse(a: &[String]) -> Result<Condition, Usage> {
        let name = a
            .first()
            .ok_or_else(|| Usage("'wait' needs a condition".into()))?;
        let (c, n) = match name.as_str() {
            "enabled" => (Condition::Enabled, 1),
            "disabled" => (Condition::Disabled, 1),
            "in-position" => (Condition::InPosition, 1),
            "homing-done" => (Condition::HomingDone, 1),
            "all-homed" => (Condition::AllHomed, 1),
            "queue-done" => (Condition::QueueDone, 1),
            "paused" => (Condition::Paused, 1),
            "homed" => {
                let j = int(a.get(1), "JOINT")?;
                let j = usize::try_from(j)
                    .map_err(|_| Usage(format!("JOINT must not be negative, not {j}")))?;
                (Condition::Homed(j), 2)
            }
            o => return Err(Usage(format!("unknown wait condition '{o}'"))),
        };
        if a.len() != n {
            return Err(Usage(format!("'wait {name}' takes {} argument(s)", n - 1)));
        }
        Ok(c)
    }

    /// Whether the condition holds; `Err` when it never can.
    fn holds(self, s: &motion::MotionStatus) -> Result<bool, String> {
        Ok(match self {
            Condition::Enabled => s.enabled,
            Condition::Disabled => !s.enabled,
            Condition::InPosition => s.in_position,
            Condition::HomingDone => !s.homing_active,
            Condition::AllHomed => s.all_homed,
            Condition::QueueDone => s.traj.depth == 0 && s.in_position,
            Condition::Paused => s.traj.paused && s.traj.current_vel == 0.0,
            Condition::Homed(j) => {
                s.joints
                    .get(j)
                    .ok_or_else(|| {
                        format!("joint {j} does not exist (there are {})", s.joints.len())
                    })?
                    .homed
            }
        })
    }
}

/// Polls the status until `cond` holds in a snapshot taken at least two
/// servo cycles after the start, or `limit` passes.
fn wait_for(client: &MotionClient, cond: Condition, limit: Duration) -> ExitCode {
    let start = std::time::Instant::now();
    let mut first_beat = None;
    loop {
        let s = match client.status() {
            Ok(s) => s,
            Err(e) => {
                eprintln!("motion-cmd: {e}");
                return ExitCode::from(2);
            }
        };
        let beat0 = *first_beat.get_or_insert(s.heartbeat);
        if s.heartbeat.wrapping_sub(beat0) >= 2 {
            match cond.holds(&s) {
                Ok(true) => return ExitCode::SUCCESS,
                Ok(false) => {}
                Err(e) => {
                    eprintln!("motion-cmd: {e}");
                    return ExitCode::from(2);
                }
            }
        }
        if start.elapsed() >= limit {
            hal_tools::outln!(
                "timed out after {:.1} s waiting for {cond:?}",
                limit.as_secs_f64()
            );
            hal_tools::out!("{s}");
            return ExitCode::from(1);
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// An axis: its letter (either case) or its number.
fn axis(s: Option<&String>) -> Result<i32, Usage> {
    motion_queue_args::axis(s).map_err(|e| Usage(e.0))
}

/// Parses a command and its arguments.
fn parse_command(name: &str, a: &[String]) -> Result<Command, Usage> {
    if name == "set-homing-params" {
        return homing_params(a);
    }
    // Each argument read marks how many the command takes, so the count
    // check below cannot disagree with the parsing.
    let takes = std::cell::Cell::new(0usize);
    let arg = |i: usize| {
        takes.set(takes.get().max(i + 1));
        a.get(i)
    };
    let j = || int(arg(0), "JOINT");
    let f = |i: usize, what: &str| float(arg(i), what);
    let ax = || axis(arg(0));
    let cmd = match name {
        "enable" => Command::Enable,
        "disable" => Command::Disable,
        "abort" => Command::Abort,
        "free" => Command::Free,
        "teleop" => Command::Teleop,
        "coord" => Command::Coord,
        "scale" => Command::Scale {
            scale: f(0, "VALUE")?,
        },
        "override-limits" => Command::OverrideLimits { joint: j()? },
        "activate" => Command::JointActivate { joint: j()? },
        "deactivate" => Command::JointDeactivate { joint: j()? },
        "amp-enable" => Command::EnableAmplifier { joint: j()? },
        "amp-disable" => Command::DisableAmplifier { joint: j()? },
        "jog-cont" => Command::JogCont {
            joint: j()?,
            vel: f(1, "VEL")?,
        },
        "jog-incr" => Command::JogIncr {
            joint: j()?,
            vel: f(1, "VEL")?,
            offset: f(2, "DISTANCE")?,
        },
        "jog-abs" => Command::JogAbs {
            joint: j()?,
            vel: f(1, "VEL")?,
            pos: f(2, "POSITION")?,
        },
        "jog-abort" => Command::JogAbort { joint: j()? },
        "set-limits" => Command::SetJointPositionLimits {
            joint: j()?,
            min: f(1, "MIN")?,
            max: f(2, "MAX")?,
        },
        "set-vel-limit" => Command::SetJointVelLimit {
            joint: j()?,
            vel: f(1, "VEL")?,
        },
        "set-acc-limit" => Command::SetJointAccLimit {
            joint: j()?,
            acc: f(1, "ACC")?,
        },
        "set-min-ferror" => Command::SetJointMinFerror {
            joint: j()?,
            ferror: f(1, "VALUE")?,
        },
        "set-max-ferror" => Command::SetJointMaxFerror {
            joint: j()?,
            ferror: f(1, "VALUE")?,
        },
        "set-backlash" => Command::SetJointBacklash {
            joint: j()?,
            backlash: f(1, "VALUE")?,
        },
        "set-motor-offset" => Command::SetJointMotorOffset {
            joint: j()?,
            offset: f(1, "VALUE")?,
        },
        "axis-jog-cont" => Command::AxisJogCont {
            axis: ax()?,
            vel: f(1, "VEL")?,
        },
        "axis-jog-incr" => Command::AxisJogIncr {
            axis: ax()?,
            vel: f(1, "VEL")?,
            offset: f(2, "DIST")?,
        },
        "axis-jog-abs" => Command::AxisJogAbs {
            axis: ax()?,
            vel: f(1, "VEL")?,
            pos: f(2, "POS")?,
        },
        "axis-jog-abort" => Command::AxisJogAbort { axis: ax()? },
        "set-axis-limits" => Command::SetAxisPositionLimits {
            axis: ax()?,
            min: f(1, "MIN")?,
            max: f(2, "MAX")?,
        },
        "set-axis-vel-limit" => Command::SetAxisVelLimit {
            axis: ax()?,
            vel: f(1, "VEL")?,
        },
        "set-axis-acc-limit" => Command::SetAxisAccLimit {
            axis: ax()?,
            acc: f(1, "ACC")?,
        },
        "set-world-home" => {
            let mut pose = Pose::ZERO;
            for (i, v) in pose.0.iter_mut().enumerate() {
                *v = f(i, "coordinate")?;
            }
            Command::SetWorldHome { pose }
        }
        "home" => Command::Home { joint: j()? },
        "unhome" => Command::Unhome { joint: j()? },
        "update-homing-params" => Command::UpdateJointHomingParams {
            joint: j()?,
            offset: f(1, "OFFSET")?,
            home: f(2, "HOME")?,
            sequence: int(arg(3), "SEQUENCE")?,
        },
        _ => return Err(Usage(format!("unknown command '{name}'"))),
    };
    let n = takes.get();
    if a.len() != n {
        return Err(Usage(format!(
            "'{name}' takes {n} argument(s), {} given",
            a.len()
        )));
    }
    Ok(cmd)
}

fn run(cli: Cli) -> Result<ExitCode, Usage> {
    let instance = cli.instance.unwrap_or_else(hal_core::instance_from_env);
    // A year at most: far beyond any wait, and an Instant that far ahead
    // still exists.
    let timeout = match &cli.timeout {
        Some(text) => Some(
            hal_tools::stdio::parse_seconds("--timeout", text, 365.0 * 86_400.0)
                .map_err(|e| Usage(e.to_string()))?,
        ),
        None => None,
    };
    let Some((name, rest)) = cli.command.split_first() else {
        return Err(Usage("no command given".into()));
    };
    // Parse before connecting, so usage errors need no running instance.
    enum Action {
        Status,
        Watch {
            ms: u64,
            count: Option<u64>,
        },
        Send(Command),
        Wait(Condition),
        /// A queueing command: parsed again once the goal is known.
        Queue(String),
        LoadComp {
            joint: i32,
            entries: Vec<Command>,
        },
    }
    let action = match name.as_str() {
        "status" if rest.is_empty() => Action::Status,
        "status" => return Err(Usage("'status' takes no argument".into())),
        "watch" => {
            let (mut ms, mut count) = (200, None);
            let mut k = 0;
            while k < rest.len() {
                let v = rest.get(k + 1);
                let n = |v: Option<&String>, what: &str| -> Result<u64, Usage> {
                    v.and_then(|s| s.parse().ok())
                        .ok_or_else(|| Usage(format!("{what} needs a whole number")))
                };
                match rest[k].as_str() {
                    "-n" | "--interval" => ms = n(v, "--interval")?.max(1),
                    "-c" | "--count" => count = Some(n(v, "--count")?),
                    o => return Err(Usage(format!("unknown watch option '{o}'"))),
                }
                k += 2;
            }
            Action::Watch { ms, count }
        }
        "wait" => Action::Wait(Condition::parse(rest)?),
        "load-comp" => {
            if rest.len() != 3 {
                return Err(Usage("'load-comp' takes JOINT FILE TYPE".into()));
            }
            let joint = int(rest.first(), "JOINT")?;
            let kind = CompFileType::from_ini(&rest[2]).map_err(|e| Usage(e.to_string()))?;
            match read_comp_file(std::path::Path::new(&rest[1]), kind) {
                Ok(entries) => Action::LoadComp {
                    joint,
                    entries: entries
                        .into_iter()
                        .map(|e| Command::SetJointComp {
                            joint,
                            nominal: e.nominal,
                            forward: e.forward,
                            reverse: e.reverse,
                        })
                        .collect(),
                },
                Err(e) => {
                    eprintln!("motion-cmd: {e}");
                    return Ok(ExitCode::from(2));
                }
            }
        }
        q if motion_queue_args::is_queue_command(q) => {
            // Check the words now, so usage errors need no instance.
            motion_queue_args::parse(q, rest, motion::Pose::ZERO).map_err(|e| Usage(e.0))?;
            Action::Queue(q.to_string())
        }
        _ => Action::Send(parse_command(name, rest)?),
    };
    let mut client = match MotionClient::attach(&instance) {
        Ok(c) => c.with_timeout(timeout.unwrap_or(Duration::from_secs(1))),
        Err(e) => {
            eprintln!("motion-cmd: instance '{instance}': {e}");
            return Ok(ExitCode::from(2));
        }
    };
    match action {
        Action::Wait(cond) => Ok(wait_for(
            &client,
            cond,
            timeout.unwrap_or(Duration::from_secs(60)),
        )),
        Action::Queue(q) => {
            let goal = match client.status() {
                Ok(s) => motion::Pose(s.traj.goal),
                Err(e) => {
                    eprintln!("motion-cmd: {e}");
                    return Ok(ExitCode::from(2));
                }
            };
            let cmd = motion_queue_args::parse(&q, rest, goal).map_err(|e| Usage(e.0))?;
            Ok(send(&mut client, cmd))
        }
        Action::LoadComp { joint, entries } => {
            let mut code = send(&mut client, Command::ClearJointComp { joint });
            for e in entries {
                if code != ExitCode::SUCCESS {
                    break;
                }
                code = send(&mut client, e);
            }
            Ok(code)
        }
        Action::Send(cmd) => Ok(send(&mut client, cmd)),
        Action::Status => match client.status() {
            Ok(s) => {
                hal_tools::out!("{s}");
                Ok(ExitCode::SUCCESS)
            }
            Err(e) => {
                eprintln!("motion-cmd: {e}");
                Ok(ExitCode::from(2))
            }
        },
        Action::Watch { ms, count } => {
            let mut n = 0u64;
            loop {
                match client.status() {
                    // Home the cursor and clear, then the snapshot.
                    Ok(s) => hal_tools::out!("\x1b[H\x1b[2J{s}"),
                    Err(e) => {
                        eprintln!("motion-cmd: {e}");
                        return Ok(ExitCode::from(2));
                    }
                }
                use std::io::Write;
                let _ = std::io::stdout().flush();
                n += 1;
                if count.is_some_and(|c| n >= c) {
                    return Ok(ExitCode::SUCCESS);
                }
                std::thread::sleep(Duration::from_millis(ms));
            }
        }
    }
}

/// Sends one command and prints its answer.
fn send(client: &mut MotionClient, cmd: Command) -> ExitCode {
    match client.send(cmd) {
        Ok(a) => {
            hal_tools::outln!("accepted (serial {})", a.serial);
            ExitCode::SUCCESS
        }
        Err(r) => {
            hal_tools::outln!("{r}");
            ExitCode::from(1)
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(c) => c,
        Err(Usage(m)) => {
            eprintln!("motion-cmd: {m} (see motion-cmd --help)");
            ExitCode::from(2)
        }
    }
}
