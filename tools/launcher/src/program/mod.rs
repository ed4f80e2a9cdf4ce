//! Programs and MDI lines executed by task: the RS274NGC interpreter
//! ([`rs274ngc`]) reads ahead into [`canon::TaskCanon`]'s op queue, and
//! every task cycle the ops go out in program order: moves and planner
//! settings into motion's queue as fast as it takes them, tool and
//! coolant requests to iocontrol once the moves before them have ended,
//! M0/M1 stops and the program end likewise. Where the interpreter needs
//! the world's state (after a tool change, for instance) reading waits
//! until everything before has happened, then it synchronises.

pub mod canon;
mod config;
mod error;
mod input_wait;
mod io_watch;
mod mdi_chain;
mod motion_watch;
mod op;
mod user_m;
mod view;
mod waits;

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use motion::{Command, Reject};
use rs274ngc::{Interp, Status};

use crate::iocontrol::{IoControl, IoEvent, Started};
use crate::motion_setup::MotionLink;
use canon::{Op, TaskCanon};
pub use config::ProgramConfig;
pub use error::ProgramError;
use input_wait::InputWait;
pub use view::ProgramView;

/// Blocks read ahead of motion at most (ops waiting in task).
const READ_AHEAD_OPS: usize = 200;
/// Blocks read in one task cycle at most.
const BLOCKS_PER_CYCLE: usize = 500;

/// Where a program (or MDI line) is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunState {
    /// Nothing runs.
    Idle,
    /// Running.
    Running,
    /// Paused by the operator (motion holds along the path).
    Paused,
    /// Stopped at an M0 or M1 until resumed.
    Held,
}

impl RunState {
    /// The state's name in `task-cmd status`.
    pub fn name(self) -> &'static str {
        match self {
            RunState::Idle => "IDLE",
            RunState::Running => "RUNNING",
            RunState::Paused => "PAUSED",
            RunState::Held => "HELD (M0/M1)",
        }
    }

    /// The state as LinuxCNC's interpreter states name it: a stop at M0
    /// or M1 is PAUSED, as an operator's pause.
    pub fn short_name(self) -> &'static str {
        match self {
            RunState::Idle => "IDLE",
            RunState::Running => "RUNNING",
            RunState::Paused | RunState::Held => "PAUSED",
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ended {
    /// Every block ran.
    Done(String),
    /// Refused or failed, with where and why.
    Failed(String),
}

/// The program side of task.
pub struct Program {
    interp: Interp,
    /// The return code of the interpreter's last error (0: none yet).
    interp_errcode: i32,
    canon: TaskCanon,
    initialised: bool,
    file: Option<PathBuf>,
    state: RunState,
    /// Reading waits until everything queued has happened.
    needs_synch: bool,
    /// The program (or MDI line) has nothing more to read.
    read_done: bool,
    /// An iocontrol handshake started by an op is running.
    io_busy: bool,
    /// MDI lines waiting to run.
    mdi: VecDeque<String>,
    /// Is the run an MDI one.
    is_mdi: bool,
    /// Lines before this one are skipped (run LINE).
    start_line: i32,
    /// The program line of the last block read.
    read_line: i32,
    /// What the last run ended with.
    last_end: Option<Ended>,
    /// The M66 wait in progress.
    input_wait: Option<InputWait>,
    /// When the M19 wait in progress runs out of time.
    orient_deadline: Option<std::time::Instant>,
    /// The user M-code program task waits for.
    user_m_running: Option<user_m::Running>,
    /// The tool table file G10 L0 reads (`[EMCIO]TOOL_TABLE`).
    tool_table: Option<PathBuf>,
    /// User M-code programs interrupted by an abort, not yet reaped.
    abandoned: user_m::Abandoned,
    /// Motion's heartbeat when task last queued a command: motion counts
    /// as idle only in a snapshot taken a few cycles later, which shows
    /// the command in the queue (or done).
    sent_beat: u64,
    /// Motion's fault count when the run started (then as last seen): a
    /// fault reported after it stops the run.
    seen_faults: u64,
    /// The program line motion executed last in this run.
    motion_line: i32,
    /// The MDI line that runs, for messages.
    mdi_text: String,
    /// `[TASK]IO_ERROR`.
    io_error: String,
    /// The program's messages (MSG comments) not yet taken by task.
    pub messages: Vec<String>,
    /// `RS274NGC_STARTUP_CODE`.
    startup_code: Option<String>,
    /// The start-up code is due: at task start and after the
    /// interpreter is reset, before any other line.
    startup_due: bool,
}

impl Program {
    /// A program side for the machine `config` describes, whose tool
    /// table file (G10 L0 reads it again) is `tool_table`.
    pub fn new(config: ProgramConfig, tool_table: Option<PathBuf>) -> Program {
        let mut canon = TaskCanon::new(config.user_per_mm, config.axis_mask);
        canon.user_m = user_m::UserMCodes::scan(&config.user_m_dirs);
        canon.tool_change_position = config.tool_change_position;
        canon.rates = config.axis_rates;
        Program {
            canon,
            interp: Interp::new(config.interp),
            interp_errcode: 0,
            initialised: false,
            file: None,
            state: RunState::Idle,
            needs_synch: false,
            read_done: true,
            io_busy: false,
            mdi: VecDeque::new(),
            is_mdi: false,
            start_line: 0,
            read_line: 0,
            last_end: None,
            sent_beat: 0,
            seen_faults: 0,
            motion_line: 0,
            mdi_text: String::new(),
            io_error: config.io_error,
            input_wait: None,
            user_m_running: None,
            orient_deadline: None,
            tool_table,
            abandoned: user_m::Abandoned::default(),
            messages: Vec::new(),
            startup_due: config.startup_code.is_some(),
            startup_code: config.startup_code,
        }
    }

    /// Whether nothing runs (no program, no MDI line).
    pub fn idle(&self) -> bool {
        self.state == RunState::Idle
    }

    /// Where the program (or MDI line) is.
    pub fn run_state(&self) -> RunState {
        self.state
    }

    /// Whether nothing runs and no MDI line waits.
    pub fn settled(&self) -> bool {
        self.idle() && self.mdi.is_empty()
    }

    /// The spindle speed (S) in effect in the interpreter.
    pub fn active_speed(&self) -> f64 {
        self.interp.active_codes().speed
    }

    /// What the last run ended with, if one ended.
    pub fn last_end(&self) -> Option<&Ended> {
        self.last_end.as_ref()
    }

    /// Takes the machine's state into the canon and synchronises the
    /// interpreter (initialising it the first time: parameter file).
    fn synch(&mut self, motion: &MotionLink, io: &IoControl) -> Result<(), ProgramError> {
        let status = motion.status().ok_or(ProgramError::NoMotionStatus)?;
        let (tools, slot) = tool_entries(io);
        let probe = (status.traj.probe_tripped, status.traj.probed);
        self.canon
            .refresh(status.traj.goal, tools, slot, status.io, probe);
        self.canon.toolchanger = io.toolchanger_fault();
        if !self.initialised {
            self.interp
                .init(&mut self.canon)
                .map_err(|source| ProgramError::Interpreter {
                    doing: "starting the interpreter",
                    source,
                })?;
            self.initialised = true;
        }
        self.interp
            .synch(&mut self.canon)
            .map_err(|source| ProgramError::Interpreter {
                doing: "synchronising the interpreter",
                source,
            })
    }

    /// Opens `path` (the previous program is closed).
    pub fn open(
        &mut self,
        path: &Path,
        motion: &MotionLink,
        io: &IoControl,
    ) -> Result<(), ProgramError> {
        if !self.idle() {
            return Err(ProgramError::Running {
                hint: " (abort it first)",
            });
        }
        self.synch(motion, io)?;
        self.interp.close(&mut self.canon);
        if let Err(e) = self.reopen(path) {
            self.note_error(&e);
            return Err(e);
        }
        self.file = Some(path.to_path_buf());
        Ok(())
    }

    /// Keeps the interpreter's return code of `e`, if it is an
    /// interpreter error (LinuxCNC's `interpreter_errcode` stays until
    /// the next one).
    fn note_error(&mut self, e: &ProgramError) {
        if let Some(code) = e.interp_errcode() {
            self.interp_errcode = code;
        }
    }

    /// Starts the open program, from `line` on: earlier lines run
    /// through the interpreter (their modes, offsets and parameters
    /// hold, as LinuxCNC's run from a line) without moving anything.
    pub fn run(
        &mut self,
        line: i32,
        motion: &MotionLink,
        io: &IoControl,
    ) -> Result<(), ProgramError> {
        if !self.idle() {
            return Err(ProgramError::Running { hint: "" });
        }
        let Some(path) = self.file.clone() else {
            return Err(ProgramError::NoProgram);
        };
        // A program that ran to its end is read again from the start.
        if self.last_end.is_some() {
            self.interp.close(&mut self.canon);
            self.reopen(&path)?;
        }
        self.synch(motion, io)?;
        self.start(false, line);
        self.watch_from(motion);
        Ok(())
    }

    /// Opens `path` in the interpreter.
    fn reopen(&mut self, path: &Path) -> Result<(), ProgramError> {
        self.interp
            .open(path, &mut self.canon)
            .map_err(|source| ProgramError::Open {
                path: path.to_path_buf(),
                source,
            })
    }

    /// Queues an MDI line; it runs when the ones before it have.
    pub fn mdi(&mut self, text: &str) -> Result<(), ProgramError> {
        if !self.idle() && !self.is_mdi {
            return Err(ProgramError::Running {
                hint: " (no MDI until it ends)",
            });
        }
        self.mdi.push_back(text.to_string());
        Ok(())
    }

    fn start(&mut self, mdi: bool, line: i32) {
        self.state = RunState::Running;
        self.is_mdi = mdi;
        self.read_done = false;
        self.needs_synch = false;
        self.start_line = line;
        self.last_end = None;
    }

    /// Pause along the path.
    pub fn pause(&mut self, motion: &mut MotionLink) -> Result<(), ProgramError> {
        // As LinuxCNC's task, a pause is taken in every state; with
        // nothing running, or already held, there is nothing to hold.
        if self.state != RunState::Running {
            return Ok(());
        }
        motion
            .command(Command::Pause)
            .map_err(ProgramError::Motion)?;
        self.state = RunState::Paused;
        Ok(())
    }

    /// Carry on after a pause or an M0/M1.
    pub fn resume(&mut self, motion: &mut MotionLink) -> Result<(), ProgramError> {
        match self.state {
            RunState::Paused | RunState::Held => {
                motion
                    .command(Command::Resume)
                    .map_err(ProgramError::Motion)?;
                self.state = RunState::Running;
                Ok(())
            }
            // Taken in every state, as LinuxCNC's task takes it: with
            // nothing paused, nothing changes.
            _ => Ok(()),
        }
    }

    /// While paused: run to the end of the current line, pause again.
    pub fn step(&mut self, motion: &mut MotionLink) -> Result<(), ProgramError> {
        match self.state {
            RunState::Paused => motion.command(Command::Step).map_err(ProgramError::Motion),
            RunState::Held => {
                motion
                    .command(Command::Resume)
                    .map_err(ProgramError::Motion)?;
                motion
                    .command(Command::Pause)
                    .map_err(ProgramError::Motion)?;
                self.state = RunState::Paused;
                Ok(())
            }
            state => Err(ProgramError::WrongState {
                what: "step needs a paused program",
                state,
            }),
        }
    }

    /// Saves the parameter file (`[RS274NGC]PARAMETER_FILE`), as
    /// LinuxCNC's task does when it exits; nothing if the interpreter
    /// never started.
    pub fn save_parameters(&mut self) -> Result<(), ProgramError> {
        if !self.initialised {
            return Ok(());
        }
        self.interp
            .exit(&mut self.canon)
            .map_err(|source| ProgramError::Interpreter {
                doing: "saving the parameter file",
                source,
            })
    }

    /// Stops everything: the interpreter, the ops not yet carried out,
    /// MDI lines waiting (motion and iocontrol are aborted by task).
    pub fn abort(&mut self) {
        self.interp.abort(&mut self.canon);
        self.canon.ops.clear();
        self.canon.planner_reset();
        self.canon.fault = None;
        self.mdi.clear();
        self.io_busy = false;
        self.input_wait = None;
        self.orient_deadline = None;
        if let Some(running) = self.user_m_running.take() {
            self.abandoned.push(running.interrupt());
        }
        if self.state != RunState::Idle {
            self.last_end = Some(Ended::Failed("aborted".into()));
        }
        self.state = RunState::Idle;
        self.read_done = true;
    }

    /// One task cycle: read ahead, carry out ops, synchronise; returns
    /// how the run ended when it did.
    pub fn cycle(
        &mut self,
        motion: &mut MotionLink,
        io: &mut IoControl,
        events: &[IoEvent],
        optional_stop: bool,
    ) -> Option<Ended> {
        self.canon.optional_stop = optional_stop;
        self.abandoned.reap();
        if self.state == RunState::Idle {
            // As LinuxCNC's task: the start-up code runs as the
            // interpreter's first line.
            let startup = std::mem::take(&mut self.startup_due)
                .then(|| self.startup_code.clone())
                .flatten();
            if let Some(code) = &startup {
                self.mdi.push_front(code.clone());
            }
            let text = self.mdi.pop_front()?;
            if let Err(e) = self.synch(motion, io) {
                return Some(self.fail(e));
            }
            self.start(true, 0);
            self.watch_from(motion);
            self.mdi_text.clone_from(&text);
            if let Err(e) = self.execute_mdi(&text) {
                return Some(self.fail(e));
            }
            // While the machine is off its modal settings hold but it
            // moves nothing: LinuxCNC's task sends none of its moves,
            // dwells or outputs then.
            if startup.is_some() && !motion.status().is_some_and(|s| s.enabled) {
                self.canon.drop_actions_from(0);
            }
        }
        if self.io_busy {
            if let Err(e) = self.io_events(events) {
                return Some(self.fail(e));
            }
        }
        if let Err(e) = self.read_ahead() {
            return Some(self.fail(e));
        }
        let status = motion.status()?;
        if let Err(e) = self.watch_motion(&status) {
            return Some(self.fail(e));
        }
        let motion_idle = status.traj.depth == 0
            && status.in_position
            && status.heartbeat >= self.sent_beat.saturating_add(3);
        match self.carry_out(motion, io, motion_idle) {
            Ok(true) => self.sent_beat = status.heartbeat,
            Ok(false) => {}
            Err(e) => return Some(self.fail(e)),
        }
        let motion_idle = motion_idle && status.heartbeat >= self.sent_beat.saturating_add(3);
        if !motion_idle && self.can_chain_mdi() {
            if let Err(e) = self.chain_next_mdi() {
                return Some(self.fail(e));
            }
            return None;
        }
        let all_done = self.canon.ops.is_empty() && !self.io_busy && motion_idle;
        if self.needs_synch && all_done {
            self.needs_synch = false;
            if let Err(e) = self.synch(motion, io) {
                return Some(self.fail(e));
            }
        }
        if self.read_done && all_done && self.state == RunState::Running {
            if self.is_mdi && !self.mdi.is_empty() {
                self.state = RunState::Idle;
                return None;
            }
            return Some(self.finish());
        }
        None
    }

    fn execute_mdi(&mut self, text: &str) -> Result<(), ProgramError> {
        self.canon.line = 0;
        let r = self.interp.execute_mdi(text.as_bytes(), &mut self.canon);
        self.canon.place_user_m(0, &format!("MDI '{text}'"));
        self.read_done = true;
        if self.canon.has_reload_from(0) {
            self.needs_synch = true;
        }
        match r {
            Ok(Status::ExecuteFinish) => self.needs_synch = true,
            Ok(_) => {}
            Err(source) => {
                return Err(ProgramError::Mdi {
                    text: text.to_string(),
                    source,
                })
            }
        }
        match self.canon.fault.take() {
            Some(what) => Err(ProgramError::Unsupported {
                at: format!("MDI '{text}'"),
                what,
            }),
            None => Ok(()),
        }
    }

    /// Reads and executes blocks while there is room ahead of motion.
    fn read_ahead(&mut self) -> Result<(), ProgramError> {
        let mut blocks = 0;
        while !self.read_done
            && !self.needs_synch
            && self.canon.ops.len() < READ_AHEAD_OPS
            && blocks < BLOCKS_PER_CYCLE
        {
            blocks += 1;
            match self.interp.read(&mut self.canon) {
                Ok(Status::EndFile) => {
                    self.read_done = true;
                    break;
                }
                Ok(_) => {}
                Err(source) => return Err(self.located(source)),
            }
            self.read_line = self.interp.sequence_number();
            // Lines before the start line (run LINE) run through the
            // interpreter, so their modal state holds, but move nothing.
            let skipping = self.read_line < self.start_line;
            let queued = self.canon.ops.len();
            self.canon.line = self.read_line;
            match self.interp.execute(&mut self.canon) {
                Ok(Status::Exit) => self.read_done = true,
                Ok(Status::ExecuteFinish) => self.needs_synch = true,
                Ok(_) => {}
                Err(source) => return Err(self.located(source)),
            }
            if !skipping && self.canon.has_reload_from(queued) {
                self.needs_synch = true;
            }
            if skipping {
                self.canon.drop_actions_from(queued);
            } else if self.canon.has_user_m_from(queued) {
                let at = self.interp.error_location();
                let at = format!("{}:{}", at.file.display(), at.line);
                self.canon.place_user_m(queued, &at);
            }
            if let Some(what) = self.canon.fault.take() {
                return Err(ProgramError::Unsupported {
                    at: self.interp.error_location().to_string(),
                    what,
                });
            }
        }
        Ok(())
    }

    /// An error with the program place it belongs to.
    fn located(&self, source: rs274ngc::InterpError) -> ProgramError {
        ProgramError::Line {
            at: Box::new(self.interp.error_location()),
            source,
        }
    }

    /// Carries out ops in order until one has to wait; true if a command
    /// went to motion.
    fn carry_out(
        &mut self,
        motion: &mut MotionLink,
        io: &mut IoControl,
        motion_idle: bool,
    ) -> Result<bool, ProgramError> {
        let mut sent = false;
        if matches!(self.state, RunState::Held) {
            return Ok(sent);
        }
        while let Some(op) = self.canon.ops.front().cloned() {
            match op {
                Op::Motion(cmd) => match motion.command(cmd) {
                    Ok(()) => sent = true,
                    // A full queue, or an abort (the operator's, just
                    // before this MDI line or run) still bringing the
                    // machine to rest: the move goes next cycle.
                    Err(Reject::QueueFull { .. } | Reject::Aborting) => return Ok(sent),
                    Err(source) => {
                        return Err(ProgramError::MotionAt {
                            at: self.place(command_line(&cmd)),
                            source,
                        })
                    }
                },
                _ if sent || !motion_idle || self.io_busy => return Ok(sent),
                Op::Io(req) => match io.request(&req) {
                    Ok(Started::Done) => {}
                    Ok(Started::Waiting(_)) => self.io_busy = true,
                    Err(e) => return Err(e.into()),
                },
                Op::AfterMoves { command, line } => {
                    motion
                        .command(command)
                        .map_err(|source| ProgramError::MotionAt {
                            at: self.place(line),
                            source,
                        })?;
                    sent = true;
                }
                Op::Stop { optional } => {
                    self.canon.ops.pop_front();
                    if !optional || self.canon.optional_stop {
                        eprintln!(
                            "task: program stop (M{}): task-cmd resume",
                            u8::from(optional)
                        );
                        self.state = RunState::Held;
                        return Ok(sent);
                    }
                    continue;
                }
                Op::WaitInput {
                    index,
                    digital,
                    mode,
                    timeout,
                } => {
                    if !self
                        .input_wait
                        .get_or_insert_with(|| {
                            InputWait::start(index, digital, mode, timeout, motion)
                        })
                        .done(motion, &mut self.canon.input_timeout)
                    {
                        return Ok(sent);
                    }
                    self.input_wait = None;
                }
                Op::ReloadTools { line } => self.reload_tools(io, line)?,
                Op::ProbeCheck { probe, line } => {
                    let status = motion.status().ok_or(ProgramError::NoMotionStatus)?;
                    if !status.traj.probe_tripped {
                        let why = motion::Event::ProbeNoContact {
                            trip_on_clear: probe.trip_on_clear,
                        };
                        return Err(ProgramError::Probe {
                            line,
                            why: why.to_string(),
                        });
                    }
                }
                Op::WaitOrient {
                    spindle,
                    timeout,
                    line,
                } => {
                    if !self.oriented(motion, spindle, timeout, line)? {
                        return Ok(sent);
                    }
                }
                Op::End => self.read_done = true,
                Op::Message(text) => {
                    eprintln!("task: {text}");
                    if self.messages.len() < 256 {
                        self.messages.push(text);
                    }
                }
                Op::UserM {
                    number,
                    program,
                    p,
                    q,
                    at,
                } => {
                    if !self.user_m_done(number, &program, p, q, &at)? {
                        return Ok(sent);
                    }
                }
            }
            self.canon.ops.pop_front();
        }
        Ok(sent)
    }

    /// Where a command of program line `line` came from, for messages:
    /// the MDI line itself in an MDI run (its line number is 0).
    fn place(&self, line: i32) -> String {
        if self.is_mdi {
            format!("MDI '{}'", self.mdi_text)
        } else {
            format!("line {line}")
        }
    }

    fn fail(&mut self, why: ProgramError) -> Ended {
        self.note_error(&why);
        self.abort();
        let e = Ended::Failed(why.to_string());
        self.last_end = Some(e.clone());
        e
    }

    fn finish(&mut self) -> Ended {
        self.state = RunState::Idle;
        let what = if self.is_mdi {
            "MDI done".to_string()
        } else {
            format!(
                "{}: done",
                self.file.as_deref().unwrap_or(Path::new("")).display()
            )
        };
        let e = Ended::Done(what);
        self.last_end = Some(e.clone());
        e
    }

    /// The offsets in effect, machine units per axis: G5x, G92, tool.
    pub fn offsets(&self) -> [[f64; 9]; 3] {
        self.canon.offsets()
    }

    /// The block delete switch: lines starting with `/` are skipped
    /// (read from the next line the interpreter reads).
    pub fn set_block_delete(&mut self, on: bool) {
        self.canon.block_delete = on;
    }
}

/// The motion id (program line) a queued command carries.
fn command_line(cmd: &Command) -> i32 {
    match cmd {
        Command::Line { id, .. }
        | Command::Circle { id, .. }
        | Command::Dwell { id, .. }
        | Command::Probe { id, .. } => *id,
        _ => 0,
    }
}

/// iocontrol's tool table as the interpreter sees it (index 0 the
/// spindle), and the index of the tool in the spindle.
fn tool_entries(io: &IoControl) -> (Vec<rs274ngc::ToolEntry>, i32) {
    let table = io.table();
    let entries: Vec<rs274ngc::ToolEntry> = table
        .slots
        .iter()
        .map(|slot| {
            slot.as_ref()
                .map_or(rs274ngc::ToolEntry::EMPTY, |t| t.entry())
        })
        .collect();
    let spindle = io.tool_in_spindle();
    let slot = if table.random {
        0
    } else {
        entries
            .iter()
            .skip(1)
            .position(|e| e.toolno == spindle && spindle > 0)
            .map_or(0, |i| i as i32 + 1)
    };
    let mut entries = entries;
    if entries.is_empty() {
        entries.push(rs274ngc::ToolEntry::EMPTY);
    }
    // On a non-random changer the tool also sits in the spindle's entry.
    if slot > 0 {
        entries[0] = entries[slot as usize];
    }
    (entries, slot)
}
