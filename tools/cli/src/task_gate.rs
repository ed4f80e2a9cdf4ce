//! Task is the one authority over a machine started by `linuxcnc`: while
//! its task runs on an instance, `motion-cmd` may not turn motion on or
//! off (that is `task-cmd machine-on`/`machine-off`), and sends nothing
//! but an abort while task runs a program or MDI line (modes AUTO and
//! MDI). Read-only commands (status, watch, wait) stay open, and in
//! MANUAL mode the homing, jogging and setting commands too (task has no
//! requests of its own for them). Without a task (a bare `halrun` with
//! motmod) `motion-cmd` remains the bring-up tool and nothing is gated.

use std::time::Duration;

use hal_launcher::{request, TaskAnswer};
use motion::Command;

use crate::ToolsError;

/// What task says about the instance, if a task runs there: its mode.
fn task_mode(instance: &str) -> Option<String> {
    match request(instance, &["status".to_string()], Duration::from_secs(2)) {
        Ok(TaskAnswer::Done(status)) => Some(
            status
                .lines()
                .find_map(|l| l.strip_prefix("mode: "))
                .unwrap_or("MANUAL")
                .to_string(),
        ),
        _ => None,
    }
}

/// Whether `motion-cmd` may send `cmd` (`None`: a queued move, a
/// compensation table) to the machine on `instance`.
pub fn allow(instance: &str, cmd: Option<&Command>) -> Result<(), ToolsError> {
    if matches!(cmd, Some(Command::Abort)) {
        return Ok(());
    }
    let Some(mode) = task_mode(instance) else {
        return Ok(());
    };
    if matches!(cmd, Some(Command::Enable | Command::Disable)) {
        return Err(ToolsError::TaskOwns {
            instance: instance.to_string(),
            why: "task alone turns the machine on and off: task-cmd machine-on, \
                  task-cmd machine-off"
                .to_string(),
        });
    }
    if mode != "MANUAL" {
        return Err(ToolsError::TaskOwns {
            instance: instance.to_string(),
            why: format!(
                "task is in {mode} mode and runs the machine's programs and MDI lines \
                 (task-cmd mode manual first; abort stays open)"
            ),
        });
    }
    Ok(())
}
