//! What `task-cmd` and the other clients may ask of task: the request
//! vocabulary and its parser, kept apart from the task that carries the
//! requests out.

use std::path::PathBuf;

use crate::error::LaunchError;
use crate::task::Mode;

/// A request of `task-cmd`.
#[derive(Debug, Clone, PartialEq)]
pub enum TaskRequest {
    /// Assert the e-stop.
    Estop,
    /// Release it (LinuxCNC's "estop reset"): `user-enable-out` on and a
    /// `user-request-enable` pulse; done once `emc-enable-in` reads TRUE.
    EstopReset,
    /// Machine on.
    MachineOn,
    /// Machine off.
    MachineOff,
    /// Stop motion, coolant and tool handshakes.
    Abort,
    /// Prepare and load a tool (T*n* M6).
    ToolChange(i32),
    /// Prepare a tool (T*n*).
    ToolPrepare(i32),
    /// Load the prepared tool (M6).
    ToolLoad,
    /// Declare the tool in the spindle (M61 Q*n*).
    SetTool(i32),
    /// Mist coolant.
    Mist(bool),
    /// Flood coolant.
    Flood(bool),
    /// Lube.
    Lube(bool),
    /// Read the tool table file again.
    ReloadToolTable,
    /// The state as text.
    Status,
    /// Switch mode (MANUAL, AUTO, MDI).
    Mode(Mode),
    /// Open a program.
    Open(PathBuf),
    /// Run the open program from a line (0: the start).
    Run(i32),
    /// Pause the program along its path.
    Pause,
    /// Resume after a pause or M0/M1.
    Resume,
    /// While paused: run to the end of the current line.
    Step,
    /// Run a line of G-code in MDI mode.
    Mdi(String),
    /// Answer once the program or MDI line has ended.
    WaitDone,
    /// Home a joint (`None`: every joint, in HOME_SEQUENCE order).
    Home(Option<i32>),
    /// Forget a joint's home (`None`: every joint).
    Unhome(Option<i32>),
    /// Jog a joint (free mode) or an axis (teleop) until stopped.
    JogCont {
        /// What moves.
        what: crate::task_manual::Jogged,
        /// Signed speed, machine units per second.
        vel: f64,
    },
    /// Jog a joint or an axis by a distance.
    JogIncr {
        /// What moves.
        what: crate::task_manual::Jogged,
        /// Speed, machine units per second.
        vel: f64,
        /// Signed distance.
        dist: f64,
    },
    /// Stop a joint's or an axis's jog.
    JogStop(crate::task_manual::Jogged),
    /// The feed override (1: 100 %).
    FeedOverride(f64),
    /// The rapid override (0..=1).
    RapidOverride(f64),
    /// The tool-tip speed limit, machine units per second.
    MaxVelocity(f64),
    /// The state as `key=value` lines, for programs (halui).
    State,
    /// The optional-stop switch (M1 stops).
    OptionalStop(bool),
    /// The block-delete switch (`/` lines skipped).
    BlockDelete(bool),
    /// MANUAL mode's jogs: world axes (teleop) or joints (free mode).
    Teleop(bool),
    /// Whether `motion.feed-hold` holds the moves (LinuxCNC's feed hold
    /// enable, M53).
    FeedHold(bool),
    /// Whether the feed and rapid overrides apply to the moves queued
    /// next (LinuxCNC's feed override enable, M50).
    FeedOverrideEnable(bool),
    /// Whether the spindle override applies (LinuxCNC's spindle override
    /// enable, M51).
    SpindleOverrideEnable(bool),
    /// Override the joints' tripped hard limits until the next jog ends
    /// (`true`), or end an override (`false`).
    OverrideLimits(bool),
    /// Forget the last probe result (the tripped flag).
    ClearProbe,
    /// A tool's offsets, diameter, angles and orientation in the table.
    ToolOffset(crate::task_tool_offset::ToolOffset),
    /// The trajectory mode (LinuxCNC's traj_mode).
    TrajMode(crate::task_traj::TrajMode),
    /// One soft position limit of a world axis (0..=8).
    AxisLimit {
        /// The world axis.
        axis: usize,
        /// The upper limit (else the lower).
        upper: bool,
        /// The new limit.
        value: f64,
    },
    /// The state as one snapshot of `NAME=KIND:VALUE` lines in
    /// LinuxCNC's names (the Python `linuxcnc.stat`).
    Stat,
    /// Start the interpreter afresh (nothing may run).
    ResetInterpreter,
    /// The messages for the error channel after a number.
    Messages(u64),
    /// An operator message for the error channel (LinuxCNC's kind).
    Message {
        /// OPERATOR_ERROR, OPERATOR_TEXT or OPERATOR_DISPLAY.
        kind: i32,
        /// The text.
        text: String,
    },
    /// Set `motion.digital-out-NN` at once.
    SetDout {
        /// The output number.
        index: i32,
        /// On or off.
        on: bool,
    },
    /// Set `motion.analog-out-NN` at once.
    SetAout {
        /// The output number.
        index: i32,
        /// The value.
        value: f64,
    },
    /// A spindle by hand: start, stop, speed steps, brake, override.
    Spindle {
        /// The spindle number.
        spindle: i32,
        /// What it should do.
        action: crate::task_spindle::SpindleAction,
    },
}

/// Parses `task-cmd`'s words.
pub fn parse_request(words: &[String]) -> Result<TaskRequest, LaunchError> {
    let w: Vec<&str> = words.iter().map(String::as_str).collect();
    let tool = |s: Option<&&str>| -> Result<i32, LaunchError> {
        let s = s.ok_or(LaunchError::MissingTool)?;
        s.parse::<i32>()
            .ok()
            .filter(|t| *t >= 0)
            .ok_or_else(|| LaunchError::BadTool {
                word: s.to_string(),
            })
    };
    let on_off = |s: Option<&&str>| -> Result<bool, LaunchError> {
        match s.copied() {
            Some("on") => Ok(true),
            Some("off") => Ok(false),
            other => Err(LaunchError::OnOff {
                given: other.map(str::to_string),
            }),
        }
    };
    if let Some(switch) = crate::task_panel::parse(&w) {
        return switch;
    }
    if let Some(r) = crate::task_stat::parse(&w) {
        return r;
    }
    if let Some(r) = crate::task_messages::parse(&w) {
        return r;
    }
    if let Some(r) = crate::task_traj::parse(&w) {
        return r;
    }
    if let Some(r) = crate::task_tool_offset::parse(&w) {
        return r;
    }
    Ok(match w.as_slice() {
        ["estop"] => TaskRequest::Estop,
        ["estop-reset"] => TaskRequest::EstopReset,
        ["machine-on"] => TaskRequest::MachineOn,
        ["machine-off"] => TaskRequest::MachineOff,
        ["abort"] => TaskRequest::Abort,
        ["tool-change", rest @ ..] if rest.len() == 1 => {
            TaskRequest::ToolChange(tool(rest.first())?)
        }
        ["tool-prepare", rest @ ..] if rest.len() == 1 => {
            TaskRequest::ToolPrepare(tool(rest.first())?)
        }
        ["tool-load"] => TaskRequest::ToolLoad,
        ["set-tool", rest @ ..] if rest.len() == 1 => TaskRequest::SetTool(tool(rest.first())?),
        ["coolant", "mist", rest @ ..] if rest.len() == 1 => {
            TaskRequest::Mist(on_off(rest.first())?)
        }
        ["coolant", "flood", rest @ ..] if rest.len() == 1 => {
            TaskRequest::Flood(on_off(rest.first())?)
        }
        ["lube", rest @ ..] if rest.len() == 1 => TaskRequest::Lube(on_off(rest.first())?),
        ["reload-tool-table"] => TaskRequest::ReloadToolTable,
        ["reset-interpreter"] => TaskRequest::ResetInterpreter,
        ["status"] => TaskRequest::Status,
        ["mode", "manual"] => TaskRequest::Mode(Mode::Manual),
        ["mode", "auto"] => TaskRequest::Mode(Mode::Auto),
        ["mode", "mdi"] => TaskRequest::Mode(Mode::Mdi),
        ["open", file] => TaskRequest::Open(PathBuf::from(file)),
        ["run"] => TaskRequest::Run(0),
        ["run", line] => {
            TaskRequest::Run(line.parse().ok().filter(|l| *l >= 0).ok_or_else(|| {
                LaunchError::BadLine {
                    word: line.to_string(),
                }
            })?)
        }
        ["pause"] => TaskRequest::Pause,
        ["resume"] => TaskRequest::Resume,
        ["step"] => TaskRequest::Step,
        ["mdi", rest @ ..] if !rest.is_empty() => TaskRequest::Mdi(rest.join(" ")),
        ["wait-done"] => TaskRequest::WaitDone,
        ["state"] => TaskRequest::State,
        ["override-limits"] | ["override-limits", "on"] => TaskRequest::OverrideLimits(true),
        ["override-limits", "off"] => TaskRequest::OverrideLimits(false),
        ["clear-probe"] => TaskRequest::ClearProbe,
        ["spindle", rest @ ..] => crate::task_spindle::parse(rest)?,
        [word @ ("home" | "unhome" | "jog-cont" | "jog-incr" | "jog-stop"), rest @ ..]
        | [word @ ("feed-override" | "rapid-override" | "max-velocity"), rest @ ..] => {
            crate::task_manual::parse(word, rest)?
        }
        _ => return Err(LaunchError::UnknownRequest { words: w.join(" ") }),
    })
}

/// The fuzz body for requests arriving on task's socket: a request line
/// (words separated by 0x1F) through [`parse_request`]; a refusal names
/// the request, and an accepted `message` keeps one line whatever its
/// text.
pub fn fuzz_request(data: &[u8]) {
    let line = String::from_utf8_lossy(data);
    let words = hal_lang::protocol::decode_request(&line);
    match parse_request(&words) {
        Ok(TaskRequest::Message { kind, text }) => {
            let mut log = crate::task_messages::MessageLog::default();
            log.push(kind, &text);
            assert_eq!(log.since(0).lines().count(), 2);
        }
        Ok(_) => {}
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn requests_parse() {
        assert_eq!(
            parse_request(&w("tool-change 3")).unwrap(),
            TaskRequest::ToolChange(3)
        );
        assert_eq!(
            parse_request(&w("coolant flood on")).unwrap(),
            TaskRequest::Flood(true)
        );
        assert_eq!(
            parse_request(&w("lube off")).unwrap(),
            TaskRequest::Lube(false)
        );
        assert!(parse_request(&w("tool-change x")).is_err());
        assert!(parse_request(&w("coolant mist maybe")).is_err());
        assert!(parse_request(&w("fly"))
            .unwrap_err()
            .to_string()
            .contains("unknown request 'fly'"));
    }
}
