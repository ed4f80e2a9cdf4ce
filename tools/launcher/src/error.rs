//! The error of the launcher: starting and running a machine, and the
//! answers of task's requests.

use std::path::{Path, PathBuf};

use hal_lang::ini::{IniError, Origin};
use motion::Reject;

/// What a refusal of the motion controller says; a timeout names the
/// likely cause.
fn refusal(reason: &Reject) -> String {
    match reason {
        Reject::Timeout => "the motion controller did not answer: is motion-command-handler \
                            added to a running thread?"
            .to_string(),
        other => other.to_string(),
    }
}

impl From<crate::program::ProgramError> for LaunchError {
    fn from(e: crate::program::ProgramError) -> Self {
        LaunchError::Run(Box::new(e))
    }
}

/// Why the machine could not be started (or stopped cleanly).
#[derive(Debug, thiserror::Error)]
pub enum LaunchError {
    /// The INI file, or a value in it.
    #[error(transparent)]
    Ini(#[from] IniError),
    /// A file named in `[HAL]` is not usable.
    #[error("{origin}: {key} = {spec}: {reason}")]
    HalFile {
        /// Where the INI file names it.
        origin: Origin,
        /// The key (`[HAL]HALFILE`).
        key: String,
        /// The value.
        spec: String,
        /// What is wrong.
        reason: String,
    },
    /// SIGTERM, SIGINT or SIGHUP arrived while the machine was starting:
    /// the start was abandoned and what it started is stopped.
    #[error(
        "stop requested during start-up: the start was abandoned; the HAL host and \
         the programs it started are stopped"
    )]
    StoppedDuringStart,
    /// A HAL file or command failed; its own error was printed above.
    #[error("{0}")]
    Failed(String),
    /// A Tcl file could not be run.
    #[error(transparent)]
    Tcl(#[from] hal_lang::haltcl::HaltclError),
    /// The motion controller refused a setting.
    #[error("{at}: the motion controller refused the setting: {}", refusal(source))]
    Motion {
        /// The INI key.
        at: String,
        /// The controller's answer.
        #[source]
        source: Reject,
    },
    /// A joint's COMP_FILE or COMP_FILE_TYPE is not usable.
    #[error("{at}: {source}")]
    CompFile {
        /// The INI key.
        at: String,
        /// What is wrong with the file.
        #[source]
        source: motion::comp_file::CompFileError,
    },
    /// The HAL instance.
    #[error(transparent)]
    Hal(#[from] hal_core::HalError),
    /// A file could not be read.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: std::io::Error,
    },
    /// Starting the HAL host.
    #[error(transparent)]
    Host(#[from] hal_lang::LangError),
    /// The HAL host went away while the machine ran.
    #[error("the HAL host exited")]
    HostExited,
    /// A HAL file's command failed (its own error was printed above):
    /// the command filter's TWOPASS merging refused a `loadrt`.
    #[error("twopass: loadrt {module}: {reason}")]
    TwoPass {
        /// The module.
        module: String,
        /// What is wrong with its arguments.
        reason: String,
    },
    /// TWOPASS given a `loadrt` without a module (halcmd's message).
    #[error("loadrt requires at least 1 arguments, 0 given")]
    TwoPassNoModule,
    /// An option that needs a value came last.
    #[error("{option} needs a value")]
    OptionValue {
        /// The option.
        option: String,
    },
    /// `-l`, LinuxCNC's last configuration.
    #[error("-l (the last configuration) is not supported: name the INI file")]
    LastConfig,
    /// An option `linuxcnc` does not have.
    #[error("unknown option '{option}'")]
    UnknownOption {
        /// The option.
        option: String,
    },
    /// A second INI file on the command line.
    #[error("more than one INI file given ('{second}')")]
    TwoInis {
        /// The second one.
        second: String,
    },
    /// No INI file on the command line.
    #[error("no INI file given")]
    NoIni,
    /// The motion controller refused a command or did not answer.
    #[error("{}", refusal(source))]
    MotionRefused {
        /// Its answer.
        #[source]
        source: Reject,
    },
    /// A changed `ini.*` pin the motion controller has no setting for.
    #[error("{pin}: not applied, the motion controller has no such setting")]
    NotApplied {
        /// The pin.
        pin: String,
    },
    /// A changed `ini.*` pin's setting the motion controller refused.
    #[error("{pin}: {}", refusal(source))]
    IniPin {
        /// The pin.
        pin: String,
        /// The controller's answer.
        #[source]
        source: Reject,
    },
    /// A task request needs a motion controller and none is loaded.
    #[error("no motion controller is loaded")]
    NoMotion,
    /// Machine on, refused by the motion controller.
    #[error("machine on refused by the motion controller: {}", refusal(source))]
    MachineOn {
        /// The controller's answer.
        #[source]
        source: Reject,
    },
    /// Machine on that the motion controller did not answer in time: the
    /// enable may still be taken later, so a disable was queued behind it
    /// and task stays off (task and motion never disagree).
    #[error(
        "machine on did not complete: the motion controller did not answer in time \
         (its thread stalled?); a disable was queued behind the enable, so motion stays \
         disabled and the machine is {state}"
    )]
    MachineOnUndone {
        /// The machine state task keeps (`OFF`).
        state: &'static str,
    },
    /// Machine off or e-stop, and motion could not be disabled.
    #[error("disabling motion: {}", refusal(source))]
    Disabling {
        /// The controller's answer.
        #[source]
        source: Reject,
    },
    /// A task request that needs the machine on.
    #[error("the machine is {state} (estop-reset and machine-on first)")]
    NotOn {
        /// The machine state (`ESTOP`, `OFF`).
        state: &'static str,
    },
    /// Machine on while in e-stop.
    #[error("the machine is in e-stop (estop-reset first)")]
    InEstop,
    /// A waiting request ended by `abort`.
    #[error("aborted")]
    Aborted,
    /// Waiting requests ended by the e-stop chain opening.
    #[error("aborted: the e-stop chain opened")]
    ChainOpened,
    /// Waiting requests ended by the launcher's shutdown.
    #[error("the machine is shutting down")]
    ShuttingDown,
    /// An e-stop reset the external chain did not follow.
    #[error(
        "e-stop reset sent (user-enable-out TRUE), but iocontrol.0.emc-enable-in \
         stayed FALSE: the external e-stop chain is open"
    )]
    ChainOpen,
    /// The tool changer had faulted, so iocontrol gave the change up
    /// (iov2's `toolchanger-faulted`).
    #[error(
        "the tool change was given up: the tool changer faulted (toolchanger-reason {reason}); \
         clear it with iocontrol.0.toolchanger-clear-fault"
    )]
    ToolchangerFault {
        /// `toolchanger-reason` when the change was given up.
        reason: i32,
    },
    /// iocontrol refused a tool request.
    #[error(transparent)]
    Tool(#[from] crate::iocontrol::IoError),
    /// `reload-tool-table` without a tool table.
    #[error("no [EMCIO]TOOL_TABLE is configured")]
    NoToolTable,
    /// The tool table could not be read again; the old one stays.
    #[error("{source}; the tool table in use stays, and is not written back until the file reads completely")]
    ToolTable {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: crate::iocontrol::tooltable::TableError,
    },
    /// The tool table file could not be read at start.
    #[error("{origin}: [EMCIO]TOOL_TABLE: {source}")]
    ToolTableAtStart {
        /// The INI line naming it.
        origin: Origin,
        /// What went wrong.
        #[source]
        source: crate::iocontrol::tooltable::TableError,
    },
    /// A task request this launcher does not know.
    #[error("unknown request '{words}'")]
    UnknownRequest {
        /// Its words.
        words: String,
    },
    /// `[DISPLAY]DISPLAY`'s program could not be started.
    #[error("{origin}: can't execute DISPLAY program {}: {source}", .program.display())]
    Display {
        /// The program.
        program: std::path::PathBuf,
        /// Where the INI file names it.
        origin: String,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A tool request without its number.
    #[error("missing TOOL number")]
    MissingTool,
    /// A tool number that is not one.
    #[error("TOOL must be a tool number, not '{word}'")]
    BadTool {
        /// The word given.
        word: String,
    },
    /// `run LINE` with a LINE that is not one.
    #[error("LINE must be a line number, not '{word}'")]
    BadLine {
        /// The word given.
        word: String,
    },
    /// A program request refused (the mode, the program's state, the
    /// interpreter's refusal with its place).
    #[error("{0}")]
    Program(String),
    /// A manual request (home, jog, override) with a bad argument.
    #[error("{request}: {why}")]
    BadArgument {
        /// The request.
        request: &'static str,
        /// What is wrong with its argument.
        why: String,
    },
    /// A request LinuxCNC's task takes in one mode only, in another, in
    /// LinuxCNC's words.
    #[error("{}", crate::task_mode_filter::refusal_text(command, *number, mode, interp))]
    ModeRefused {
        /// LinuxCNC's name for the command (`EMC_TASK_PLAN_STEP`).
        command: &'static str,
        /// LinuxCNC's number for it.
        number: u32,
        /// Task's mode.
        mode: &'static str,
        /// The interpreter's state, as LinuxCNC names it in AUTO mode.
        interp: &'static str,
    },
    /// A manual request (home, jog) outside MANUAL mode.
    #[error("{request} needs MANUAL mode (task is in {mode} mode)")]
    NotManual {
        /// The request.
        request: &'static str,
        /// Task's mode.
        mode: &'static str,
    },
    /// Task's `state` answer could not be read (halui).
    #[error("task's state answer: {why}")]
    TaskState {
        /// What is wrong with it.
        why: String,
    },
    /// halui's command line.
    #[error("halui: {why}")]
    HaluiUsage {
        /// What is wrong.
        why: String,
    },
    /// The program side refused a request (its state, the interpreter's
    /// refusal with its place).
    /// Boxed: an interpreter refusal with its place is large.
    #[error(transparent)]
    Run(Box<crate::program::ProgramError>),
    /// z_level_compensation's probe file is not a usable map (`line` 0:
    /// the file as a whole).
    #[error("{}{}: {why}", .path.display(), if *.line > 0 { format!(": line {line}") } else { String::new() })]
    ProbeFile {
        /// The probe file.
        path: PathBuf,
        /// The line (1-based), 0 for the whole file.
        line: usize,
        /// What is wrong.
        why: String,
    },
    /// A user's file (a probe map) could not be read: missing, not a
    /// regular file, too large.
    #[error(transparent)]
    File(#[from] hal_core::files::FileError),
    /// z_level_compensation's command line.
    #[error("z_level_compensation: {why}")]
    ZLevelUsage {
        /// What is wrong.
        why: String,
    },
    /// sim-torch's command line.
    #[error("sim-torch: {why}")]
    SimTorchUsage {
        /// What is wrong.
        why: String,
    },
    /// `[TRAJ]POSITION_FILE` does not hold 16 finite positions.
    #[error("{}: joint {joint}: {why} (positions not restored)", .path.display())]
    PositionFile {
        /// The position file.
        path: PathBuf,
        /// The first joint slot that could not be read.
        joint: usize,
        /// What is wrong.
        why: String,
    },
    /// panelui's command line.
    #[error("{why}")]
    PaneluiUsage {
        /// What is wrong.
        why: String,
    },
    /// A line of panelui's panel file.
    #[error("{}:{line}: {why}", .path.display())]
    PaneluiConfig {
        /// The panel file.
        path: PathBuf,
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        why: String,
    },
    /// The sampler channel panelui reads keycodes from.
    #[error("sampler channel {chan}: {why}")]
    PaneluiSampler {
        /// The channel.
        chan: usize,
        /// What is wrong.
        why: String,
    },
    /// A switch request (coolant, lube) without `on` or `off`.
    #[error("expected on or off, not {given:?}")]
    OnOff {
        /// The word given, if any.
        given: Option<String>,
    },
}

impl LaunchError {
    /// A file read error.
    pub fn read(path: &Path, source: std::io::Error) -> LaunchError {
        LaunchError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
