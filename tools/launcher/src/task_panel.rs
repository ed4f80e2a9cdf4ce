//! The operator's switches task keeps, as LinuxCNC's task takes them from
//! a GUI or halui: optional stop (M1 stops the program) and block delete
//! (lines starting with `/` are skipped), each on or off; jogging joint by
//! joint (free mode) or in world coordinates (teleop) while in MANUAL
//! mode; and the lines of the `state` answer that report these, the tool
//! offsets and diameter, and the offsets between machine and relative
//! coordinates.

use motion::Command;

use crate::error::LaunchError;
use crate::task::{Mode, Task, TaskRequest};

type Answer = Result<String, LaunchError>;

/// The optional-stop and block-delete switches. Optional stop starts on
/// and block delete off, as LinuxCNC's interpreter starts them; the
/// operator (a GUI or halui) changes them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Switches {
    /// M1 stops the program as M0 does.
    pub optional_stop: bool,
    /// Lines that start with `/` are skipped.
    pub block_delete: bool,
}

impl Default for Switches {
    fn default() -> Switches {
        Switches {
            optional_stop: true,
            block_delete: false,
        }
    }
}

/// Parses `optional-stop on|off`, `block-delete on|off`, `teleop on|off`,
/// `feed-hold on|off`, `feed-override-enable on|off` and
/// `spindle-override-enable on|off`; `None` when `words` is none of them.
pub fn parse(words: &[&str]) -> Option<Result<TaskRequest, LaunchError>> {
    let (name, rest) = words.split_first()?;
    let make: fn(bool) -> TaskRequest = match *name {
        "optional-stop" => TaskRequest::OptionalStop,
        "block-delete" => TaskRequest::BlockDelete,
        "teleop" => TaskRequest::Teleop,
        "feed-hold" => TaskRequest::FeedHold,
        "feed-override-enable" => TaskRequest::FeedOverrideEnable,
        "spindle-override-enable" => TaskRequest::SpindleOverrideEnable,
        _ => return None,
    };
    Some(match rest {
        ["on"] => Ok(make(true)),
        ["off"] => Ok(make(false)),
        _ => Err(LaunchError::OnOff {
            given: (!rest.is_empty()).then(|| rest.join(" ")),
        }),
    })
}

/// `on` or `off`.
fn on_off(on: bool) -> &'static str {
    if on {
        "on"
    } else {
        "off"
    }
}

/// `enabled` or `disabled`.
fn enabled(on: bool) -> &'static str {
    if on {
        "enabled"
    } else {
        "disabled"
    }
}

/// A row of nine numbers, space-separated, for the `state` answer.
fn row(values: &[f64; 9]) -> String {
    let words: Vec<String> = values.iter().map(f64::to_string).collect();
    words.join(" ")
}

impl Task {
    /// Sends `cmd` to the motion controller.
    fn motion_command(&mut self, cmd: Command) -> Result<(), LaunchError> {
        let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
        m.command(cmd)
            .map_err(|source| LaunchError::MotionRefused { source })
    }

    /// Takes an optional-stop, block-delete, teleop, feed-hold, override
    /// enable, override-limits or clear-probe request.
    pub(crate) fn panel_request(&mut self, req: &TaskRequest) -> Answer {
        match *req {
            TaskRequest::OptionalStop(on) => {
                self.switches.optional_stop = on;
                Ok(format!("optional stop {}", on_off(on)))
            }
            TaskRequest::BlockDelete(on) => {
                self.switches.block_delete = on;
                if let Some(p) = &mut self.program {
                    p.set_block_delete(on);
                }
                Ok(format!("block delete {}", on_off(on)))
            }
            TaskRequest::Teleop(on) => self.teleop(on),
            TaskRequest::FeedHold(on) => {
                self.motion_command(Command::FeedHoldEnable { on })?;
                Ok(format!("feed hold {}", on_off(on)))
            }
            TaskRequest::FeedOverrideEnable(on) => {
                self.motion_command(Command::FeedScaleEnable { on })?;
                Ok(format!("feed override {}", enabled(on)))
            }
            TaskRequest::SpindleOverrideEnable(on) => {
                self.motion_command(Command::SpindleScaleEnable { on })?;
                Ok(format!("spindle override {}", enabled(on)))
            }
            TaskRequest::OverrideLimits(on) => {
                self.mode_filter(req)?;
                // Joint 0: every joint's tripped hard limits, until the
                // next jog ends; a joint below 0 ends the override.
                let joint = if on { 0 } else { -1 };
                self.motion_command(Command::OverrideLimits { joint })?;
                Ok(if on {
                    "limits overridden until the next jog ends"
                } else {
                    "limits override ended"
                }
                .to_string())
            }
            TaskRequest::ClearProbe => {
                // Taken in every state, as LinuxCNC's task takes it.
                self.motion_command(Command::ClearProbeFlags)?;
                Ok("probe tripped flag cleared".to_string())
            }
            _ => Err(LaunchError::Program("not a switch request".into())),
        }
    }

    /// Teleop (`on`: jogs move world axes) or free mode (`off`: jogs move
    /// joints), in MANUAL mode with the machine on. The motion controller
    /// refuses teleop while the kinematics cannot map the joints (not
    /// homed, for kinematics that need it).
    fn teleop(&mut self, on: bool) -> Answer {
        self.require_on()?;
        if self.mode != Mode::Manual {
            return Err(LaunchError::NotManual {
                request: "teleop",
                mode: self.mode.name(),
            });
        }
        let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
        let cmd = if on { Command::Teleop } else { Command::Free };
        m.command(cmd)
            .map_err(|source| LaunchError::MotionRefused { source })?;
        Ok(if on { "teleop mode" } else { "joint mode" }.to_string())
    }

    /// The switch, tool and offset lines of the `state` answer:
    /// `optional-stop` and `block-delete` (0 or 1), `tool-offset` (the
    /// tool length offsets of X Y Z A B C U V W), `tool-diameter` (0 with
    /// no tool), `relative-offset` (what lies between machine and relative
    /// coordinates: G5x, G92 and tool offsets together, per axis),
    /// `g5x-offset` (the active G5x work offset alone, per axis).
    pub(crate) fn panel_state_lines(&self) -> String {
        let [g5x, g92, tool] = self.program.as_ref().map_or([[0.0; 9]; 3], |p| p.offsets());
        let mut relative = [0.0; 9];
        for (i, r) in relative.iter_mut().enumerate() {
            *r = g5x[i] + g92[i] + tool[i];
        }
        let in_spindle = self.io.tool_in_spindle();
        let diameter = self
            .io
            .table()
            .tool(0)
            .filter(|t| in_spindle > 0 && t.number == in_spindle)
            .map_or(0.0, |t| t.diameter);
        format!(
            "optional-stop={}\nblock-delete={}\ntool-offset={}\ntool-diameter={diameter}\n\
             relative-offset={}\ng5x-offset={}\n",
            u8::from(self.switches.optional_stop),
            u8::from(self.switches.block_delete),
            row(&tool),
            row(&relative),
            row(&g5x),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn switch_requests_parse_and_refuse_other_words() {
        assert_eq!(
            parse(&["optional-stop", "on"]).unwrap().unwrap(),
            TaskRequest::OptionalStop(true)
        );
        assert_eq!(
            parse(&["block-delete", "off"]).unwrap().unwrap(),
            TaskRequest::BlockDelete(false)
        );
        assert_eq!(
            parse(&["teleop", "on"]).unwrap().unwrap(),
            TaskRequest::Teleop(true)
        );
        assert_eq!(
            parse(&["feed-hold", "off"]).unwrap().unwrap(),
            TaskRequest::FeedHold(false)
        );
        assert_eq!(
            parse(&["feed-override-enable", "off"]).unwrap().unwrap(),
            TaskRequest::FeedOverrideEnable(false)
        );
        assert_eq!(
            parse(&["spindle-override-enable", "on"]).unwrap().unwrap(),
            TaskRequest::SpindleOverrideEnable(true)
        );
        assert!(parse(&["feed-override-enable", "1"]).unwrap().is_err());
        let words = ["override-limits".to_string()];
        assert_eq!(
            crate::task::parse_request(&words).unwrap(),
            TaskRequest::OverrideLimits(true)
        );
        let words = ["clear-probe".to_string()];
        assert_eq!(
            crate::task::parse_request(&words).unwrap(),
            TaskRequest::ClearProbe
        );
        let words = ["override-limits".to_string(), "off".to_string()];
        assert_eq!(
            crate::task::parse_request(&words).unwrap(),
            TaskRequest::OverrideLimits(false)
        );
        assert!(parse(&["mode", "auto"]).is_none());
        let e = parse(&["teleop", "maybe"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("maybe"), "{e}");
        let e = parse(&["block-delete"]).unwrap().unwrap_err().to_string();
        assert!(e.contains("on or off"), "{e}");
        assert_eq!(
            row(&[1.5, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            "1.5 0 -2 0 0 0 0 0 0"
        );
    }
}
