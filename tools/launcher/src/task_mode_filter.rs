//! Requests LinuxCNC's task takes in one mode only, and its refusal of
//! them in the others: the request is not done, and LinuxCNC's words for
//! it go to the error channel as well as back to the requester
//! (`can't do that (EMC_TASK_PLAN_STEP:511) in MDI mode`). Overriding
//! the limits is a MANUAL request (jogging off a limit switch); a single
//! step is an AUTO one (it starts or steps the opened program).

use crate::error::LaunchError;
use crate::program::RunState;
use crate::task::{Mode, Task, TaskRequest};
use crate::task_messages::OPERATOR_ERROR;

/// LinuxCNC's command name and number for `req`, and the one mode it is
/// taken in; `None` for a request this filter does not hold back.
fn only_in(req: &TaskRequest) -> Option<(&'static str, u32, Mode)> {
    match req {
        TaskRequest::OverrideLimits(_) => Some(("EMC_JOINT_OVERRIDE_LIMITS", 129, Mode::Manual)),
        TaskRequest::Step => Some(("EMC_TASK_PLAN_STEP", 511, Mode::Auto)),
        _ => None,
    }
}

impl Task {
    /// Refuses `req` outside the one mode LinuxCNC's task takes it in,
    /// with LinuxCNC's words, which are also put on the error channel.
    pub(crate) fn mode_filter(&mut self, req: &TaskRequest) -> Result<(), LaunchError> {
        let Some((command, number, mode)) = only_in(req) else {
            return Ok(());
        };
        if self.mode == mode {
            return Ok(());
        }
        let interp = self
            .program
            .as_ref()
            .map_or("idle", |p| match p.run_state() {
                RunState::Idle if p.settled() => "idle",
                RunState::Idle | RunState::Running => "reading",
                RunState::Paused | RunState::Held => "paused",
            });
        let e = LaunchError::ModeRefused {
            command,
            number,
            mode: self.mode.name(),
            interp,
        };
        self.messages.push(OPERATOR_ERROR, &e.to_string());
        Err(e)
    }
}

/// LinuxCNC's words for a command refused in `mode` (`MANUAL`, `MDI`,
/// `AUTO`; in AUTO they name the interpreter's state `interp`).
pub(crate) fn refusal_text(command: &str, number: u32, mode: &str, interp: &str) -> String {
    match mode {
        "MANUAL" => format!("can't do that ({command}:{number}) in manual mode"),
        "AUTO" => format!("can't do that ({command}) in auto mode with the interpreter {interp}"),
        _ => format!("can't do that ({command}:{number}) in {mode} mode"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_are_in_linuxcnc_words() {
        assert_eq!(
            refusal_text("EMC_TASK_PLAN_STEP", 511, "MDI", "idle"),
            "can't do that (EMC_TASK_PLAN_STEP:511) in MDI mode"
        );
        assert_eq!(
            refusal_text("EMC_JOINT_OVERRIDE_LIMITS", 129, "MANUAL", "idle"),
            "can't do that (EMC_JOINT_OVERRIDE_LIMITS:129) in manual mode"
        );
        assert_eq!(
            refusal_text("EMC_JOINT_OVERRIDE_LIMITS", 129, "AUTO", "paused"),
            "can't do that (EMC_JOINT_OVERRIDE_LIMITS) in auto mode with the interpreter paused"
        );
    }

    #[test]
    fn only_override_limits_and_step_are_held_back() {
        assert_eq!(
            only_in(&TaskRequest::OverrideLimits(false)).map(|f| f.2),
            Some(Mode::Manual)
        );
        assert_eq!(only_in(&TaskRequest::Step).map(|f| f.2), Some(Mode::Auto));
        assert_eq!(only_in(&TaskRequest::Pause), None);
    }
}
