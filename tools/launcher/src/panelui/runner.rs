//! The commands' effects, as requests to task (the channel `task-cmd`
//! and halui use), in the order the buttons ran them, on a thread of
//! their own so that reading keys never waits for task. Commands wait
//! until task answers (the HAL files still run at start). Its memory is
//! LinuxCNC's: the jog speeds, which axes jog, the restart line and the
//! mode an `mdi_and_return` goes back to.

use std::collections::HashMap;
use std::time::Duration;

use super::commands::Command;
use super::panel::Fired;
use crate::task_socket::{request, TaskAnswer, TaskClientError};

/// How long a request may take (a mode change waits for motion).
const REQUEST_WAIT: Duration = Duration::from_secs(10);
/// How long an MDI line may run before the next is sent.
const MDI_WAIT: Duration = Duration::from_secs(300);
/// The axis letters in LinuxCNC's axis numbering.
const AXES: [char; 9] = ['x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w'];

/// Task's state, the parts the commands read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapshot {
    /// `MANUAL`, `AUTO` or `MDI`.
    pub mode: String,
    /// `IDLE`, `RUNNING` or `PAUSED`.
    pub program: String,
    /// Spindle 0: 1 forward, -1 reverse, 0 stopped.
    pub spindle_direction: i32,
}

/// Reads the parts of task's `state` answer the commands need.
pub fn parse_snapshot(text: &str) -> Option<Snapshot> {
    let map: HashMap<&str, &str> = text
        .lines()
        .filter_map(|l| l.split_once('='))
        .map(|(k, v)| (k.trim(), v.trim()))
        .collect();
    Some(Snapshot {
        mode: map.get("mode")?.to_string(),
        program: map.get("program")?.to_string(),
        spindle_direction: map.get("spindle-direction")?.parse().ok()?,
    })
}

/// What the runner is asked to do.
#[derive(Debug, Clone, PartialEq)]
pub enum Job {
    /// Run a button's command.
    Run(Fired),
    /// The periodic check (every 100 ms): back to the mode an
    /// `mdi_and_return` left, once idle.
    Periodic,
}

/// The runner's memory between commands.
pub struct Runner {
    instance: String,
    /// `[TRAJ]COORDINATES`, lower case: the joint of an axis in joint
    /// mode is its place here.
    coordinates: Vec<char>,
    /// Units per second.
    linear_speed: f64,
    /// Degrees per second.
    angular_speed: f64,
    /// Each axis's continuous jog direction (0: not jogging).
    jogging: [i32; 9],
    restart_line: i32,
    restart_reset: i32,
    return_to: Option<String>,
    motion: Option<motion::MotionClient>,
    /// Print each request.
    pub debug: bool,
}

impl Runner {
    /// A runner for task of `instance`; `coordinates` is
    /// `[TRAJ]COORDINATES`.
    pub fn new(instance: String, coordinates: &str) -> Runner {
        Runner {
            instance,
            coordinates: coordinates
                .chars()
                .filter(|c| !c.is_whitespace())
                .map(|c| c.to_ascii_lowercase())
                .collect(),
            linear_speed: 100.0 / 60.0,
            angular_speed: 3600.0 / 60.0,
            jogging: [0; 9],
            restart_line: 0,
            restart_reset: 0,
            return_to: None,
            motion: None,
            debug: false,
        }
    }

    /// Task's state, `None` while task does not answer.
    pub fn snapshot(&self) -> Option<Snapshot> {
        match request(&self.instance, &["state".to_string()], REQUEST_WAIT) {
            Ok(TaskAnswer::Done(text)) => parse_snapshot(&text),
            Ok(TaskAnswer::Refused(_))
            | Err(TaskClientError::NotRunning { .. })
            | Err(TaskClientError::Io(_)) => None,
            Err(e) => {
                eprintln!("panelui: task: {e}");
                None
            }
        }
    }

    /// Sends a request; prints a refusal. Whether it was done.
    fn ask(&self, who: &str, words: &[&str], wait: Duration) -> bool {
        let owned: Vec<String> = words.iter().map(|w| w.to_string()).collect();
        if self.debug {
            println!("panelui: {who}: task-cmd {}", words.join(" "));
        }
        match request(&self.instance, &owned, wait) {
            Ok(TaskAnswer::Done(_)) => true,
            Ok(TaskAnswer::Refused(why)) => {
                eprintln!("panelui: {who}: {}: {why}", words.join(" "));
                false
            }
            Err(e) => {
                eprintln!("panelui: {who}: {}: {e}", words.join(" "));
                false
            }
        }
    }

    /// Puts task in `mode` (lower case) unless it is there.
    fn mode(&self, who: &str, s: &Snapshot, mode: &str) -> bool {
        s.mode.eq_ignore_ascii_case(mode) || self.ask(who, &["mode", mode], REQUEST_WAIT)
    }

    /// Does a job with task's state `s`.
    pub fn job(&mut self, job: Job, s: &Snapshot) {
        match job {
            Job::Periodic => {
                if s.program == "IDLE" {
                    if let Some(m) = self.return_to.take() {
                        self.mode("mdi_and_return", s, &m);
                    }
                }
            }
            Job::Run(f) => self.run(&f.button, &f.command, s),
        }
    }

    fn run(&mut self, who: &str, c: &Command, s: &Snapshot) {
        if let Some((mode, words)) = plain_request(c) {
            let w: Vec<&str> = words.iter().map(String::as_str).collect();
            if mode.is_none_or(|m| self.mode(who, s, m)) {
                self.ask(who, &w, REQUEST_WAIT);
            }
            return;
        }
        match c {
            Command::Jogging => _ = self.mode(who, s, "manual"),
            Command::SpindleForwardAdjust(rpm) | Command::SpindleReverseAdjust(rpm) => {
                let dir = if matches!(c, Command::SpindleForwardAdjust(_)) {
                    1
                } else {
                    -1
                };
                if s.mode != "MDI" || self.mode(who, s, "manual") {
                    self.spindle_adjust(who, s, dir, *rpm);
                }
            }
            Command::SpindleForward(rpm) | Command::SpindleReverse(rpm) => {
                let word = if matches!(c, Command::SpindleForward(_)) {
                    "forward"
                } else {
                    "reverse"
                };
                if self.mode(who, s, "manual") && s.spindle_direction == 0 {
                    let rpm = rpm.to_string();
                    self.ask(who, &["spindle", "0", word, &rpm], REQUEST_WAIT);
                }
            }
            Command::LinearJogVelocity(v) => {
                self.linear_speed = v / 60.0;
                self.rejog(who, &[0, 1, 2, 6, 7, 8]);
            }
            Command::AngularJogVelocity(v) => {
                self.angular_speed = v / 60.0;
                self.rejog(who, &[3, 4, 5]);
            }
            Command::ContinuousJog { axis, direction } => self.jog(who, *axis, *direction),
            Command::IncrementalJog {
                axis,
                direction,
                distance,
            } => {
                if let Some(target) = self.jog_target(who, *axis) {
                    let speed = self.speed(*axis).to_string();
                    let dist = (f64::from(*direction) * distance).to_string();
                    self.ask(who, &["jog-incr", &target, &speed, &dist], REQUEST_WAIT);
                }
            }
            _ => self.program_command(who, c, s),
        }
    }

    /// The program and MDI commands, and those that do nothing here.
    fn program_command(&mut self, who: &str, c: &Command, s: &Snapshot) {
        match c {
            Command::QuillUp(z) => _ = self.mdi(who, s, &[format!("G53 G0 Z {z:.6}")]),
            Command::SingleBlock(on) if s.program != "IDLE" => {
                let w = if *on { "pause" } else { "resume" };
                self.ask(who, &[w], REQUEST_WAIT);
            }
            Command::SmartCycleStart => self.cycle_start(who, s),
            Command::Restart(line) => {
                if self.mode(who, s, "auto") {
                    self.ask(who, &["run", &line.to_string()], REQUEST_WAIT);
                }
                self.restart_line = self.restart_reset;
            }
            Command::SetRestartLine(line) => {
                self.restart_line = *line;
                self.restart_reset = 0;
            }
            Command::Mdi(lines) => _ = self.mdi(who, s, lines),
            Command::MdiAndReturn(lines) if s.program == "IDLE" => {
                let before = s.mode.to_ascii_lowercase();
                if self.mdi(who, s, lines) && before != "mdi" {
                    self.return_to = Some(before);
                }
            }
            Command::Handler(name) => eprintln!(
                "panelui: {who}: {name} is a function of panelui_handler.py, which is \
                 Python: this panelui does not run it"
            ),
            // `mdi_active` keeps a value nobody reads; single_block while
            // idle and mdi_and_return while busy do nothing, as LinuxCNC's;
            // the rest are plain requests or taken by `run`.
            _ => {}
        }
    }

    /// `spindle_*_adjust`: start in `dir` if stopped, else faster when
    /// turning that way and slower when turning the other.
    fn spindle_adjust(&self, who: &str, s: &Snapshot, dir: i32, rpm: f64) {
        let words: Vec<String> = match s.spindle_direction {
            0 => {
                let w = if dir > 0 { "forward" } else { "reverse" };
                vec!["spindle".into(), "0".into(), w.into(), rpm.to_string()]
            }
            d if d == dir => vec!["spindle".into(), "0".into(), "increase".into()],
            _ => vec!["spindle".into(), "0".into(), "decrease".into()],
        };
        let w: Vec<&str> = words.iter().map(String::as_str).collect();
        self.ask(who, &w, REQUEST_WAIT);
    }

    fn speed(&self, axis: usize) -> f64 {
        if (3..6).contains(&axis) {
            self.angular_speed
        } else {
            self.linear_speed
        }
    }

    /// What a jog of `axis` moves: the axis in teleop, else its joint.
    fn jog_target(&mut self, who: &str, axis: usize) -> Option<String> {
        let letter = AXES[axis];
        if self.motion.is_none() {
            self.motion = motion::MotionClient::attach(&self.instance).ok();
        }
        let teleop = self
            .motion
            .as_ref()
            .and_then(|m| m.status().ok())
            .is_some_and(|st| st.teleop_mode);
        if teleop {
            return Some(letter.to_string());
        }
        match self.coordinates.iter().position(|&c| c == letter) {
            Some(j) => Some(j.to_string()),
            None => {
                eprintln!(
                    "panelui: {who}: axis {} is not in [TRAJ]COORDINATES: no joint to jog",
                    letter.to_ascii_uppercase()
                );
                None
            }
        }
    }

    fn jog(&mut self, who: &str, axis: usize, direction: i32) {
        let Some(target) = self.jog_target(who, axis) else {
            return;
        };
        if direction == 0 {
            self.jogging[axis] = 0;
            self.ask(who, &["jog-stop", &target], REQUEST_WAIT);
        } else {
            self.jogging[axis] = direction;
            let vel = (f64::from(direction) * self.speed(axis)).to_string();
            self.ask(who, &["jog-cont", &target, &vel], REQUEST_WAIT);
        }
    }

    /// The running jogs of `axes` again at the new speed.
    fn rejog(&mut self, who: &str, axes: &[usize]) {
        for &a in axes {
            if self.jogging[a] != 0 {
                self.jog(who, a, self.jogging[a]);
            }
        }
    }

    /// MDI mode, then the lines one after the other.
    fn mdi(&self, who: &str, s: &Snapshot, lines: &[String]) -> bool {
        if !self.mode(who, s, "mdi") {
            return false;
        }
        for (i, line) in lines.iter().enumerate() {
            if i > 0 && !self.ask(who, &["wait-done"], MDI_WAIT) {
                return false;
            }
            if !self.ask(who, &["mdi", line], REQUEST_WAIT) {
                return false;
            }
        }
        true
    }

    /// `smart_cycle_start`.
    fn cycle_start(&mut self, who: &str, s: &Snapshot) {
        if !self.mode(who, s, "auto") {
            return;
        }
        match s.program.as_str() {
            "PAUSED" => _ = self.ask(who, &["step"], REQUEST_WAIT),
            "IDLE" => {
                let line = self.restart_line.to_string();
                self.ask(who, &["run", &line], REQUEST_WAIT);
                self.restart_line = self.restart_reset;
            }
            _ => self.restart_line = self.restart_reset,
        }
    }
}

/// A command that is one task request, perhaps after a mode change: the
/// mode (lower case) and the request's words. `None` for the others.
pub fn plain_request(c: &Command) -> Option<(Option<&'static str>, Vec<String>)> {
    let on_off = |b: bool| if b { "on" } else { "off" };
    let manual = Some("manual");
    let (mode, words): (Option<&'static str>, Vec<String>) = match c {
        Command::Mist(on) => (
            None,
            vec!["coolant".into(), "mist".into(), on_off(*on).into()],
        ),
        Command::Flood(on) => (
            None,
            vec!["coolant".into(), "flood".into(), on_off(*on).into()],
        ),
        Command::Estop => (None, vec!["estop".into()]),
        Command::EstopReset => (None, vec!["estop-reset".into()]),
        Command::MachineOn => (None, vec!["machine-on".into()]),
        Command::MachineOff => (None, vec!["machine-off".into()]),
        Command::HomeAll => (manual, vec!["home".into(), "all".into()]),
        Command::UnhomeAll => (manual, vec!["unhome".into(), "all".into()]),
        Command::Home(j) => (manual, vec!["home".into(), j.to_string()]),
        Command::Unhome(j) => (manual, vec!["unhome".into(), j.to_string()]),
        Command::OverrideLimits => (manual, vec!["override-limits".into()]),
        Command::SpindleStop => (manual, vec!["spindle".into(), "0".into(), "off".into()]),
        Command::SpindleFaster => (
            manual,
            vec!["spindle".into(), "0".into(), "increase".into()],
        ),
        Command::SpindleSlower => (
            manual,
            vec!["spindle".into(), "0".into(), "decrease".into()],
        ),
        Command::FeedHold(on) => (None, vec!["feed-hold".into(), on_off(*on).into()]),
        Command::FeedOverride(x) => (None, vec!["feed-override".into(), x.to_string()]),
        Command::RapidOverride(x) => (None, vec!["rapid-override".into(), x.to_string()]),
        Command::SpindleOverride(x) => (
            None,
            vec![
                "spindle".into(),
                "0".into(),
                "override".into(),
                x.to_string(),
            ],
        ),
        Command::MaxVelocity(x) => (None, vec!["max-velocity".into(), x.to_string()]),
        Command::ReloadToolTable => (None, vec!["reload-tool-table".into()]),
        Command::OptionalStop(on) => (None, vec!["optional-stop".into(), on_off(*on).into()]),
        Command::BlockDelete(on) => (None, vec!["block-delete".into(), on_off(*on).into()]),
        Command::Abort => (None, vec!["abort".into()]),
        Command::Pause => (None, vec!["pause".into()]),
        Command::Resume => (None, vec!["resume".into()]),
        _ => return None,
    };
    Some((mode, words))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_snapshot_reads_mode_program_and_spindle() {
        let s = parse_snapshot(
            "machine=ON\nmode=MANUAL\nprogram=IDLE\nspindle-speed=200\nspindle-direction=-1\n",
        )
        .unwrap();
        assert_eq!(
            (s.mode.as_str(), s.program.as_str(), s.spindle_direction),
            ("MANUAL", "IDLE", -1)
        );
        assert!(parse_snapshot("mode=MANUAL\n").is_none());
    }

    #[test]
    fn plain_commands_are_one_task_request() {
        let w = |c: Command| plain_request(&c).map(|(m, w)| (m, w.join(" ")));
        assert_eq!(
            w(Command::Flood(true)),
            Some((None, "coolant flood on".into()))
        );
        assert_eq!(w(Command::Home(2)), Some((Some("manual"), "home 2".into())));
        assert_eq!(
            w(Command::SpindleStop),
            Some((Some("manual"), "spindle 0 off".into()))
        );
        assert_eq!(
            w(Command::FeedHold(false)),
            Some((None, "feed-hold off".into()))
        );
        assert_eq!(
            w(Command::SpindleOverride(0.8)),
            Some((None, "spindle 0 override 0.8".into()))
        );
        assert_eq!(w(Command::SmartCycleStart), None);
        // Each plain request is one task parses.
        for c in [
            Command::Mist(false),
            Command::EstopReset,
            Command::UnhomeAll,
            Command::OverrideLimits,
            Command::SpindleFaster,
            Command::RapidOverride(0.5),
            Command::MaxVelocity(2.0),
            Command::ReloadToolTable,
            Command::OptionalStop(true),
            Command::BlockDelete(false),
            Command::Abort,
            Command::Resume,
        ] {
            let (_, words) = plain_request(&c).unwrap();
            assert!(crate::task::parse_request(&words).is_ok(), "{words:?}");
        }
    }

    #[test]
    fn joints_follow_the_coordinates() {
        let mut r = Runner::new("panelui-unit-no-such-instance".into(), "X Z");
        assert_eq!(
            r.jog_target("t", 2).as_deref(),
            Some("1"),
            "Z is joint 1 of XZ"
        );
        assert_eq!(r.jog_target("t", 0).as_deref(), Some("0"));
        assert_eq!(r.jog_target("t", 1), None, "no Y");
        assert!((r.speed(0) - 100.0 / 60.0).abs() < 1e-12);
        assert!((r.speed(3) - 60.0).abs() < 1e-12);
    }
}
