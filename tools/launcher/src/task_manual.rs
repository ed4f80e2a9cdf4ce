//! Task's manual requests, as LinuxCNC's task takes them from a GUI or
//! halui: homing and jogging joints (MANUAL mode, machine on), the feed
//! and rapid overrides and the tool-tip speed limit; and the `state`
//! answer, the machine state as `key=value` lines for programs.

use std::time::{Duration, Instant};

use hal_lang::ini::Ini;
use motion::Command;

use crate::error::LaunchError;
use crate::motion_setup::MotionLink;
use crate::task::{MachineState, Mode, Task, TaskRequest};

type Answer = Result<String, LaunchError>;

/// The overrides task sent last, and their limits from the INI file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overrides {
    /// The feed override.
    pub feed: f64,
    /// The rapid override.
    pub rapid: f64,
    /// The tool-tip speed limit (machine units per second).
    pub max_velocity: f64,
    /// `[DISPLAY]MAX_FEED_OVERRIDE`.
    pub max_feed: f64,
    /// `[TRAJ]MAX_LINEAR_VELOCITY`: the largest speed limit.
    pub max_velocity_limit: f64,
}

impl Default for Overrides {
    fn default() -> Self {
        Overrides {
            feed: 1.0,
            rapid: 1.0,
            max_velocity: crate::config::NO_LIMIT,
            max_feed: 1.0,
            max_velocity_limit: crate::config::NO_LIMIT,
        }
    }
}

impl Overrides {
    /// The start values for the machine of `ini`: both overrides at 100 %,
    /// the speed limit at `[TRAJ]MAX_LINEAR_VELOCITY`.
    pub fn from_ini(ini: &Ini) -> Result<Overrides, LaunchError> {
        let max_feed = crate::config::max_feed_override(ini)?;
        let max_velocity = crate::config::TrajSettings::from_ini(ini)?.max_velocity;
        Ok(Overrides {
            max_feed,
            max_velocity,
            max_velocity_limit: max_velocity,
            ..Overrides::default()
        })
    }
}

/// What a jog moves: a joint (free mode) or a world axis (teleop mode).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Jogged {
    /// A joint number.
    Joint(i32),
    /// A world axis: 0..=8 for X Y Z A B C U V W.
    Axis(i32),
}

impl std::fmt::Display for Jogged {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Jogged::Joint(j) => write!(f, "joint {j}"),
            Jogged::Axis(a) => {
                let letter = usize::try_from(a)
                    .ok()
                    .and_then(|a| AXIS_LETTERS.get(a))
                    .copied()
                    .unwrap_or('?');
                write!(f, "axis {letter}")
            }
        }
    }
}

/// The world axes' letters, in motion's order.
const AXIS_LETTERS: [char; 9] = ['x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w'];

/// Parses the words after a manual request's name.
pub fn parse(word: &str, rest: &[&str]) -> Result<TaskRequest, LaunchError> {
    let request: &'static str = match word {
        "home" => "home",
        "unhome" => "unhome",
        "jog-cont" => "jog-cont",
        "jog-incr" => "jog-incr",
        "jog-stop" => "jog-stop",
        "feed-override" => "feed-override",
        "rapid-override" => "rapid-override",
        _ => "max-velocity",
    };
    let bad = |why: String| LaunchError::BadArgument { request, why };
    let joint = |w: Option<&&str>| -> Result<i32, LaunchError> {
        let w = w.ok_or_else(|| bad("missing JOINT".into()))?;
        w.parse::<i32>()
            .ok()
            .filter(|j| (0..16).contains(j))
            .ok_or_else(|| bad(format!("JOINT must be a joint number 0..15, not '{w}'")))
    };
    let number = |w: Option<&&str>, what: &str| -> Result<f64, LaunchError> {
        let w = w.ok_or_else(|| bad(format!("missing {what}")))?;
        w.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("{what} must be a number, not '{w}'")))
    };
    let count = match request {
        "jog-cont" => 2,
        "jog-incr" => 3,
        _ => 1,
    };
    if rest.len() != count {
        return Err(bad(format!(
            "takes {count} argument{}, not {}",
            if count == 1 { "" } else { "s" },
            rest.len()
        )));
    }
    let jogged = |w: Option<&&str>| -> Result<Jogged, LaunchError> {
        let axis = w.and_then(|w| {
            let mut chars = w.chars();
            match (chars.next(), chars.next()) {
                (Some(c), None) => AXIS_LETTERS
                    .iter()
                    .position(|l| *l == c.to_ascii_lowercase()),
                _ => None,
            }
        });
        match axis {
            Some(a) => Ok(Jogged::Axis(a as i32)),
            None => joint(w).map(Jogged::Joint),
        }
    };
    let joint_or_all = |w: Option<&&str>| match w {
        Some(&"all") => Ok(None),
        other => joint(other).map(Some),
    };
    Ok(match request {
        "home" => TaskRequest::Home(joint_or_all(rest.first())?),
        "unhome" => TaskRequest::Unhome(joint_or_all(rest.first())?),
        "jog-cont" => TaskRequest::JogCont {
            what: jogged(rest.first())?,
            vel: number(rest.get(1), "VEL")?,
        },
        "jog-incr" => TaskRequest::JogIncr {
            what: jogged(rest.first())?,
            vel: number(rest.get(1), "VEL")?,
            dist: number(rest.get(2), "DISTANCE")?,
        },
        "jog-stop" => TaskRequest::JogStop(jogged(rest.first())?),
        "feed-override" => TaskRequest::FeedOverride(number(rest.first(), "SCALE")?),
        "rapid-override" => TaskRequest::RapidOverride(number(rest.first(), "SCALE")?),
        _ => TaskRequest::MaxVelocity(number(rest.first(), "VEL")?),
    })
}

/// How long a joint's home waits for the homing in progress to end.
const PENDING_HOME_WAIT: Duration = Duration::from_secs(300);

/// Joints whose home was asked while another joint homed: the motion
/// controller takes one homing at a time, so task sends each once the
/// homing in progress has ended (a client asking for joints 0, 1 and 2
/// one after the other gets all three homed, as under LinuxCNC).
#[derive(Debug, Default)]
pub struct PendingHomes(Vec<(i32, Instant)>);

impl PendingHomes {
    /// Forgets them (abort, e-stop, machine off).
    pub fn clear(&mut self) {
        self.0.clear();
    }
}

impl Task {
    /// Homes one joint, or keeps it for when the homing in progress ends.
    pub(crate) fn home_joint(&mut self, joint: i32) -> Answer {
        if !self.pending_homes.0.is_empty() {
            self.require_manual("home")?;
            self.pending_homes
                .0
                .push((joint, Instant::now() + PENDING_HOME_WAIT));
            return Ok(format!("joint {joint} homes after the joints before it"));
        }
        match self.manual_request(&TaskRequest::Home(Some(joint))) {
            Err(LaunchError::MotionRefused {
                source: motion::Reject::HomingActive,
            }) => {
                self.pending_homes
                    .0
                    .push((joint, Instant::now() + PENDING_HOME_WAIT));
                Ok(format!(
                    "joint {joint} homes once the homing in progress ends"
                ))
            }
            other => other,
        }
    }

    /// Sends the first pending home once motion shows no homing; a
    /// refusal other than "homing active" drops it, on the error channel.
    pub(crate) fn home_pending(&mut self) {
        let Some(&(joint, until)) = self.pending_homes.0.first() else {
            return;
        };
        let homing = self
            .motion
            .as_ref()
            .and_then(MotionLink::status)
            .is_none_or(|s| s.homing_active);
        if homing && Instant::now() < until {
            return;
        }
        let result = if homing {
            Err(LaunchError::Program(format!(
                "home joint {joint}: the homing in progress did not end within {} s",
                PENDING_HOME_WAIT.as_secs()
            )))
        } else {
            self.manual_request(&TaskRequest::Home(Some(joint)))
        };
        match result {
            Err(LaunchError::MotionRefused {
                source: motion::Reject::HomingActive,
            }) if Instant::now() < until => {}
            Err(e) => {
                self.pending_homes.0.remove(0);
                eprintln!("task: {e}");
                self.messages
                    .push(crate::task_messages::OPERATOR_ERROR, &e.to_string());
            }
            Ok(_) => {
                self.pending_homes.0.remove(0);
            }
        }
    }

    /// Takes a home, jog or override request.
    pub(crate) fn manual_request(&mut self, req: &TaskRequest) -> Answer {
        let (cmd, done) = match *req {
            TaskRequest::Home(joint) => {
                self.require_manual("home")?;
                let j = joint.unwrap_or(-1);
                (
                    Command::Home { joint: j },
                    format!("homing {}", which(joint)),
                )
            }
            TaskRequest::Unhome(joint) => {
                self.require_manual("unhome")?;
                let j = joint.unwrap_or(-1);
                (
                    Command::Unhome { joint: j },
                    format!("unhomed {}", which(joint)),
                )
            }
            TaskRequest::JogCont { what, vel } => {
                self.require_manual("jog-cont")?;
                let cmd = match what {
                    Jogged::Joint(joint) => Command::JogCont { joint, vel },
                    Jogged::Axis(axis) => Command::AxisJogCont { axis, vel },
                };
                (cmd, format!("jogging {what}"))
            }
            TaskRequest::JogIncr { what, vel, dist } => {
                self.require_manual("jog-incr")?;
                // Motion takes the distance unsigned, the direction from
                // the speed's sign.
                let (vel, offset) = (vel.abs().copysign(dist), dist.abs());
                let cmd = match what {
                    Jogged::Joint(joint) => Command::JogIncr { joint, vel, offset },
                    Jogged::Axis(axis) => Command::AxisJogIncr { axis, vel, offset },
                };
                (cmd, format!("jogging {what} by {dist}"))
            }
            TaskRequest::JogStop(what) => {
                let cmd = match what {
                    Jogged::Joint(joint) => Command::JogAbort { joint },
                    Jogged::Axis(axis) => Command::AxisJogAbort { axis },
                };
                (cmd, format!("{what} jog stopped"))
            }
            TaskRequest::FeedOverride(scale) => {
                let scale = scale.clamp(0.0, self.overrides.max_feed);
                self.overrides.feed = scale;
                (
                    Command::FeedScale { scale },
                    format!("feed override {scale}"),
                )
            }
            TaskRequest::RapidOverride(scale) => {
                let scale = scale.clamp(0.0, 1.0);
                self.overrides.rapid = scale;
                (
                    Command::RapidScale { scale },
                    format!("rapid override {scale}"),
                )
            }
            TaskRequest::MaxVelocity(vel) => {
                if vel <= 0.0 {
                    return Err(LaunchError::BadArgument {
                        request: "max-velocity",
                        why: format!("VEL must be above 0, not {vel}"),
                    });
                }
                let vel = vel.min(self.overrides.max_velocity_limit);
                self.overrides.max_velocity = vel;
                (Command::SetVelLimit { vel }, format!("max velocity {vel}"))
            }
            _ => return Err(LaunchError::Program("not a manual request".into())),
        };
        let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
        m.command(cmd)
            .map_err(|source| LaunchError::MotionRefused { source })?;
        Ok(done)
    }

    /// Homing and jogging: the machine on, in MANUAL mode.
    fn require_manual(&self, request: &'static str) -> Result<(), LaunchError> {
        self.require_on()?;
        if self.mode != Mode::Manual {
            return Err(LaunchError::NotManual {
                request,
                mode: self.mode.name(),
            });
        }
        Ok(())
    }

    /// The state as `key=value` lines: `machine` (ESTOP, OFF, ON), `mode`,
    /// `program` (IDLE, RUNNING, PAUSED), `mist`, `flood`, `lube` (0 or
    /// 1), `tool`, `feed-override`, `rapid-override`, `max-velocity`;
    /// then the switch, tool and offset lines of
    /// [`panel_state_lines`](Task::panel_state_lines) and spindle 0's
    /// (`spindle-speed`, `spindle-direction`, `spindle-at-speed`, ...).
    pub(crate) fn state_lines(&self) -> String {
        let o = self.io.outputs();
        let bit = |b: bool| u8::from(b);
        // An MDI line waiting to start counts as running: a client that
        // sent it sees it run until it has.
        let program = match &self.program {
            Some(p) if p.idle() && !p.settled() => "RUNNING",
            Some(p) => p.run_state().short_name(),
            None => "IDLE",
        };
        format!(
            "machine={}\nmode={}\nprogram={program}\nmist={}\nflood={}\nlube={}\ntool={}\n\
             feed-override={}\nrapid-override={}\nmax-velocity={}\n",
            match self.state {
                MachineState::Estop => "ESTOP",
                MachineState::Off => "OFF",
                MachineState::On => "ON",
            },
            self.mode.name(),
            bit(o.coolant_mist),
            bit(o.coolant_flood),
            bit(o.lube),
            self.io.tool_in_spindle(),
            self.overrides.feed,
            self.overrides.rapid,
            self.overrides.max_velocity,
        ) + &self.panel_state_lines()
            + &crate::task_spindle::spindle_state_lines(
                self.motion
                    .as_ref()
                    .and_then(MotionLink::status)
                    .as_ref()
                    .and_then(|s| s.spindles.first()),
            )
    }
}

fn which(joint: Option<i32>) -> String {
    joint.map_or("every joint".to_string(), |j| format!("joint {j}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manual_requests_parse_and_refuse_bad_words() {
        assert_eq!(parse("home", &["all"]).unwrap(), TaskRequest::Home(None));
        assert_eq!(parse("home", &["2"]).unwrap(), TaskRequest::Home(Some(2)));
        assert_eq!(
            parse("jog-incr", &["1", "5", "-0.5"]).unwrap(),
            TaskRequest::JogIncr {
                what: Jogged::Joint(1),
                vel: 5.0,
                dist: -0.5
            }
        );
        assert_eq!(
            parse("jog-stop", &["Z"]).unwrap(),
            TaskRequest::JogStop(Jogged::Axis(2))
        );
        assert_eq!(Jogged::Axis(8).to_string(), "axis w");
        assert_eq!(
            parse("feed-override", &["1.2"]).unwrap(),
            TaskRequest::FeedOverride(1.2)
        );
        let e = parse("jog-cont", &["1"]).unwrap_err().to_string();
        assert_eq!(e, "jog-cont: takes 2 arguments, not 1");
        let e = parse("home", &["17"]).unwrap_err().to_string();
        assert!(
            e.contains("JOINT must be a joint number 0..15, not '17'"),
            "{e}"
        );
        let e = parse("max-velocity", &["fast"]).unwrap_err().to_string();
        assert_eq!(e, "max-velocity: VEL must be a number, not 'fast'");
        let e = parse("rapid-override", &["nan"]).unwrap_err().to_string();
        assert!(e.contains("not 'nan'"), "{e}");
    }

    #[test]
    fn overrides_start_from_the_ini_file() {
        let ini =
            Ini::parse("[DISPLAY]\nMAX_FEED_OVERRIDE = 1.5\n[TRAJ]\nMAX_LINEAR_VELOCITY = 4\n");
        let o = Overrides::from_ini(&ini).unwrap();
        assert_eq!(
            (o.feed, o.rapid, o.max_feed, o.max_velocity),
            (1.0, 1.0, 1.5, 4.0)
        );
    }
}
