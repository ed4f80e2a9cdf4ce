//! `halui`: LinuxCNC's HAL user interface, a user-space component whose
//! pins (`halui.machine.on`, `halui.program.run`, `halui.mdi-command-00`,
//! `halui.joint.0.is-homed`...) let buttons, pendants and panels wired in
//! HAL files drive the machine. It is a client of task, as `task-cmd`
//! is: a button's edge becomes a task request; task's `state` answer and
//! motion's status snapshot drive the status pins.
//!
//! The launcher starts it, as LinuxCNC's script does, with `loadusr -Wn
//! halui halui -ini MACHINE.ini` before the HAL files run, so they can
//! connect its pins; task answers once the HAL files ran, until then the
//! buttons wait.

mod analog;
mod joint_status;
mod logic;
mod panel_pins;
mod panel_state;
mod pins;
mod selection;
mod spindle;

use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::Instance;
use hal_lang::ini::Ini;

use crate::error::LaunchError;
use crate::task::Mode;
use crate::task_manual::Jogged;
use crate::task_socket::{request, TaskAnswer, TaskClientError};
use analog::AnalogJogs;
use logic::{Action, Edges, Override, OverrideCounter, TaskState};
use pins::{HaluiPins, Layout, Status};
use selection::OnSelected;

pub use logic::fuzz_state;

/// How often halui reads its pins and task's state.
const CYCLE: Duration = Duration::from_millis(20);
/// How long a request may take (a mode change waits up to 5 s for motion).
const REQUEST_WAIT: Duration = Duration::from_secs(10);
/// A jog speed change smaller than this is no change.
const SPEED_CHANGE: f64 = 1e-5;

/// `halui`'s usage text.
pub const USAGE: &str = "\
usage: halui [--instance NAME] [-ini MACHINE.ini]

LinuxCNC's HAL user interface: the halui.* pins (machine, e-stop, mode,
program, optional stop, block delete, coolant, lube, homing, joint and
axis jogging, selection, spindle, feed, rapid, spindle and maximum
velocity overrides, [HALUI]MDI_COMMAND) as requests to task, and the
machine's state on its status pins. The launcher (linuxcnc) starts it
when [HAL]HALUI = halui. The INI file is $INI_FILE_NAME if -ini is not
given. Buttons act on a rising edge; a jog button also stops its jog
when released.

options:
  -ini FILE        the machine's INI file
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

pins:
  (N a joint number, L an axis letter of [TRAJ]COORDINATES; in: buttons
  and settings, out: status)
  machine.on/off in, machine.is-on out, machine.units-per-mm float out
  estop.activate/reset in, estop.is-activated out
  mode.manual/auto/mdi in, mode.is-manual/is-auto/is-mdi out
  mode.teleop/joint in: MANUAL mode's jogs by world axis or by joint;
    mode.is-teleop/is-joint out
  program.run/pause/resume/step/stop in, abort in,
    program.is-idle/is-running/is-paused out
  program.optional-stop.on/off in, program.optional-stop.is-on out
  program.block-delete.on/off in, program.block-delete.is-on out
  mist, flood, lube: .on/.off in, .is-on out
  home-all in (when some [JOINT_n]HOME_SEQUENCE is set); joint.N.home/
    unhome in
  joint.N.is-homed, has-fault, on-hard-min-limit, on-hard-max-limit,
    on-soft-min-limit, on-soft-max-limit, override-limits out
  joint.N.plus/minus in: jog at joint.jog-speed (units per minute)
  joint.N.increment float in, joint.N.increment-plus/minus in
  joint.N.analog float in: jog at that fraction of joint.jog-speed while
    outside joint.jog-deadband (float in, 0.2 at start)
  axis.L.plus/minus/increment/increment-plus/increment-minus/analog,
    axis.jog-speed, axis.jog-deadband: the same for world axes (teleop);
    these and axis.L.select exist for all nine letters x..w, as in
    LinuxCNC, and do nothing on an axis the machine lacks
  axis.L.pos-commanded, pos-feedback float out (machine coordinates),
    axis.L.pos-relative float out (less the G5x, G92 and tool offsets)
  joint.N.select in, joint.N.is-selected out, joint.selected u32 out;
    joint.selected.home/unhome/plus/minus/increment-plus/increment-minus
    in and joint.selected.increment float in act on the selected joint;
    joint.selected.is-homed, has-fault, on-*-limit, override-limits out
  axis.L.select in, axis.L.is-selected out, axis.selected u32 out (0 X
    .. 8 W); axis.selected.plus/minus/increment-plus/increment-minus in,
    axis.selected.increment float in
  feed-override, rapid-override, max-velocity: .counts s32 in,
    .count-enable in (TRUE at start), .direct-value in, .scale float in
    (0.1 at start, 0 for max-velocity), .increase/.decrease in, .value
    float out; feed and rapid .reset in; max-velocity in machine units
    per second
  spindle.N.override.*: the same (scale 0.1 at start) with .reset in;
    spindle.N.start/stop/forward/reverse/increase/decrease/brake-on/
    brake-off in, spindle.N.is-on/runs-forward/runs-backward/brake-is-on
    out
  tool.number u32 out, tool.diameter float out,
    tool.length_offset.x .. .w float out
  mdi-command-NN in: runs the NN-th [HALUI]MDI_COMMAND in MDI mode, then
    returns to the mode before; halui-mdi-is-running out: TRUE until it
    (and any line queued behind it) ran
  a held joint.selected.plus/minus (axis.selected.*) moves to a newly
  selected joint (axis); held jogs follow a changed jog-speed";

/// Runs halui with its command line (without the suite's common options,
/// which the binary takes first); returns the exit status.
pub fn main(args: &[String]) -> i32 {
    match run(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("halui: {e}");
            1
        }
    }
}

fn ini_path(args: &[String]) -> Result<std::path::PathBuf, LaunchError> {
    let usage = |why: String| LaunchError::HaluiUsage { why };
    let mut ini = None;
    let mut i = 0;
    while let Some(a) = args.get(i) {
        match a.as_str() {
            "-ini" | "--ini" => {
                let path = args
                    .get(i + 1)
                    .ok_or_else(|| usage(format!("{a} needs a value")))?;
                ini = Some(std::path::PathBuf::from(path));
                i += 1;
            }
            o if o.starts_with('-') => {
                return Err(usage(format!("unknown option '{o}' (see halui --help)")))
            }
            other => {
                return Err(usage(format!(
                    "unexpected argument '{other}' (see halui --help)"
                )))
            }
        }
        i += 1;
    }
    ini.or_else(|| {
        std::env::var_os("INI_FILE_NAME")
            .filter(|v| !v.is_empty())
            .map(std::path::PathBuf::from)
    })
    .ok_or_else(|| usage("no INI file: give -ini MACHINE.ini".into()))
}

fn run(args: &[String]) -> Result<(), LaunchError> {
    // An old-format configuration is read as the launcher reads it.
    let ini = crate::old_format::current_format(Ini::load(&ini_path(args)?)?)?;
    let axes = crate::config::axis_letters(&ini);
    let mdi: Vec<String> = ini
        .all("HALUI", "MDI_COMMAND")
        .map(|e| e.value.clone())
        .collect();
    let layout = Layout {
        joints: crate::config::joint_count(&ini)?,
        axes: &axes,
        mdi_commands: mdi.len(),
        units_per_mm: crate::program::ProgramConfig::from_ini(&ini).user_per_mm,
        spindles: spindle::count(&ini)?,
        home_all: (0..crate::config::joint_count(&ini)?)
            .any(|j| ini.get(&format!("JOINT_{j}"), "HOME_SEQUENCE").is_some()),
    };
    let signals = ExitSignals::install()?;
    let instance = hal_core::instance_from_env();
    let inst = Instance::attach(&instance)?;
    let pins = HaluiPins::create(&inst, &layout)?;
    let mut halui = Halui {
        instance,
        pins,
        mdi,
        edges: Edges::default(),
        analog: AnalogJogs::default(),
        counters: [OverrideCounter::default(); 3],
        mdi_return: None,
        mdi_running: false,
        motion: None,
        said_waiting: false,
        spindle: spindle::SpindleHalui::default(),
        jog_speeds: None,
    };
    while !signals.requested() && inst.host_alive() {
        halui.cycle(&inst);
        std::thread::sleep(CYCLE);
    }
    Ok(())
}

/// Whether a request failed because task went away (the launcher stops).
fn connection_gone(e: &std::io::Error) -> bool {
    use std::io::ErrorKind::*;
    matches!(
        e.kind(),
        ConnectionReset | ConnectionRefused | ConnectionAborted | BrokenPipe | NotFound
    )
}

/// Sends a request to the task of `instance`; a refusal is reported.
/// Returns whether it was done.
fn ask(instance: &str, words: &[&str]) -> bool {
    let owned: Vec<String> = words.iter().map(|w| w.to_string()).collect();
    match request(instance, &owned, REQUEST_WAIT) {
        Ok(TaskAnswer::Done(_)) => true,
        Ok(TaskAnswer::Refused(why)) => {
            eprintln!("halui: {}: {why}", words.join(" "));
            false
        }
        Err(e) => {
            eprintln!("halui: {}: {e}", words.join(" "));
            false
        }
    }
}

/// halui's state between cycles.
struct Halui {
    instance: String,
    pins: HaluiPins,
    /// `[HALUI]MDI_COMMAND`s, in order.
    mdi: Vec<String>,
    edges: Edges,
    /// The analog jog inputs' memory.
    analog: AnalogJogs,
    /// Feed, rapid, max-velocity.
    counters: [OverrideCounter; 3],
    /// The mode to go back to once an `mdi-command-NN` line has run.
    mdi_return: Option<Mode>,
    /// An `mdi-command-NN` line task took has not finished
    /// (`halui.halui-mdi-is-running`).
    mdi_running: bool,
    motion: Option<motion::MotionClient>,
    /// Task's absence was reported.
    said_waiting: bool,
    /// The spindle pins' edges and override counters.
    spindle: spindle::SpindleHalui,
    /// `joint.jog-speed` and `axis.jog-speed` as the held jogs last
    /// started with.
    jog_speeds: Option<[f64; 2]>,
}

fn counter_index(which: Override) -> usize {
    match which {
        Override::Feed => 0,
        Override::Rapid => 1,
        Override::MaxVelocity => 2,
    }
}

impl Halui {
    fn cycle(&mut self, inst: &Instance) {
        let state = self.task_state();
        if self.motion.is_none() {
            self.motion = motion::MotionClient::open(inst).ok();
        }
        let motion = self.motion.as_ref().and_then(|m| m.status().ok());
        self.pins.write(&Status {
            task: state.as_ref(),
            motion: motion.as_ref(),
        });
        let changes = self.edges.changes(&self.pins.buttons());
        let instance = &self.instance;
        self.spindle.cycle(
            &self.pins.spindles,
            motion.as_ref(),
            state.is_some(),
            |words| ask(instance, words),
        );
        let Some(state) = state else { return };
        // Back to the mode an MDI command left, once its line (and any
        // queued after it) ran (checked before this cycle's presses:
        // `state` is from before them).
        if self.mdi_running && state.program == "IDLE" {
            self.mdi_running = false;
            if let Some(mode) = self.mdi_return.take() {
                if state.task_mode() != Some(mode) {
                    self.ask(&["mode", &mode.name().to_ascii_lowercase()]);
                }
            }
        }
        for (index, value) in changes {
            if let Some(action) = self.pins.action(index, value) {
                self.perform(action, &state);
            }
        }
        self.follow_jog_speed(&state);
        let readings = self.pins.analog.readings(|what| self.pins.jog_speed(what));
        for action in self.analog.actions(&readings) {
            self.perform(action, &state);
        }
        for (which, inputs) in self.pins.override_inputs() {
            let current = state.override_value(which);
            if let Some(v) = self.counters[counter_index(which)].target(&inputs, current) {
                self.ask(&[which.request(), &v.to_string()]);
            }
        }
        self.pins.set_mdi_running(self.mdi_running);
    }

    /// Task's state, or `None` while no task answers.
    fn task_state(&mut self) -> Option<TaskState> {
        let words = vec!["state".to_string()];
        match request(&self.instance, &words, REQUEST_WAIT) {
            Ok(TaskAnswer::Done(text)) => {
                self.said_waiting = false;
                match logic::parse_state(&text) {
                    Ok(s) => Some(s),
                    Err(e) => {
                        eprintln!("halui: {e}");
                        None
                    }
                }
            }
            Ok(TaskAnswer::Refused(why)) => {
                eprintln!("halui: state: {why}");
                None
            }
            // No task yet (the HAL files still run), or it just ended.
            Err(TaskClientError::NotRunning { .. }) => None,
            Err(TaskClientError::Io(e)) if connection_gone(&e) => None,
            Err(e) => {
                if !self.said_waiting {
                    eprintln!("halui: {e}");
                    self.said_waiting = true;
                }
                None
            }
        }
    }

    /// Sends a request; a refusal is reported. Returns whether it was
    /// done.
    fn ask(&self, words: &[&str]) -> bool {
        ask(&self.instance, words)
    }

    /// Puts task in `mode` unless it is there.
    fn ensure_mode(&self, state: &TaskState, mode: Mode) -> bool {
        state.task_mode() == Some(mode) || self.ask(&["mode", &mode.name().to_ascii_lowercase()])
    }

    /// The selection buttons act on halui itself; a `selected` button
    /// and an increment jog become the jog (or home) they ask for now.
    /// Empty when nothing is left to ask task for.
    fn resolve_selection(&mut self, action: Action) -> Vec<Action> {
        match action {
            Action::SelectJoint(j) => {
                let before = self.pins.selection.joint();
                self.pins.selection.select_joint(j);
                self.hand_over(Action::SelectedJoint, Jogged::Joint, before, j)
            }
            Action::SelectAxis(a) => {
                let before = self.pins.selection.axis();
                self.pins.selection.select_axis(a);
                self.hand_over(Action::SelectedAxis, Jogged::Axis, before, a)
            }
            Action::SelectedJoint(_) | Action::SelectedAxis(_) => {
                self.pins.selection.resolve(action).into_iter().collect()
            }
            Action::JogIncrement(what, dir) => {
                vec![Action::JogBy(what, dir * self.pins.increment(what))]
            }
            other => vec![other],
        }
    }

    /// A new selection while a `selected` jog button is held moves the
    /// jog over, as LinuxCNC's halui does: the joint (axis) selected
    /// before stops, unless its own plus/minus button holds it, and the
    /// new one jogs in the held direction (plus before minus).
    fn hand_over(
        &self,
        selected: fn(OnSelected) -> Action,
        jogged: fn(i32) -> Jogged,
        before: usize,
        now: usize,
    ) -> Vec<Action> {
        let held = |dir: f64| self.pins.held(selected(OnSelected::JogStart(dir)));
        let dir = if held(1.0) {
            1.0
        } else if held(-1.0) {
            -1.0
        } else {
            return Vec::new();
        };
        let (Ok(before), Ok(now)) = (i32::try_from(before), i32::try_from(now)) else {
            return Vec::new();
        };
        if before == now {
            return Vec::new();
        }
        let old = jogged(before);
        let own = [1.0, -1.0]
            .iter()
            .any(|&d| self.pins.held(Action::JogStart(old, d)));
        let mut out = Vec::new();
        if !own {
            out.push(Action::JogStop(old));
        }
        out.push(Action::JogStart(jogged(now), dir));
        out
    }

    /// A changed `joint.jog-speed` (`axis.jog-speed`) restarts the jogs
    /// its held plus/minus buttons make at the new speed, as LinuxCNC's
    /// halui does. The first cycle only notes the speeds.
    fn follow_jog_speed(&mut self, state: &TaskState) {
        let now = [
            self.pins.jog_speed(Jogged::Joint(0)),
            self.pins.jog_speed(Jogged::Axis(0)),
        ];
        let before = *self.jog_speeds.get_or_insert(now);
        let changed = [0, 1].map(|i| (now[i] - before[i]).abs() > SPEED_CHANGE);
        if changed == [false, false] {
            // Kept as it was, so that a speed creeping by less than
            // SPEED_CHANGE a cycle still counts once it has moved enough.
            return;
        }
        self.jog_speeds = Some(now);
        let changed = |what: Jogged| match what {
            Jogged::Joint(_) => changed[0],
            Jogged::Axis(_) => changed[1],
        };
        for action in self.pins.held_jogs() {
            if let Action::JogStart(what, _) = action {
                if changed(what) {
                    self.request(action, state);
                }
            }
        }
    }

    fn perform(&mut self, action: Action, state: &TaskState) {
        for action in self.resolve_selection(action) {
            self.request(action, state);
        }
    }

    /// Asks task for what one resolved action means.
    fn request(&mut self, action: Action, state: &TaskState) {
        let on_off = |on: bool| if on { "on" } else { "off" };
        // Jog speeds are in machine units per minute, as LinuxCNC's.
        let jog_vel = |what: Jogged| self.pins.jog_speed(what) / 60.0;
        let target = |what: Jogged| match what {
            Jogged::Joint(j) => j.to_string(),
            Jogged::Axis(a) => ["x", "y", "z", "a", "b", "c", "u", "v", "w"]
                .get(usize::try_from(a).unwrap_or(9))
                .map_or_else(|| a.to_string(), |l| l.to_string()),
        };
        match action {
            Action::MachineOn => self.ask(&["machine-on"]),
            Action::MachineOff => self.ask(&["machine-off"]),
            Action::EstopActivate => self.ask(&["estop"]),
            Action::EstopReset => self.ask(&["estop-reset"]),
            // As LinuxCNC's halui: nothing is sent for the mode task is in.
            Action::Mode(m) => self.ensure_mode(state, m),
            Action::Run => self.ensure_mode(state, Mode::Auto) && self.ask(&["run"]),
            Action::Pause => self.ask(&["pause"]),
            Action::Resume => self.ask(&["resume"]),
            Action::Step => self.ask(&["step"]),
            Action::Abort => self.ask(&["abort"]),
            Action::Mist(on) => self.ask(&["coolant", "mist", on_off(on)]),
            Action::Flood(on) => self.ask(&["coolant", "flood", on_off(on)]),
            Action::Lube(on) => self.ask(&["lube", on_off(on)]),
            Action::HomeAll => self.ensure_mode(state, Mode::Manual) && self.ask(&["home", "all"]),
            Action::Home(j) => {
                self.ensure_mode(state, Mode::Manual) && self.ask(&["home", &j.to_string()])
            }
            Action::Unhome(j) => {
                self.ensure_mode(state, Mode::Manual) && self.ask(&["unhome", &j.to_string()])
            }
            Action::JogStart(what, dir) => {
                let vel = (dir * jog_vel(what)).to_string();
                self.ensure_mode(state, Mode::Manual)
                    && self.ask(&["jog-cont", &target(what), &vel])
            }
            Action::JogStop(what) => self.ask(&["jog-stop", &target(what)]),
            Action::JogBy(what, dist) => {
                let vel = jog_vel(what).to_string();
                self.ensure_mode(state, Mode::Manual)
                    && self.ask(&["jog-incr", &target(what), &vel, &dist.to_string()])
            }
            Action::JogMode { teleop } => {
                self.ensure_mode(state, Mode::Manual) && self.ask(&["teleop", on_off(teleop)])
            }
            Action::OptionalStop(on) => self.ask(&["optional-stop", on_off(on)]),
            Action::BlockDelete(on) => self.ask(&["block-delete", on_off(on)]),
            // Resolved by `resolve_selection` before.
            Action::JogIncrement(..)
            | Action::SelectJoint(_)
            | Action::SelectAxis(_)
            | Action::SelectedJoint(_)
            | Action::SelectedAxis(_) => false,
            Action::Mdi(n) => self.mdi_command(n, state),
            Action::OverrideStep(which, dir) => {
                let v = state.override_value(which) + dir * self.pins.override_scale(which);
                self.ask(&[which.request(), &v.max(0.0).to_string()])
            }
            Action::OverrideReset(which) => self.ask(&[which.request(), "1"]),
        };
    }

    /// Back to `before` at once, when task refused the line after the
    /// switch to MDI.
    fn mdi_return_now(&self, before: Option<Mode>) {
        if let Some(mode) = before.filter(|m| *m != Mode::Mdi) {
            self.ask(&["mode", &mode.name().to_ascii_lowercase()]);
        }
    }

    /// `mdi-command-NN`: MDI mode (remembering the mode to go back to),
    /// the line, and back once it ran (or at once when task refuses it).
    fn mdi_command(&mut self, n: usize, state: &TaskState) -> bool {
        let Some(line) = self.mdi.get(n).cloned() else {
            return false;
        };
        let before = state.task_mode();
        if !self.ensure_mode(state, Mode::Mdi) {
            return false;
        }
        let done = self.ask(&["mdi", &line]);
        if done {
            // A line queued behind a running one keeps the first's mode.
            if !self.mdi_running && before != Some(Mode::Mdi) {
                self.mdi_return = before;
            }
            self.mdi_running = true;
        } else if !self.mdi_running {
            self.mdi_return_now(before);
        }
        done
    }
}
