//! What LinuxCNC's task does once the machine runs: the machine state
//! (e-stop, off, on) following the e-stop chain, kept in agreement with
//! motion's (task alone enables motion), iocontrol's cycle, the `ini.*`
//! pins, and the requests `task-cmd` sends (e-stop reset, machine on and
//! off, tool prepare and change, coolant, lube, abort, status; the modes
//! and program requests are in `task_program`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use crate::error::LaunchError;
use crate::iocontrol::{Handshake, IoControl, IoEvent, IoPins, IoRequest, Started, ToolTable};
use crate::motion_setup::MotionLink;
use crate::program::{Program, ProgramConfig};
use crate::task_pins::TaskPins;
use crate::task_socket::{ConnId, TaskServer};

/// A request's answer: its text, or why it was refused.
type Answer = Result<String, LaunchError>;

/// The machine state, as LinuxCNC's task keeps it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MachineState {
    /// E-stop: `user-enable-out` off, motion disabled.
    Estop,
    /// E-stop released, machine off.
    Off,
    /// Machine on: motion enabled.
    On,
}

impl MachineState {
    pub(crate) fn name(self) -> &'static str {
        match self {
            MachineState::Estop => "ESTOP",
            MachineState::Off => "OFF",
            MachineState::On => "ON",
        }
    }
}

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

/// Task's modes, as LinuxCNC's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Jogging and homing (motion-cmd), tool and coolant requests.
    Manual,
    /// Programs: open, run, pause, resume, step.
    Auto,
    /// Lines of G-code typed in.
    Mdi,
}

impl Mode {
    /// The mode's name, as LinuxCNC's.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Manual => "MANUAL",
            Mode::Auto => "AUTO",
            Mode::Mdi => "MDI",
        }
    }
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

/// A request waiting for the HAL side.
#[derive(Debug)]
pub(crate) enum Waiting {
    /// `emc-enable-in` to read TRUE.
    EnableIn { until: Instant },
    /// The prepare handshake; then, for a tool change, the load.
    Prepare { then_load: bool },
    /// The change handshake.
    Change,
    /// Motion to show the coordinated (or, for MANUAL, another) mode.
    Mode { mode: Mode, until: Instant },
    /// The program or MDI line to end.
    Done,
}

/// How long an e-stop reset waits for the chain to close.
const RESET_WAIT: Duration = Duration::from_secs(1);

/// The task: iocontrol, the `ini.*` pins, the machine state, the waiters.
pub struct Task {
    pub(crate) io: IoControl,
    pub(crate) pins: IoPins,
    ini_pins: Option<TaskPins>,
    pub(crate) motion: Option<MotionLink>,
    pub(crate) state: MachineState,
    pub(crate) waiting: Vec<(ConnId, Waiting)>,
    table_path: Option<PathBuf>,
    pub(crate) mode: Mode,
    pub(crate) program: Option<Program>,
    /// AUTO and MDI are allowed before homing.
    pub(crate) no_force_homing: bool,
    /// The overrides task last sent: feed, rapid, maximum velocity.
    pub(crate) overrides: crate::task_manual::Overrides,
    /// The optional-stop and block-delete switches.
    pub(crate) switches: crate::task_panel::Switches,
    /// The spindle override's limits.
    pub(crate) spindle_limits: crate::task_spindle::SpindleLimits,
    /// The INI settings `stat` reports (units, cycle time, speeds).
    pub(crate) traj_info: crate::task_stat::TrajInfo,
    /// What the error channel carries.
    pub(crate) messages: crate::task_messages::MessageLog,
    /// Joints to home once the homing in progress ends.
    pub(crate) pending_homes: crate::task_manual::PendingHomes,
    /// Motion's heartbeat before which its enable flag is not compared
    /// with the machine state (an enable or disable just sent shows in
    /// the snapshot a cycle or two later).
    pub(crate) settle_until: u64,
    /// What task has seen of motion's messages.
    pub(crate) motion_messages: crate::task_motion::MotionMessages,
}

impl Task {
    /// A task in e-stop with `io` on `pins`.
    pub fn new(
        io: IoControl,
        pins: IoPins,
        ini_pins: Option<TaskPins>,
        motion: Option<MotionLink>,
        table_path: Option<PathBuf>,
        program: Option<ProgramConfig>,
    ) -> Task {
        let t = Task {
            io,
            pins,
            ini_pins,
            motion,
            state: MachineState::Estop,
            waiting: Vec::new(),
            mode: Mode::Manual,
            no_force_homing: program.as_ref().is_some_and(|p| p.no_force_homing),
            program: program.map(|p| Program::new(p, table_path.clone())),
            table_path,
            settle_until: 0,
            motion_messages: crate::task_motion::MotionMessages::default(),
            overrides: crate::task_manual::Overrides::default(),
            switches: crate::task_panel::Switches::default(),
            spindle_limits: crate::task_spindle::SpindleLimits::default(),
            traj_info: crate::task_stat::TrajInfo::default(),
            messages: crate::task_messages::MessageLog::default(),
            pending_homes: crate::task_manual::PendingHomes::default(),
        };
        t.pins.write(t.io.outputs());
        t
    }

    /// One cycle: inputs, e-stop chain, handshakes, `ini.*` pins, motion
    /// watch, outputs; answers waiting requests on `server`.
    pub fn step(&mut self, server: &mut TaskServer) {
        let inputs = self.pins.inputs();
        if !inputs.emc_enable_in && self.state != MachineState::Estop {
            self.go_estop();
            eprintln!("task: e-stop: iocontrol.0.emc-enable-in went FALSE");
            self.fail_all(server, || LaunchError::ChainOpened);
        }
        if inputs.emc_enable_in
            && self.state == MachineState::Estop
            && self.io.outputs().user_enable_out
        {
            self.state = MachineState::Off;
        }
        let events = self.io.step(&inputs);
        self.finish_waiters(server, &events, inputs.emc_enable_in);
        self.program_cycle(server, &events);
        if let Some(ip) = &mut self.ini_pins {
            for change in ip.changes() {
                let r = match &mut self.motion {
                    Some(m) => m.apply(&change),
                    None => Err(LaunchError::NoMotion),
                };
                if let Err(e) = r {
                    eprintln!("task: {e}");
                }
            }
        }
        self.watch_motion();
        self.home_pending();
        self.pins.write(self.io.outputs());
    }

    /// Holds back [`Task::watch_motion`] until motion's snapshot shows the
    /// enable or disable just sent.
    pub(crate) fn settle(&mut self) {
        if let Some(s) = self.motion.as_ref().and_then(MotionLink::status) {
            self.settle_until = s.heartbeat + 3;
        }
    }

    fn go_estop(&mut self) {
        self.pending_homes.clear();
        let _ = self.io.request(&IoRequest::EstopOn);
        if let Some(m) = &mut self.motion {
            if let Err(source) = m.estop() {
                eprintln!("task: {}", LaunchError::Disabling { source });
            }
        }
        self.settle();
        self.state = MachineState::Estop;
        self.stop_program();
    }

    fn fail_all(&mut self, server: &mut TaskServer, why: impl Fn() -> LaunchError) {
        for (id, _) in self.waiting.drain(..) {
            server.reply(id, Err(why()));
        }
    }

    fn finish_waiters(&mut self, server: &mut TaskServer, events: &[IoEvent], enable_in: bool) {
        let waiting = std::mem::take(&mut self.waiting);
        for (id, w) in waiting {
            match w {
                Waiting::EnableIn { .. } if enable_in => {
                    self.answer(server, id, Ok("e-stop released; machine off".into()));
                }
                Waiting::EnableIn { until } if Instant::now() > until => {
                    self.answer(server, id, Err(LaunchError::ChainOpen))
                }
                Waiting::Prepare { then_load } => {
                    let done = events.iter().find_map(|e| match e {
                        IoEvent::Prepared { tool } => Some(*tool),
                        _ => None,
                    });
                    match (done, then_load) {
                        (None, _) => self.waiting.push((id, Waiting::Prepare { then_load })),
                        (Some(tool), false) => {
                            self.answer(server, id, Ok(format!("tool {tool} prepared")))
                        }
                        (Some(_), true) => match self.io.request(&IoRequest::Load) {
                            Ok(Started::Done) => self.answer(server, id, Ok(self.in_spindle())),
                            Ok(Started::Waiting(_)) => self.waiting.push((id, Waiting::Change)),
                            Err(e) => self.answer(server, id, Err(e.into())),
                        },
                    }
                }
                Waiting::Change => {
                    let fault = events.iter().find_map(|e| match e {
                        IoEvent::ChangeFaulted { reason } => Some(*reason),
                        _ => None,
                    });
                    if let Some(reason) = fault {
                        self.answer(server, id, Err(LaunchError::ToolchangerFault { reason }));
                    } else if events.iter().any(|e| matches!(e, IoEvent::Changed { .. })) {
                        self.answer(server, id, Ok(self.in_spindle()));
                    } else {
                        self.waiting.push((id, Waiting::Change));
                    }
                }
                Waiting::Mode { mode, until } => match self.mode_reached(mode, until) {
                    Some(answer) => self.answer(server, id, answer),
                    None => self.waiting.push((id, Waiting::Mode { mode, until })),
                },
                other => self.waiting.push((id, other)),
            }
        }
    }

    pub(crate) fn in_spindle(&self) -> String {
        format!("tool {} in spindle", self.io.tool_in_spindle())
    }

    pub(crate) fn require_on(&self) -> Result<(), LaunchError> {
        if self.state == MachineState::On {
            Ok(())
        } else {
            Err(LaunchError::NotOn {
                state: self.state.name(),
            })
        }
    }

    /// Takes a request; answers at once or when its handshake ends.
    pub fn handle(&mut self, server: &mut TaskServer, id: ConnId, words: &[String]) {
        let req = match parse_request(words) {
            Ok(r) => r,
            Err(e) => return server.reply(id, Err(e)),
        };
        if req == TaskRequest::Abort {
            for (waiter, w) in std::mem::take(&mut self.waiting) {
                match w {
                    Waiting::EnableIn { .. } => self.waiting.push((waiter, w)),
                    _ => server.reply(waiter, Err(LaunchError::Aborted)),
                }
            }
        }
        let result = self.start(&req, id);
        self.pins.write(self.io.outputs());
        if let Some(r) = result {
            server.reply(id, r);
        }
    }

    /// Answers a waiting request once the outputs it changed are on the
    /// pins, so a client reading them after the answer sees them.
    pub(crate) fn answer(&mut self, server: &mut TaskServer, id: ConnId, result: Answer) {
        self.pins.write(self.io.outputs());
        server.reply(id, result);
    }

    /// Starts a request: `Some` answer now, `None` when it waits.
    fn start(&mut self, req: &TaskRequest, id: ConnId) -> Option<Answer> {
        match req {
            TaskRequest::Estop => {
                self.go_estop();
                Some(Ok("e-stop".into()))
            }
            TaskRequest::EstopReset => {
                let _ = self.io.request(&IoRequest::EstopOff);
                // LinuxCNC's task aborts on the way out of e-stop: nothing
                // queued or jogging before it survives the reset.
                if let Some(m) = &mut self.motion {
                    let _ = m.abort();
                }
                self.waiting.push((
                    id,
                    Waiting::EnableIn {
                        until: Instant::now() + RESET_WAIT,
                    },
                ));
                None
            }
            TaskRequest::MachineOn => Some(self.machine_on()),
            TaskRequest::MachineOff => Some(self.machine_off()),
            TaskRequest::Abort => {
                self.pending_homes.clear();
                if let Some(p) = &mut self.program {
                    p.abort();
                }
                let _ = self.io.request(&IoRequest::Abort);
                Some(match &mut self.motion {
                    Some(m) => m
                        .abort()
                        .map(|()| "aborted".to_string())
                        .map_err(|source| LaunchError::MotionRefused { source }),
                    None => Ok("aborted".to_string()),
                })
            }
            TaskRequest::ToolChange(tool) | TaskRequest::ToolPrepare(tool) => {
                let then_load = matches!(req, TaskRequest::ToolChange(_));
                self.tool_prepare(*tool, then_load, id)
            }
            TaskRequest::ToolLoad => self.tool_load(id),
            TaskRequest::SetTool(tool) => Some(
                self.require_on()
                    .and_then(|()| Ok(self.io.request(&IoRequest::SetNumber { tool: *tool })?))
                    .map(|_| self.in_spindle()),
            ),
            TaskRequest::Mist(on) | TaskRequest::Flood(on) | TaskRequest::Lube(on) => {
                Some(self.switch(req, *on))
            }
            TaskRequest::ReloadToolTable => Some(self.reload_tool_table()),
            TaskRequest::Status => Some(Ok(self.status())),
            TaskRequest::State => Some(Ok(self.state_lines())),
            TaskRequest::Stat => Some(Ok(self.stat_lines())),
            TaskRequest::Messages(seq) => Some(Ok(self.messages.since(*seq))),
            TaskRequest::Message { kind, text } => {
                self.messages.push(*kind, text);
                Some(Ok("message kept".into()))
            }
            TaskRequest::SetDout { .. } | TaskRequest::SetAout { .. } => {
                Some(self.output_request(req))
            }
            TaskRequest::Home(Some(joint)) => Some(self.home_joint(*joint)),
            TaskRequest::Home(None)
            | TaskRequest::Unhome(_)
            | TaskRequest::JogCont { .. }
            | TaskRequest::JogIncr { .. }
            | TaskRequest::JogStop(_)
            | TaskRequest::FeedOverride(_)
            | TaskRequest::RapidOverride(_)
            | TaskRequest::MaxVelocity(_) => Some(self.manual_request(req)),
            TaskRequest::OptionalStop(_)
            | TaskRequest::BlockDelete(_)
            | TaskRequest::Teleop(_)
            | TaskRequest::FeedHold(_)
            | TaskRequest::FeedOverrideEnable(_)
            | TaskRequest::SpindleOverrideEnable(_)
            | TaskRequest::OverrideLimits(_)
            | TaskRequest::ClearProbe => Some(self.panel_request(req)),
            TaskRequest::ToolOffset(o) => Some(self.tool_offset(o)),
            TaskRequest::TrajMode(_) | TaskRequest::AxisLimit { .. } => {
                Some(self.traj_request(req))
            }
            TaskRequest::Spindle { spindle, action } => {
                Some(self.spindle_request(*spindle, *action))
            }
            _ => self.program_request(req, id),
        }
    }

    /// Machine on: refused in e-stop; motion enabled if there is motion.
    /// An enable the controller does not answer in time is undone: a
    /// disable goes into the command ring behind it, so whenever the
    /// controller runs again it ends disabled, as task says.
    fn machine_on(&mut self) -> Answer {
        if self.state == MachineState::Estop {
            return Err(LaunchError::InEstop);
        }
        let r = match &mut self.motion {
            Some(m) => match m.enable() {
                Ok(()) => Ok("machine on".to_string()),
                Err(motion::Reject::Timeout) => {
                    let _ = m.disable();
                    Err(LaunchError::MachineOnUndone {
                        state: self.state.name(),
                    })
                }
                Err(source) => Err(LaunchError::MachineOn { source }),
            },
            None => Ok("machine on (no motion controller is loaded)".to_string()),
        };
        self.settle();
        if r.is_ok() {
            self.state = MachineState::On;
        }
        r
    }

    /// Machine off: motion disabled; from on, the state becomes off.
    fn machine_off(&mut self) -> Answer {
        self.pending_homes.clear();
        if let Some(m) = &mut self.motion {
            let r = m.disable();
            self.settle();
            r.map_err(|source| LaunchError::Disabling { source })?;
        }
        if self.state == MachineState::On {
            self.state = MachineState::Off;
        }
        self.stop_program();
        Ok(format!("machine {}", self.state.name().to_lowercase()))
    }

    /// Prepares `tool` (T*n*), then for a change loads it (M6); answers
    /// when the handshakes are done.
    fn tool_prepare(&mut self, tool: i32, then_load: bool, id: ConnId) -> Option<Answer> {
        if let Err(e) = self.require_on() {
            return Some(Err(e));
        }
        match self.io.request(&IoRequest::Prepare { tool }) {
            Err(e) => Some(Err(e.into())),
            Ok(Started::Waiting(_)) => {
                self.waiting.push((id, Waiting::Prepare { then_load }));
                None
            }
            Ok(Started::Done) if then_load => self.tool_load(id),
            Ok(Started::Done) => Some(Ok(format!("tool {tool} prepared (in the spindle)"))),
        }
    }

    /// Loads the prepared tool (M6); answers when the handshake is done.
    fn tool_load(&mut self, id: ConnId) -> Option<Answer> {
        if let Err(e) = self.require_on() {
            return Some(Err(e));
        }
        match self.io.request(&IoRequest::Load) {
            Ok(Started::Done) => Some(Ok(self.in_spindle())),
            Ok(Started::Waiting(_)) => {
                self.waiting.push((id, Waiting::Change));
                None
            }
            Err(e) => Some(Err(e.into())),
        }
    }

    /// Mist, flood or lube on or off.
    fn switch(&mut self, req: &TaskRequest, on: bool) -> Answer {
        self.require_on()?;
        let (r, what) = match req {
            TaskRequest::Mist(_) => (IoRequest::Mist(on), "mist coolant"),
            TaskRequest::Flood(_) => (IoRequest::Flood(on), "flood coolant"),
            _ => (IoRequest::Lube(on), "lube"),
        };
        let _ = self.io.request(&r);
        Ok(format!("{what} {}", if on { "on" } else { "off" }))
    }

    /// Reads the tool table file again. A file that cannot be read
    /// completely changes nothing, and stops write-backs until it can.
    fn reload_tool_table(&mut self) -> Answer {
        let path = self.table_path.as_ref().ok_or(LaunchError::NoToolTable)?;
        match ToolTable::load(path, self.io.table().random) {
            Ok(t) => {
                self.io.reload(t);
                Ok(format!("tool table {} reloaded", path.display()))
            }
            Err(source) => {
                self.io.hold_write_back();
                Err(LaunchError::ToolTable {
                    path: path.clone(),
                    source,
                })
            }
        }
    }

    /// The state as text.
    pub fn status(&self) -> String {
        let o = self.io.outputs();
        let onoff = |b: bool| if b { "on" } else { "off" };
        let handshake = match self.io.busy() {
            None => "none",
            Some(Handshake::Prepare) => "waiting for tool-prepared",
            Some(Handshake::Change) => "waiting for tool-changed",
            Some(Handshake::StartChange) => "waiting for start-change-ack",
        };
        let mut s = format!(
            "state: {}\nmode: {}\ntool in spindle: {}\nprepared: {}\nhandshake: {handshake}\n\
             coolant: mist {}, flood {}\nlube: {}\n",
            self.state.name(),
            self.mode.name(),
            self.io.tool_in_spindle(),
            self.io
                .prepared_tool()
                .map_or("none".to_string(), |t| t.to_string()),
            onoff(o.coolant_mist),
            onoff(o.coolant_flood),
            onoff(o.lube),
        );
        s.push_str(&match &self.motion {
            Some(m) => m.summary(),
            None => "motion: no motion controller is loaded".into(),
        });
        if let Some(p) = &self.program {
            s.push('\n');
            s.push_str(p.status(self.motion.as_ref()).trim_end());
        }
        s
    }

    /// The safe state at exit: e-stop, motion disabled, coolant off; the
    /// interpreter's parameter file saved.
    pub fn shut_down(&mut self, server: &mut TaskServer) {
        self.go_estop();
        self.pins.write(self.io.outputs());
        self.fail_all(server, || LaunchError::ShuttingDown);
        if let Some(m) = &self.motion {
            if let Err(why) = m.save_positions() {
                eprintln!("task: {why}");
            }
        }
        if let Some(p) = &mut self.program {
            if let Err(why) = p.save_parameters() {
                eprintln!("task: {why}");
            }
        }
    }
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
