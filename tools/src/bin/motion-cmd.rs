//! `motion-cmd`: send commands to the motion controller (`motmod`) of a
//! running HAL instance through its shared-memory command channel, and
//! show its status. Exit status: 0 accepted, 1 rejected, 2 usage or
//! connection error.

use std::process::ExitCode;
use std::time::Duration;

use hal_tools::motion_queue_args;
use motion::comp_file::{read_comp_file, CompFileType};
use motion::homing::{HomeFlags, HomingConfig};
use motion::kins::Pose;
use motion::{Command, MotionClient};

const HELP: &str = "\
usage: motion-cmd [-i INSTANCE] [-t SECONDS] COMMAND [ARGS...]

Sends one command to the motion controller of a running HAL instance and
prints whether it was accepted or rejected (with the reason).

options:
  -i, --instance NAME   HAL instance (default: $HAL_INSTANCE or 'default')
  -t, --timeout SECS    how long to wait for the answer (default 1)
  -h, --help            this text

status:
  status                print the status snapshot once
  watch [-n MS] [-c COUNT]
                        refresh the status every MS milliseconds (default
                        200), COUNT times (default: until interrupted)
  wait CONDITION        wait until CONDITION holds (exit 0) or --timeout
                        passes (default 60 s here; exit 1, status shown).
                        Only snapshots from two servo cycles after the
                        start count, so a command just sent has taken
                        effect. CONDITION: enabled, disabled, in-position,
                        homing-done, all-homed, homed JOINT

machine:
  enable | disable | abort
  free | teleop | coord         mode requests
  scale VALUE                   jog speed scale, 0..1
  override-limits JOINT         override tripped hard limits until the end
                                of the next jog (JOINT -1: end the override)

joints:
  activate JOINT | deactivate JOINT
  amp-enable JOINT | amp-disable JOINT
  jog-cont JOINT VEL            jog until jog-abort (sign of VEL = direction)
  jog-incr JOINT VEL DISTANCE   jog DISTANCE (>= 0) in the direction of VEL
  jog-abs JOINT VEL POSITION    jog to POSITION at speed |VEL|
  jog-abort JOINT               stop the jog of JOINT
  home JOINT                    home JOINT (its group if its HOME_SEQUENCE
                                is negative); JOINT -1: home all joints in
                                HOME_SEQUENCE order
  unhome JOINT                  forget the home of JOINT; -1 every joint,
                                -2 the VOLATILE_HOME joints

axes (teleop mode):
  AXIS is a letter x y z a b c u v w, or its number 0..8
  axis-jog-cont AXIS VEL        jog until axis-jog-abort (sign of VEL =
                                direction), at most to the axis limit
  axis-jog-incr AXIS VEL DIST   jog DIST (>= 0) in the direction of VEL
  axis-jog-abs AXIS VEL POS     jog to POS (clamped into the axis limits)
                                at speed |VEL|
  axis-jog-abort AXIS           stop the jog of AXIS
  set-axis-limits AXIS MIN MAX  axis position limits
  set-axis-vel-limit AXIS VEL   axis maximum velocity
  set-axis-acc-limit AXIS ACC   axis maximum acceleration

configuration:
  set-limits JOINT MIN MAX      soft position limits
  set-vel-limit JOINT VEL       maximum velocity
  set-acc-limit JOINT ACC       maximum acceleration
  set-min-ferror JOINT VALUE    following-error limit at standstill
  set-max-ferror JOINT VALUE    following-error limit at maximum velocity
  set-backlash JOINT VALUE      backlash
  set-motor-offset JOINT VALUE  homing offset (motor = joint + offset)
  set-world-home X Y Z A B C U V W
                                world home pose
  set-homing-params JOINT [KEY=VALUE...]
                                the joint's whole homing configuration, with
                                the [JOINT_n] INI keys HOME_OFFSET, HOME,
                                HOME_SEARCH_VEL, HOME_LATCH_VEL,
                                HOME_FINAL_VEL, HOME_SEQUENCE, HOME_USE_INDEX,
                                HOME_INDEX_NO_ENCODER_RESET,
                                HOME_IGNORE_LIMITS, HOME_IS_SHARED,
                                HOME_ABSOLUTE_ENCODER (0, 1, 2),
                                VOLATILE_HOME and LOCKING_INDEXER; keys left
                                out take the INI defaults
  update-homing-params JOINT OFFSET HOME SEQUENCE
                                HOME_OFFSET, HOME and HOME_SEQUENCE only
  set-jerk-limit JOINT JERK     maximum jerk (S-curve planner; 0 none)
  set-axis-jerk-limit AXIS JERK axis maximum jerk (0 none)
  comp-entry JOINT NOMINAL FORWARD REVERSE
                                append one screw-compensation entry (trims;
                                nominals increasing; only while disabled)
  clear-comp JOINT              empty the joint's compensation table
  load-comp JOINT FILE TYPE     load a [JOINT_n]COMP_FILE of COMP_FILE_TYPE
                                0 or 1 (replaces the table; errors name the
                                file and line)

coordinated moves (coord mode; END is AXIS=VALUE words, e.g. X=10 Y=-2;
axes left out stay where the last queued move ends):
  line ID VEL END...            straight feed move at VEL (units/s)
  rapid ID END...               straight rapid (as fast as the axes allow)
  arc ID VEL center=CX,CY,CZ [normal=NX,NY,NZ] [turns=N] END...
                                arc or helix counter-clockwise about the
                                normal (default 0,0,1); turns < 0 clockwise
                                (G2 P n is turns=-n, G3 P n is turns=n-1)
  probe ID VEL G38.2|G38.3|G38.4|G38.5 END...
                                probing move
  dwell ID SECONDS              wait, after the moves before have stopped
  clear-probe                   forget the last probe result
  term-cond stop|exact|blend [TOLERANCE]
                                how the next moves end: G61.1, G61, G64 P
  pause | resume | step         step: run to the end of the current id
  feed-scale S | rapid-scale S | max-feed-override S
  feed-scale-enable 0|1 | feed-hold-enable 0|1 | adaptive-feed-enable 0|1
  spindle-scale-enable 0|1      M50 M53 M52 M51: for the moves queued next
  set-traj-vel V | set-traj-acc A | set-traj-jerk J
                                [TRAJ] MAX_LINEAR_VELOCITY, _ACCELERATION,
                                _JERK
  planner-type 0|1              trapezoidal or S-curve (PLANNER_TYPE)
";

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

fn run(args: Vec<String>) -> Result<ExitCode, Usage> {
    let mut instance = hal_core::instance_from_env();
    let mut timeout = None;
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "-h" | "--help" => {
                hal_tools::out!("{HELP}");
                return Ok(ExitCode::SUCCESS);
            }
            "-i" | "--instance" => {
                instance = args
                    .get(i + 1)
                    .ok_or_else(|| Usage("--instance needs a name".into()))?
                    .clone();
                i += 2;
            }
            "-t" | "--timeout" => {
                let text = args.get(i + 1).map_or("", String::as_str);
                // A year at most: far beyond any wait, and an Instant
                // that far ahead still exists.
                timeout = Some(
                    hal_tools::stdio::parse_seconds("--timeout", text, 365.0 * 86_400.0)
                        .map_err(Usage)?,
                );
                i += 2;
            }
            _ => break,
        }
    }
    let Some(name) = args.get(i) else {
        return Err(Usage("no command given".into()));
    };
    let rest = &args[i + 1..];
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
    match run(hal_tools::stdio::args_or_exit("motion-cmd", 2)) {
        Ok(c) => c,
        Err(Usage(m)) => {
            eprintln!("motion-cmd: {m} (see motion-cmd --help)");
            ExitCode::from(2)
        }
    }
}
