//! `motion-cmd`: send commands to the motion controller (`motmod`) of a
//! running HAL instance through its shared-memory command channel, and
//! show its status. Exit status: 0 accepted, 1 rejected, 2 usage or
//! connection error.

use std::io::Write;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hal_tools::tool_args::motion_cmd::Cli;
use hal_tools::{motion_queue_args, ToolsError};
use motion::comp_file::{read_comp_file, CompFileType};
use motion::kins::Pose;
use motion::{Command, MotionClient};

/// A usage error, printed with a hint to --help.
fn usage(message: impl Into<String>) -> ToolsError {
    ToolsError::usage(message)
}

fn int(s: Option<&String>, what: &str) -> Result<i32, ToolsError> {
    let s = s.ok_or_else(|| usage(format!("missing {what}")))?;
    s.parse()
        .map_err(|_| usage(format!("{what} must be an integer, not '{s}'")))
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
    fn parse(a: &[String]) -> Result<Condition, ToolsError> {
        let name = a.first().ok_or_else(|| usage("'wait' needs a condition"))?;
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
                    .map_err(|_| usage(format!("JOINT must not be negative, not {j}")))?;
                (Condition::Homed(j), 2)
            }
            o => return Err(usage(format!("unknown wait condition '{o}'"))),
        };
        if a.len() != n {
            return Err(usage(format!("'wait {name}' takes {} argument(s)", n - 1)));
        }
        Ok(c)
    }

    /// Whether the condition holds; `Err` when it never can.
    fn holds(self, s: &motion::MotionStatus) -> Result<bool, ToolsError> {
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
                    .ok_or(ToolsError::NoSuchJoint {
                        joint: j,
                        count: s.joints.len(),
                    })?
                    .homed
            }
        })
    }
}

/// Polls the status until `cond` holds in a snapshot taken at least two
/// servo cycles after the start (success), or `limit` passes (status 1).
fn wait_for(
    client: &MotionClient,
    cond: Condition,
    limit: Duration,
) -> Result<ExitCode, ToolsError> {
    let start = std::time::Instant::now();
    let mut first_beat = None;
    loop {
        let s = client.status()?;
        let beat0 = *first_beat.get_or_insert(s.heartbeat);
        if s.heartbeat.wrapping_sub(beat0) >= 2 && cond.holds(&s)? {
            return Ok(ExitCode::SUCCESS);
        }
        if start.elapsed() >= limit {
            hal_tools::outln!(
                "timed out after {:.1} s waiting for {cond:?}",
                limit.as_secs_f64()
            );
            hal_tools::out!("{s}");
            return Ok(ExitCode::from(1));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// What a command line asks for, parsed before connecting so usage
/// errors need no running instance.
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

/// Parses command `name` and its arguments `rest`.
fn parse_action(name: &str, rest: &[String]) -> Result<Action, ToolsError> {
    Ok(match name {
        "status" if rest.is_empty() => Action::Status,
        "status" => return Err(usage("'status' takes no argument")),
        "watch" => parse_watch(rest)?,
        "wait" => Action::Wait(Condition::parse(rest)?),
        "load-comp" => parse_load_comp(rest)?,
        q if motion_queue_args::is_queue_command(q) => {
            // Check the words now, so usage errors need no instance.
            motion_queue_args::parse(q, rest, Pose::ZERO).map_err(|e| usage(e.to_string()))?;
            Action::Queue(q.to_string())
        }
        _ => Action::Send(
            motion::command::parse(name, rest, Pose::ZERO).map_err(|e| usage(e.to_string()))?,
        ),
    })
}

/// `watch [-n MS] [-c COUNT]`.
fn parse_watch(rest: &[String]) -> Result<Action, ToolsError> {
    let (mut ms, mut count) = (200, None);
    let mut k = 0;
    while k < rest.len() {
        let v = rest.get(k + 1);
        let n = |v: Option<&String>, what: &str| -> Result<u64, ToolsError> {
            v.and_then(|s| s.parse().ok())
                .ok_or_else(|| usage(format!("{what} needs a whole number")))
        };
        match rest[k].as_str() {
            "-n" | "--interval" => ms = n(v, "--interval")?.max(1),
            "-c" | "--count" => count = Some(n(v, "--count")?),
            o => return Err(usage(format!("unknown watch option '{o}'"))),
        }
        k += 2;
    }
    Ok(Action::Watch { ms, count })
}

/// `load-comp JOINT FILE TYPE`: the file is read now, its entries sent
/// once connected.
fn parse_load_comp(rest: &[String]) -> Result<Action, ToolsError> {
    if rest.len() != 3 {
        return Err(usage("'load-comp' takes JOINT FILE TYPE"));
    }
    let joint = int(rest.first(), "JOINT")?;
    let kind = CompFileType::from_ini(&rest[2]).map_err(|e| usage(e.to_string()))?;
    let entries = read_comp_file(std::path::Path::new(&rest[1]), kind)?;
    Ok(Action::LoadComp {
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
    })
}

fn run(cli: Cli) -> Result<ExitCode, ToolsError> {
    let instance = cli.instance.unwrap_or_else(hal_core::instance_from_env);
    let quiet = cli.quiet;
    // A year at most: far beyond any wait, and an Instant that far ahead
    // still exists.
    let timeout = match &cli.timeout {
        Some(text) => Some(
            hal_tools::stdio::parse_seconds("--timeout", text, 365.0 * 86_400.0)
                .map_err(|e| usage(e.to_string()))?,
        ),
        None => None,
    };
    let Some((name, rest)) = cli.command.split_first() else {
        return Err(usage("no command given"));
    };
    // The command words may start with '-' (negative numbers) only after
    // the command: a first word that does is an option motion-cmd lacks.
    if name.starts_with('-') {
        return Err(usage(format!("unknown option '{name}'")));
    }
    let action = parse_action(name, rest)?;
    match &action {
        Action::Send(cmd) => hal_tools::task_gate::allow(&instance, Some(cmd))?,
        Action::Queue(_) | Action::LoadComp { .. } => hal_tools::task_gate::allow(&instance, None)?,
        Action::Status | Action::Watch { .. } | Action::Wait(_) => {}
    }
    let mut client = MotionClient::attach(&instance)
        .map_err(|source| ToolsError::MotionAttach { instance, source })?
        .with_timeout(timeout.unwrap_or(Duration::from_secs(1)));
    match action {
        Action::Wait(cond) => wait_for(&client, cond, timeout.unwrap_or(Duration::from_secs(60))),
        Action::Queue(q) => {
            let goal = Pose(client.status()?.traj.goal);
            let cmd = motion_queue_args::parse(&q, rest, goal).map_err(|e| usage(e.to_string()))?;
            Ok(send(&mut client, cmd, quiet))
        }
        Action::LoadComp { joint, entries } => {
            let mut code = send(&mut client, Command::ClearJointComp { joint }, quiet);
            for e in entries {
                if code != ExitCode::SUCCESS {
                    break;
                }
                code = send(&mut client, e, quiet);
            }
            Ok(code)
        }
        Action::Send(cmd) => Ok(send(&mut client, cmd, quiet)),
        Action::Status => {
            hal_tools::out!("{}", client.status()?);
            Ok(ExitCode::SUCCESS)
        }
        Action::Watch { ms, count } => watch(&client, ms, count),
    }
}

/// Redraws the status every `ms` milliseconds, `count` times or until
/// stopped.
fn watch(client: &MotionClient, ms: u64, count: Option<u64>) -> Result<ExitCode, ToolsError> {
    let mut n = 0u64;
    loop {
        // Home the cursor and clear, then the snapshot.
        hal_tools::out!("\x1b[H\x1b[2J{}", client.status()?);
        let _ = std::io::stdout().flush();
        n += 1;
        if count.is_some_and(|c| n >= c) {
            return Ok(ExitCode::SUCCESS);
        }
        std::thread::sleep(Duration::from_millis(ms));
    }
}

/// Sends one command and prints its answer.
fn send(client: &mut MotionClient, cmd: Command, quiet: bool) -> ExitCode {
    match client.send(cmd) {
        Ok(a) => {
            if !quiet {
                hal_tools::outln!("accepted (serial {})", a.serial);
            }
            ExitCode::SUCCESS
        }
        Err(r) => {
            hal_tools::outln!("{r}");
            if let Some(hint) = hint(&r.reason) {
                hal_tools::outln!("  {hint}");
            }
            ExitCode::from(1)
        }
    }
}

/// What to do instead, for refusals whose cause is a habit from elsewhere.
fn hint(reason: &motion::Reject) -> Option<&'static str> {
    match reason {
        motion::Reject::BadValue {
            what: motion::Quantity::JogIncrement,
            value,
        } if *value < 0.0 => Some(
            "an increment is a distance (0 or more); the direction is the sign of the \
             velocity: 'axis-jog-incr z -5 3' moves Z 3 down at 5 per second",
        ),
        _ => None,
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(c) => c,
        Err(ToolsError::Usage(m)) => {
            eprintln!("motion-cmd: {m} (see motion-cmd --help)");
            ExitCode::from(2)
        }
        Err(e) => {
            eprintln!("motion-cmd: {e}");
            ExitCode::from(2)
        }
    }
}
