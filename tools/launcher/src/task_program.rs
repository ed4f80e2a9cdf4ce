//! Task's modes and the requests that run programs and MDI lines: mode
//! changes with LinuxCNC's rules (AUTO and MDI need the machine on and,
//! unless `[TRAJ]NO_FORCE_HOMING`, homed joints; no mode change while
//! something runs), open, run, pause, resume, step, mdi, wait-done, and
//! the program's share of each task cycle.

use std::time::{Duration, Instant};

use motion::Command;

use crate::error::LaunchError;
use crate::iocontrol::{IoEvent, IoRequest};
use crate::program::{Ended, RunState};
use crate::task::{Mode, Task, TaskRequest, Waiting};
use crate::task_socket::{ConnId, TaskServer};

/// How long a mode change waits for motion to show the mode.
const MODE_WAIT: Duration = Duration::from_secs(5);

type Answer = Result<String, LaunchError>;

fn refused(why: impl Into<String>) -> LaunchError {
    LaunchError::Program(why.into())
}

/// `wait-done`'s answer: how the last run ended.
fn outcome_answer(outcome: Option<&Ended>) -> Answer {
    match outcome {
        Some(Ended::Failed(why)) => Err(refused(why.clone())),
        Some(Ended::Done(what)) => Ok(what.clone()),
        None => Ok("idle".to_string()),
    }
}

impl Task {
    /// The program's share of a task cycle; answers `wait-done` when a
    /// run ends.
    pub(crate) fn program_cycle(&mut self, server: &mut TaskServer, events: &[IoEvent]) {
        let (Some(program), Some(motion)) = (&mut self.program, &mut self.motion) else {
            return;
        };
        let ended = program.cycle(motion, &mut self.io, events, self.switches.optional_stop);
        for text in program.messages.drain(..) {
            self.messages
                .push(crate::task_messages::OPERATOR_DISPLAY, &text);
        }
        if let Some(Ended::Failed(why)) = &ended {
            eprintln!("task: {why}");
            self.messages
                .push(crate::task_messages::OPERATOR_ERROR, why);
            // A failed run stops the machine's moves with a controlled
            // deceleration, stops the spindle and leaves no handshake
            // half done.
            let _ = motion.abort();
            let _ = self.io.request(&IoRequest::Abort);
        }
        if program.settled() {
            let outcome = program.last_end().cloned();
            let waiting = std::mem::take(&mut self.waiting);
            for (id, w) in waiting {
                match w {
                    Waiting::Done => self.answer(server, id, outcome_answer(outcome.as_ref())),
                    other => self.waiting.push((id, other)),
                }
            }
        }
    }

    /// The machine went off or into e-stop: the program stops, the mode
    /// is MANUAL again.
    pub(crate) fn stop_program(&mut self) {
        if let Some(p) = &mut self.program {
            if !p.idle() {
                eprintln!(
                    "task: the program stops: the machine is {}",
                    self.state.name()
                );
            }
            p.abort();
        }
        self.mode = Mode::Manual;
    }

    /// Starts a mode or program request: `Some` answer now, `None` when
    /// it waits.
    pub(crate) fn program_request(&mut self, req: &TaskRequest, id: ConnId) -> Option<Answer> {
        if self.program.is_none() {
            return Some(Err(LaunchError::NoMotion));
        }
        let r = match req {
            TaskRequest::Mode(mode) => return self.switch_mode(*mode, id),
            TaskRequest::WaitDone => {
                if let Some(p) = self.program.as_ref().filter(|p| p.settled()) {
                    return Some(outcome_answer(p.last_end()));
                }
                self.waiting.push((id, Waiting::Done));
                return None;
            }
            TaskRequest::Open(path) => self.open(path),
            TaskRequest::ResetInterpreter => self.reset_interpreter(),
            TaskRequest::Run(line) => self.run(*line),
            TaskRequest::Mdi(text) => self.mdi(text),
            TaskRequest::Pause | TaskRequest::Resume | TaskRequest::Step => self.control(req),
            _ => Err(refused("not a program request")),
        };
        Some(r)
    }

    fn require_mode(&self, mode: Mode) -> Result<(), LaunchError> {
        self.require_on()?;
        if self.mode == mode {
            Ok(())
        } else {
            Err(refused(format!(
                "task is in {} mode (task-cmd mode {} first)",
                self.mode.name(),
                mode.name().to_lowercase()
            )))
        }
    }

    fn open(&mut self, path: &std::path::Path) -> Answer {
        let (Some(p), Some(m)) = (&mut self.program, &self.motion) else {
            return Err(LaunchError::NoMotion);
        };
        let path =
            std::fs::canonicalize(path).map_err(|e| refused(format!("{}: {e}", path.display())))?;
        p.open(&path, m, &self.io)?;
        Ok(format!("opened {}", path.display()))
    }

    fn reset_interpreter(&mut self) -> Answer {
        let (Some(p), Some(m)) = (&mut self.program, &self.motion) else {
            return Err(LaunchError::NoMotion);
        };
        p.reset_interpreter(m, &self.io)?;
        Ok("interpreter reset".into())
    }

    fn run(&mut self, line: i32) -> Answer {
        self.require_mode(Mode::Auto)?;
        let (Some(p), Some(m)) = (&mut self.program, &self.motion) else {
            return Err(LaunchError::NoMotion);
        };
        p.run(line, m, &self.io)?;
        Ok("running".into())
    }

    fn mdi(&mut self, text: &str) -> Answer {
        self.require_mode(Mode::Mdi)?;
        let Some(p) = &mut self.program else {
            return Err(LaunchError::NoMotion);
        };
        p.mdi(text)?;
        Ok(format!("mdi {text}"))
    }

    fn control(&mut self, req: &TaskRequest) -> Answer {
        self.mode_filter(req)?;
        let (Some(p), Some(m)) = (&mut self.program, &mut self.motion) else {
            return Err(LaunchError::NoMotion);
        };
        // Pause and resume are taken with nothing to act on (LinuxCNC's
        // task takes them in every state): the answer says so.
        let state = p.run_state();
        let (r, done) = match req {
            TaskRequest::Pause if state != RunState::Running => (Ok(()), "nothing runs to pause"),
            TaskRequest::Pause => (p.pause(m), "paused"),
            TaskRequest::Resume if !matches!(state, RunState::Paused | RunState::Held) => {
                (Ok(()), "nothing paused to resume")
            }
            TaskRequest::Resume => (p.resume(m), "resumed"),
            _ => (p.step(m), "stepping"),
        };
        r.map(|()| done.to_string()).map_err(LaunchError::from)
    }

    /// Changes mode: refused while something runs; AUTO and MDI put
    /// motion in coordinated mode and answer once it shows it. As in
    /// LinuxCNC, the machine need not be on: motion, disabled, keeps the
    /// mode and enters it when the machine comes on.
    fn switch_mode(&mut self, mode: Mode, id: ConnId) -> Option<Answer> {
        if self.program.as_ref().is_some_and(|p| !p.settled()) {
            return Some(Err(refused(format!(
                "a program or MDI line runs in {} mode (abort it or wait for its end)",
                self.mode.name()
            ))));
        }
        if mode == self.mode {
            return Some(Ok(format!("mode {}", mode.name())));
        }
        let m = self.motion.as_mut()?;
        let status = m.status()?;
        let cmd = if mode == Mode::Manual {
            crate::motion_setup::manual_mode(Some(&status))
        } else {
            if !status.all_homed && !self.no_force_homing {
                return Some(Err(refused(format!(
                    "{} mode needs the machine homed ([TRAJ]NO_FORCE_HOMING is not set)",
                    mode.name()
                ))));
            }
            Command::Coord
        };
        if let Err(r) = m.command(cmd) {
            return Some(Err(refused(format!(
                "mode {}: the motion controller refused {}: {r}",
                mode.name(),
                cmd.name()
            ))));
        }
        if mode != Mode::Manual {
            // Entering AUTO or MDI, LinuxCNC's task aborts motion (nothing
            // runs: a running program refuses the switch above).
            let _ = m.abort_moves();
        }
        self.waiting.push((
            id,
            Waiting::Mode {
                mode,
                until: Instant::now() + MODE_WAIT,
            },
        ));
        None
    }

    /// The answer to a mode change once motion shows the mode (or the
    /// wait ran out); `None` while it waits.
    pub(crate) fn mode_reached(&mut self, mode: Mode, until: Instant) -> Option<Answer> {
        let status = self.motion.as_ref()?.status()?;
        let reached = match mode {
            Mode::Manual => status.mode != "COORD",
            // Disabled (e-stop or off): motion enters COORD once enabled.
            Mode::Auto | Mode::Mdi => matches!(status.mode, "COORD" | "DISABLED"),
        };
        if reached {
            self.mode = mode;
            return Some(Ok(format!("mode {}", mode.name())));
        }
        if Instant::now() > until {
            return Some(Err(refused(format!(
                "mode {}: the motion controller stayed in {} mode",
                mode.name(),
                status.mode
            ))));
        }
        None
    }
}
