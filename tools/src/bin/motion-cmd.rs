//! `motion-cmd`: send commands to the motion controller (`motmod`) of a
//! running HAL instance through its shared-memory command channel, and
//! show its status. Exit status: 0 accepted, 1 rejected, 2 usage or
//! connection error.

use std::process::ExitCode;
use std::time::Duration;

use motion::kins::{Pose, NUM_AXES};
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

/// An axis: its letter (either case) or its number. Numbers out of range
/// pass through, for the controller to refuse.
fn axis(s: Option<&String>) -> Result<i32, Usage> {
    let s = s.ok_or_else(|| Usage("missing AXIS".into()))?;
    let mut chars = s.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        let c = c.to_ascii_lowercase();
        if let Some(i) = motion::kins::AXIS_LETTERS.iter().position(|&l| l == c) {
            return Ok(i as i32);
        }
    }
    s.parse().map_err(|_| {
        Usage(format!(
            "AXIS must be one of x y z a b c u v w or a number, not '{s}'"
        ))
    })
}

/// Parses a command and its arguments.
fn parse_command(name: &str, a: &[String]) -> Result<Command, Usage> {
    let j = || int(a.first(), "JOINT");
    let f = |i: usize, what: &str| float(a.get(i), what);
    let want = |n: usize| {
        if a.len() == n {
            Ok(())
        } else {
            Err(Usage(format!(
                "'{name}' takes {n} argument(s), {} given",
                a.len()
            )))
        }
    };
    let cmd = match name {
        "enable" => Command::Enable,
        "disable" => Command::Disable,
        "abort" => Command::Abort,
        "free" => Command::Free,
        "teleop" => Command::Teleop,
        "coord" => Command::Coord,
        "scale" => Command::Scale {
            scale: float(a.first(), "VALUE")?,
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
            axis: axis(a.first())?,
            vel: f(1, "VEL")?,
        },
        "axis-jog-incr" => Command::AxisJogIncr {
            axis: axis(a.first())?,
            vel: f(1, "VEL")?,
            offset: f(2, "DIST")?,
        },
        "axis-jog-abs" => Command::AxisJogAbs {
            axis: axis(a.first())?,
            vel: f(1, "VEL")?,
            pos: f(2, "POS")?,
        },
        "axis-jog-abort" => Command::AxisJogAbort {
            axis: axis(a.first())?,
        },
        "set-axis-limits" => Command::SetAxisPositionLimits {
            axis: axis(a.first())?,
            min: f(1, "MIN")?,
            max: f(2, "MAX")?,
        },
        "set-axis-vel-limit" => Command::SetAxisVelLimit {
            axis: axis(a.first())?,
            vel: f(1, "VEL")?,
        },
        "set-axis-acc-limit" => Command::SetAxisAccLimit {
            axis: axis(a.first())?,
            acc: f(1, "ACC")?,
        },
        "set-world-home" => {
            let mut pose = Pose::ZERO;
            for (i, v) in pose.0.iter_mut().enumerate() {
                *v = f(i, "coordinate")?;
            }
            want(NUM_AXES)?;
            Command::SetWorldHome { pose }
        }
        _ => return Err(Usage(format!("unknown command '{name}'"))),
    };
    let n = match cmd {
        Command::Enable
        | Command::Disable
        | Command::Abort
        | Command::Free
        | Command::Teleop
        | Command::Coord => 0,
        Command::Scale { .. }
        | Command::OverrideLimits { .. }
        | Command::JointActivate { .. }
        | Command::JointDeactivate { .. }
        | Command::EnableAmplifier { .. }
        | Command::DisableAmplifier { .. }
        | Command::JogAbort { .. } => 1,
        Command::JogCont { .. }
        | Command::SetJointVelLimit { .. }
        | Command::SetJointAccLimit { .. }
        | Command::SetJointMinFerror { .. }
        | Command::SetJointMaxFerror { .. }
        | Command::SetJointBacklash { .. }
        | Command::SetJointMotorOffset { .. } => 2,
        Command::JogIncr { .. }
        | Command::JogAbs { .. }
        | Command::SetJointPositionLimits { .. } => 3,
        Command::SetWorldHome { .. } => NUM_AXES,
        Command::AxisJogAbort { .. } => 1,
        Command::AxisJogCont { .. }
        | Command::SetAxisVelLimit { .. }
        | Command::SetAxisAccLimit { .. } => 2,
        Command::AxisJogIncr { .. }
        | Command::AxisJogAbs { .. }
        | Command::SetAxisPositionLimits { .. } => 3,
    };
    want(n)?;
    Ok(cmd)
}

fn run(args: Vec<String>) -> Result<ExitCode, Usage> {
    let mut instance = std::env::var("HAL_INSTANCE").unwrap_or_else(|_| "default".into());
    let mut timeout = Duration::from_secs(1);
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "-h" | "--help" => {
                print!("{HELP}");
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
                let s = float(args.get(i + 1), "--timeout")?;
                if !(s.is_finite() && s > 0.0) {
                    return Err(Usage("--timeout must be a positive number".into()));
                }
                timeout = Duration::from_secs_f64(s);
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
        Watch { ms: u64, count: Option<u64> },
        Send(Command),
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
        _ => Action::Send(parse_command(name, rest)?),
    };
    let mut client = match MotionClient::attach(&instance) {
        Ok(c) => c.with_timeout(timeout),
        Err(e) => {
            eprintln!("motion-cmd: instance '{instance}': {e}");
            return Ok(ExitCode::from(2));
        }
    };
    match action {
        Action::Send(cmd) => match client.send(cmd) {
            Ok(a) => {
                println!("accepted (serial {})", a.serial);
                Ok(ExitCode::SUCCESS)
            }
            Err(r) => {
                println!("{r}");
                Ok(ExitCode::from(1))
            }
        },
        Action::Status => match client.status() {
            Ok(s) => {
                print!("{s}");
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
                    Ok(s) => print!("\x1b[H\x1b[2J{s}"),
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

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(c) => c,
        Err(Usage(m)) => {
            eprintln!("motion-cmd: {m} (see motion-cmd --help)");
            ExitCode::from(2)
        }
    }
}
