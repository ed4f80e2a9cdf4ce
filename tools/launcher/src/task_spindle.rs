//! Task's spindle requests, as LinuxCNC's task takes them from a GUI or
//! halui (`task-cmd spindle [N] ACTION`): start forward or in reverse,
//! stop, faster and slower by a step, the brake, and the spindle
//! override. Starts and stops need the machine on and nothing running;
//! the override may change any time. A program's M3/M4/M5 and S go to
//! motion in program order instead (see `program`).

use motion::Command;

use crate::error::LaunchError;
use crate::task::{Task, TaskRequest};

type Answer = Result<String, LaunchError>;

/// What a spindle request asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpindleAction {
    /// Turn forward (M3) at the speed given, else the S in effect.
    Forward(Option<f64>),
    /// Turn in reverse (M4) likewise.
    Reverse(Option<f64>),
    /// Stop (M5), the brake applied.
    Off,
    /// One step faster.
    Increase,
    /// One step slower.
    Decrease,
    /// Apply (true) or release the brake.
    Brake(bool),
    /// The spindle override (1: 100 %).
    Override(f64),
}

/// The speed a start without one runs at when no S is in effect
/// (LinuxCNC's halui uses the same).
pub const DEFAULT_RPM: f64 = 500.0;
/// How much `increase` and `decrease` change the speed, rpm
/// (LinuxCNC's default `[SPINDLE_n]INCREMENT`).
pub const SPEED_STEP: f64 = 100.0;

/// The spindle override's limits: `[DISPLAY]MIN_SPINDLE_OVERRIDE` and
/// `MAX_SPINDLE_OVERRIDE` (defaults 0 and 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpindleLimits {
    /// The smallest override.
    pub min_override: f64,
    /// The largest override.
    pub max_override: f64,
}

impl Default for SpindleLimits {
    fn default() -> Self {
        SpindleLimits {
            min_override: 0.0,
            max_override: 1.0,
        }
    }
}

impl SpindleLimits {
    /// The limits of the machine of `ini`.
    pub fn from_ini(ini: &hal_lang::ini::Ini) -> Result<SpindleLimits, LaunchError> {
        let d = SpindleLimits::default();
        let min_override = ini
            .real("DISPLAY", "MIN_SPINDLE_OVERRIDE")?
            .unwrap_or(d.min_override);
        let max_override = ini
            .real("DISPLAY", "MAX_SPINDLE_OVERRIDE")?
            .unwrap_or(d.max_override);
        Ok(SpindleLimits {
            min_override: min_override.max(0.0),
            max_override: max_override.max(min_override.max(0.0)),
        })
    }
}

/// Parses the words after `spindle`: `[N] forward|reverse [RPM]`,
/// `[N] off|increase|decrease`, `[N] brake on|off`, `[N] override SCALE`.
pub fn parse(rest: &[&str]) -> Result<TaskRequest, LaunchError> {
    let bad = |why: String| LaunchError::BadArgument {
        request: "spindle",
        why,
    };
    let (spindle, rest) = match rest.split_first() {
        Some((n, more)) if n.parse::<i32>().is_ok() => {
            let n: i32 = n.parse().unwrap_or(-1);
            if !(0..motion::sizes::MAX_SPINDLES as i32).contains(&n) {
                return Err(bad(format!("no spindle {n} (spindles are 0 to 7)")));
            }
            (n, more)
        }
        _ => (0, rest),
    };
    let number = |w: &str, what: &str| -> Result<f64, LaunchError> {
        w.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v >= 0.0)
            .ok_or_else(|| bad(format!("{what} must be a number of at least 0, not '{w}'")))
    };
    let action = match rest {
        ["forward"] => SpindleAction::Forward(None),
        ["forward", rpm] => SpindleAction::Forward(Some(number(rpm, "RPM")?)),
        ["reverse"] => SpindleAction::Reverse(None),
        ["reverse", rpm] => SpindleAction::Reverse(Some(number(rpm, "RPM")?)),
        ["off"] => SpindleAction::Off,
        ["increase"] => SpindleAction::Increase,
        ["decrease"] => SpindleAction::Decrease,
        ["brake", "on"] => SpindleAction::Brake(true),
        ["brake", "off"] => SpindleAction::Brake(false),
        ["override", scale] => SpindleAction::Override(number(scale, "SCALE")?),
        _ => {
            return Err(bad(format!(
                "'{}' is not forward [RPM], reverse [RPM], off, increase, decrease, \
                 brake on|off or override SCALE",
                rest.join(" ")
            )))
        }
    };
    Ok(TaskRequest::Spindle { spindle, action })
}

impl Task {
    /// Takes a spindle request.
    pub(crate) fn spindle_request(&mut self, spindle: i32, action: SpindleAction) -> Answer {
        if !matches!(action, SpindleAction::Override(_)) {
            self.require_on()?;
            if self.program.as_ref().is_some_and(|p| !p.settled()) {
                return Err(LaunchError::Program(
                    "a program or MDI line runs: its spindle is not switched by hand".into(),
                ));
            }
        }
        let start_rpm = |rpm: Option<f64>, task: &Task| match rpm {
            Some(r) => r,
            None => {
                let s = task.program.as_ref().map_or(0.0, |p| p.active_speed());
                if s > 0.0 {
                    s
                } else {
                    DEFAULT_RPM
                }
            }
        };
        let (cmd, done) = match action {
            SpindleAction::Forward(rpm) => {
                let rpm = start_rpm(rpm, self);
                (
                    on(spindle, rpm),
                    format!("spindle {spindle} forward {rpm} rpm"),
                )
            }
            SpindleAction::Reverse(rpm) => {
                let rpm = start_rpm(rpm, self);
                (
                    on(spindle, -rpm),
                    format!("spindle {spindle} reverse {rpm} rpm"),
                )
            }
            SpindleAction::Off => (
                Command::SpindleOff { spindle },
                format!("spindle {spindle} off"),
            ),
            SpindleAction::Brake(engage) => (
                Command::SpindleBrake {
                    spindle,
                    on: engage,
                },
                format!(
                    "spindle {spindle} brake {}",
                    if engage { "on" } else { "off" }
                ),
            ),
            SpindleAction::Increase | SpindleAction::Decrease => {
                let now = self.turning_speed(spindle)?;
                let size = if action == SpindleAction::Increase {
                    now.abs() + SPEED_STEP
                } else if now.abs() > SPEED_STEP {
                    now.abs() - SPEED_STEP
                } else {
                    now.abs()
                };
                (
                    on(spindle, size.copysign(now)),
                    format!("spindle {spindle} at {size} rpm"),
                )
            }
            SpindleAction::Override(scale) => {
                let l = self.spindle_limits;
                let scale = scale.clamp(l.min_override, l.max_override);
                (
                    Command::SpindleScale { spindle, scale },
                    format!("spindle {spindle} override {scale}"),
                )
            }
        };
        let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
        m.command(cmd)
            .map_err(|source| LaunchError::MotionRefused { source })?;
        Ok(done)
    }

    /// The signed speed of a turning spindle, or why there is none.
    fn turning_speed(&self, spindle: i32) -> Result<f64, LaunchError> {
        let status = self
            .motion
            .as_ref()
            .ok_or(LaunchError::NoMotion)?
            .status()
            .ok_or(LaunchError::NoMotion)?;
        usize::try_from(spindle)
            .ok()
            .and_then(|n| status.spindles.get(n))
            .filter(|s| s.on && s.speed != 0.0)
            .map(|s| s.speed)
            .ok_or_else(|| {
                LaunchError::Program(format!("spindle {spindle} does not turn (start it first)"))
            })
    }
}

/// A start without the at-speed wait: nothing queued waits on it.
fn on(spindle: i32, speed: f64) -> Command {
    Command::SpindleOn {
        spindle,
        speed,
        wait: false,
    }
}

/// Spindle 0 as motion last reported it, as `key=value` lines for
/// task's state: `spindle-speed` (commanded rpm, 0 when stopped),
/// `spindle-direction` (1 forward, -1 reverse, 0 stopped),
/// `spindle-at-speed`, `spindle-brake` (0 or 1) and `spindle-override`.
/// Without motion: stopped, not at speed, override 1.
pub(crate) fn spindle_state_lines(status: Option<&motion::channel::SpindleState>) -> String {
    let (speed, at_speed, brake, scale) = match status {
        Some(s) if s.on => (s.speed, s.at_speed, s.brake, s.scale),
        Some(s) => (0.0, s.at_speed, s.brake, s.scale),
        None => (0.0, false, false, 1.0),
    };
    let direction = if speed > 0.0 {
        1
    } else if speed < 0.0 {
        -1
    } else {
        0
    };
    format!(
        "spindle-speed={}\nspindle-direction={direction}\nspindle-at-speed={}\n\
         spindle-brake={}\nspindle-override={scale}\n",
        speed.abs(),
        u8::from(at_speed),
        u8::from(brake),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(spindle: i32, action: SpindleAction) -> TaskRequest {
        TaskRequest::Spindle { spindle, action }
    }

    #[test]
    fn spindle_state_lines_give_speed_direction_and_at_speed() {
        let reverse = motion::channel::SpindleState {
            on: true,
            at_speed: true,
            speed: -750.0,
            scale: 0.8,
            ..Default::default()
        };
        assert_eq!(
            spindle_state_lines(Some(&reverse)),
            "spindle-speed=750\nspindle-direction=-1\nspindle-at-speed=1\n\
             spindle-brake=0\nspindle-override=0.8\n"
        );
        let off = motion::channel::SpindleState {
            speed: 300.0,
            brake: true,
            scale: 1.0,
            ..Default::default()
        };
        assert_eq!(
            spindle_state_lines(Some(&off)),
            "spindle-speed=0\nspindle-direction=0\nspindle-at-speed=0\n\
             spindle-brake=1\nspindle-override=1\n"
        );
        assert!(spindle_state_lines(None).contains("spindle-direction=0\n"));
    }

    #[test]
    fn spindle_requests_parse_and_refuse_bad_words() {
        assert_eq!(
            parse(&["forward"]).unwrap(),
            req(0, SpindleAction::Forward(None))
        );
        assert_eq!(
            parse(&["1", "reverse", "750"]).unwrap(),
            req(1, SpindleAction::Reverse(Some(750.0)))
        );
        assert_eq!(
            parse(&["brake", "on"]).unwrap(),
            req(0, SpindleAction::Brake(true))
        );
        assert_eq!(
            parse(&["override", "0.8"]).unwrap(),
            req(0, SpindleAction::Override(0.8))
        );
        let e = parse(&["9", "off"]).unwrap_err().to_string();
        assert!(e.contains("no spindle 9"), "{e}");
        let e = parse(&["forward", "-5"]).unwrap_err().to_string();
        assert!(
            e.contains("RPM must be a number of at least 0, not '-5'"),
            "{e}"
        );
        let e = parse(&["sideways"]).unwrap_err().to_string();
        assert!(e.contains("'sideways' is not forward"), "{e}");
    }

    #[test]
    fn override_limits_come_from_the_ini_file() {
        let ini = hal_lang::ini::Ini::parse(
            "[DISPLAY]\nMIN_SPINDLE_OVERRIDE = 0.5\nMAX_SPINDLE_OVERRIDE = 1.5\n",
        );
        let l = SpindleLimits::from_ini(&ini).unwrap();
        assert_eq!((l.min_override, l.max_override), (0.5, 1.5));
        let l = SpindleLimits::from_ini(&hal_lang::ini::Ini::parse("")).unwrap();
        assert_eq!(l, SpindleLimits::default());
    }
}
