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
pub use crate::task_request::{fuzz_request, parse_request, TaskRequest};
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
    /// Each joint's INI settings `stat.joint` reports.
    pub(crate) joint_info: Vec<crate::task_stat_joint::JointInfo>,
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
            joint_info: Vec::new(),
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
                // In e-stop motion's disable stopped every spindle
                // already: the moves are aborted, no SPINDLE_OFF is sent
                // (as LinuxCNC's task in e-stop).
                let estop = self.state == MachineState::Estop;
                Some(match &mut self.motion {
                    Some(m) => if estop { m.abort_moves() } else { m.abort() }
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
