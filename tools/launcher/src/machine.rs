//! `linuxcnc`: a machine's INI file run headless, as LinuxCNC's `linuxcnc`
//! script runs it, less its GUIs.
//!
//! Order, as LinuxCNC's: the INI file (with `#INCLUDE`s) is read and the
//! working directory becomes its directory; the HAL host starts; the pins
//! task creates appear (`iocontrol.0.*`, `ini.*`); the planner and homing
//! modules load (`[TRAJ]TPMOD`, `[EMCMOT]HOMEMOD`); every `[HAL]HALFILE`
//! runs (TWOPASS if asked), then every `[HAL]HALCMD`; the threads start;
//! the motion controller is configured as task configures it; the
//! `POSTGUI_HALFILE`s run. halui starts before the HAL files when
//! `[HAL]HALUI = halui`; hal-web (the HAL and the machine in a browser)
//! starts after the `POSTGUI_HALFILE`s, where a GUI would, when
//! `[HAL]HALWEB = hal-web [OPTIONS]`. The GUI (`[DISPLAY]DISPLAY`), the
//! `[APPLICATIONS]` and GUI-only HAL lines are not started: the launcher
//! says what it skipped and which pins that left without their partner.
//! It then runs the task's part (e-stop chain, iocontrol, `ini.*` pins,
//! the requests of `task-cmd`) until Ctrl-C or SIGTERM, and brings the
//! machine to its safe state: e-stop, motion disabled, `[HAL]SHUTDOWN`,
//! every module's safe-state hook, everything unloaded.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::Duration;

use hal_core::Instance;
use hal_lang::ini::Ini;
use hal_lang::{Options as HalcmdOptions, Session};

use crate::error::LaunchError;
use crate::hal_side::HalSide;
use crate::halfiles::SearchPath;
use crate::iocontrol::{Flavour, IoControl, IoPins, ToolTable};
use crate::old_format::HalRenames;
use crate::rules::Rules;
use crate::task_pins::TaskPins;

/// The `linuxcnc` command line.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The machine's INI file.
    pub ini_path: PathBuf,
    /// `-k`: keep going after failed HAL commands.
    pub keep_going: bool,
    /// `-v`: say what is done.
    pub verbose: bool,
    /// `-d`: echo every HAL command.
    pub echo: bool,
    /// `-H DIR`: directories searched for HAL files first.
    pub halfile_dirs: Vec<PathBuf>,
    /// `-t TPMOD`: the planner module instead of `[TRAJ]TPMOD`.
    pub tpmod: Option<String>,
    /// `-m HOMEMOD`: the homing module instead of `[EMCMOT]HOMEMOD`.
    pub homemod: Option<String>,
}

/// `linuxcnc`'s usage text.
pub const USAGE: &str = "\
usage: linuxcnc [-v] [-d] [-k] [-i NAME] [-t TPMOD] [-m HOMEMOD] [-H DIR]... MACHINE.ini

Runs a LinuxCNC machine configuration headless: its HAL files, its motion
settings, iocontrol, the task pins and task with its G-code interpreter,
until Ctrl-C or SIGTERM, halui if [HAL]HALUI = halui, and hal-web (the
HAL and the machine in a browser) if [HAL]HALWEB = hal-web [OPTIONS],
after the POSTGUI_HALFILEs, e.g. HALWEB = hal-web --read-only -p 8400.
GUIs are not started; a [DISPLAY]DISPLAY naming a program of the
configuration's own (a path such as ./test-ui.py, or a program in its bin/
directory) runs as LinuxCNC runs it, PROGRAM -ini INIFILE [ARGS], without
the POSTGUI_HALFILEs (a GUI's to run), and when it exits the machine stops
and linuxcnc exits with its status. Send the machine
task requests with task-cmd (estop-reset, machine-on, tool-change, coolant,
mode, open, run, mdi, status; gcode-run runs a program through task) and
motion commands with motion-cmd.

options:
  -v          say what is done
  -d          echo every HAL command
  -k          keep going after a failed HAL command
  -t TPMOD    trajectory planner module (default [TRAJ]TPMOD or tpmod)
  -m HOMEMOD  homing module (default [EMCMOT]HOMEMOD or homemod)
  -H DIR      look for HAL files in DIR first (may be repeated)
  -i, --instance NAME
              the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help  print this help and exit
  --version   print the version and exit

examples:
  cd configs/sim/mill && linuxcnc mill.ini
  task-cmd estop-reset && task-cmd machine-on   (from a second shell)";

/// Parses `linuxcnc`'s arguments.
pub fn parse_args(args: &[String]) -> Result<Options, LaunchError> {
    let mut o = Options::default();
    let mut i = 0;
    let mut ini = None;
    while let Some(a) = args.get(i) {
        let value = |i: usize| {
            args.get(i + 1)
                .cloned()
                .ok_or_else(|| LaunchError::OptionValue { option: a.clone() })
        };
        match a.as_str() {
            "-v" => o.verbose = true,
            "-d" => o.echo = true,
            "-k" => o.keep_going = true,
            "-r" => {}
            "-t" => {
                o.tpmod = Some(value(i)?);
                i += 1;
            }
            "-m" => {
                o.homemod = Some(value(i)?);
                i += 1;
            }
            "-H" => {
                o.halfile_dirs.push(PathBuf::from(value(i)?));
                i += 1;
            }
            "-l" => return Err(LaunchError::LastConfig),
            s if s.starts_with('-') => {
                return Err(LaunchError::UnknownOption {
                    option: s.to_string(),
                })
            }
            s => {
                if ini.replace(PathBuf::from(s)).is_some() {
                    return Err(LaunchError::TwoInis {
                        second: s.to_string(),
                    });
                }
            }
        }
        i += 1;
    }
    o.ini_path = ini.ok_or(LaunchError::NoIni)?;
    Ok(o)
}

/// The pins and modules of a machine's HAL side, once its files ran.
pub struct HalStartup {
    /// The rules the session applies.
    pub rules: Rc<RefCell<Rules>>,
    /// iocontrol, with the tool table loaded.
    pub io: IoControl,
    /// iocontrol's pins.
    pub io_pins: IoPins,
    /// The `ini.*` pins (none if the INI file has no `[KINS]JOINTS`).
    pub task_pins: Option<TaskPins>,
    /// The tool table file.
    pub table_path: Option<PathBuf>,
}

/// Reads the INI file and makes its directory the working directory (as
/// LinuxCNC does); exports what HAL files and Tcl scripts use.
pub fn load_ini(path: &Path) -> Result<Ini, LaunchError> {
    // Refused under the name given (not the one a link resolves to) if
    // it is not a regular file.
    hal_core::files::open_regular(path, "INI file").map_err(|e| {
        LaunchError::Ini(hal_lang::ini::IniError::Io {
            origin: None,
            path: path.to_path_buf(),
            source: e.into(),
        })
    })?;
    // Made absolute without resolving links, as LinuxCNC's script does
    // (`pwd`/FILE): a test directory whose INI file is a link to a shared
    // one keeps its own directory as the configuration's.
    let abs = std::path::absolute(path).map_err(|e| LaunchError::read(path, e))?;
    let ini = Ini::load(&abs)?;
    for w in ini.warnings() {
        eprintln!("{w}");
    }
    let dir = ini.dir();
    std::env::set_current_dir(&dir).map_err(|e| LaunchError::read(&dir, e))?;
    std::env::set_var("INI_FILE_NAME", &abs);
    // LinuxCNC's script exports the configuration's directory too
    // (panelui finds _panelui.ini there).
    std::env::set_var("CONFIG_DIR", &dir);
    if let Some(lib) = crate::halfiles::hallib_dir() {
        std::env::set_var("HALLIB_DIR", lib);
    }
    Ok(ini)
}

/// The tool table `[EMCIO]TOOL_TABLE` names (empty if none), where it is
/// written back, and whether it was read completely. As in LinuxCNC, a
/// line that cannot be read is said and left out, and a file that does
/// not exist yet is an empty table (a random changer's write-back
/// creates it); a table with a line left out is never written back, so
/// the line is not lost. A file that cannot be read at all (not a
/// regular file, too large, no permission) stops the start.
fn tool_table(ini: &Ini) -> Result<(ToolTable, Option<PathBuf>, bool), LaunchError> {
    let random = ini.boolean("EMCIO", "RANDOM_TOOLCHANGER")?.unwrap_or(false);
    if let Some(e) = ini.entry("EMCIO", "DB_PROGRAM") {
        eprintln!(
            "{}: note: [EMCIO]DB_PROGRAM (tool database programs) is not supported; using TOOL_TABLE",
            e.origin
        );
    }
    let Some(e) = ini
        .entry("EMCIO", "TOOL_TABLE")
        .filter(|e| !e.value.trim().is_empty())
    else {
        return Ok((ToolTable::empty(random), None, true));
    };
    let path = ini.dir().join(&e.value);
    match ToolTable::load_skipping(&path, random) {
        Ok((t, skipped)) => {
            for line in &skipped {
                eprintln!("{}: warning: {line}: line skipped", e.origin);
            }
            if !skipped.is_empty() {
                eprintln!(
                    "{}: warning: [EMCIO]TOOL_TABLE: {} line(s) of {} could not be read; \
                     the tools on them are not in the table, and the file is not written \
                     back until it reads completely",
                    e.origin,
                    skipped.len(),
                    path.display()
                );
            }
            Ok((t, Some(path), skipped.is_empty()))
        }
        Err(source) if source.is_not_found() => {
            eprintln!(
                "{}: warning: [EMCIO]TOOL_TABLE: {source}: starting with an empty tool table",
                e.origin
            );
            Ok((ToolTable::empty(random), Some(path), true))
        }
        Err(source) => Err(LaunchError::ToolTableAtStart {
            origin: e.origin.clone(),
            source: source.into(),
        }),
    }
}

/// The search path for `[HAL]` files.
pub fn search_path(ini: &Ini, extra: &[PathBuf]) -> SearchPath {
    SearchPath {
        extra: extra.to_vec(),
        ini_dir: ini.dir(),
        lib: crate::halfiles::hallib_dir(),
    }
}

/// The first word of a module setting (`tpmod`, or `homecomp home_parms=1`).
fn module_words(value: &str) -> Vec<String> {
    let mut v = vec!["loadrt".to_string()];
    v.extend(value.split_whitespace().map(str::to_string));
    v
}

/// Creates the task pins, loads the planner and homing modules and runs
/// `[HAL]HALFILE` and `[HAL]HALCMD` on `session`.
pub fn start_hal_side(
    session: &mut Session<'_>,
    ini: &Ini,
    opts: &Options,
    renames: Option<&HalRenames>,
) -> Result<HalStartup, LaunchError> {
    let rules = Rc::new(RefCell::new(Rules::default()));
    if let Some(display) = ini.get("DISPLAY", "DISPLAY") {
        let mut words = display.split_whitespace();
        let program = words.next().unwrap_or("");
        // A GUI's HAL component: AXIS makes axisui, QtVCP the screen's name.
        let comp = match program {
            "axis" => "axisui".to_string(),
            "qtvcp" => words.last().unwrap_or("qtvcp").to_string(),
            other => other.to_string(),
        };
        rules.borrow_mut().add_gui_component(&comp);
    }
    // GUI panels: their pins never exist on a headless machine.
    for (key, glade) in [("EMBED_TAB_COMMAND", false), ("GLADEVCP", true)] {
        for e in ini.all("DISPLAY", key) {
            if let Some(comp) = crate::rules::panel_component(&e.value, glade) {
                rules.borrow_mut().add_gui_component(&comp);
            }
        }
    }
    session.set_filter(rules.clone());
    let flavour = Flavour::from_ini(ini);
    let io_pins = IoPins::create(session.instance(), flavour)?;
    let task_pins = if ini.entry("KINS", "JOINTS").is_some() {
        Some(TaskPins::create(session.instance(), ini)?)
    } else {
        None
    };
    let (table, table_path, complete) = tool_table(ini)?;
    let mut io = IoControl::new(table, table_path.clone());
    io.set_flavour(flavour);
    if !complete {
        io.hold_write_back();
    }
    for (flag, section, key, default) in [
        (&opts.tpmod, "TRAJ", "TPMOD", "tpmod"),
        (&opts.homemod, "EMCMOT", "HOMEMOD", "homemod"),
    ] {
        let value = flag
            .clone()
            .or_else(|| ini.get(section, key).map(str::to_string))
            .unwrap_or_else(|| default.to_string());
        let words = module_words(&value);
        let (file, line) = ini
            .entry(section, key)
            .map(|e| (e.origin.file.to_string(), e.origin.line))
            .unwrap_or_else(|| (ini.name(), 0));
        if !session.run_words_at(Some(&file), line, &words) {
            return Err(LaunchError::Failed(format!(
                "{file}:{line}: [{section}]{key}: cannot load '{value}'"
            )));
        }
        rules.borrow_mut().preloaded(&words[1]);
    }
    let side = HalSide {
        ini,
        search: search_path(ini, &opts.halfile_dirs),
        rules: rules.clone(),
        keep_going: opts.keep_going,
        verbose: opts.verbose,
        renames,
    };
    side.halfiles(session)?;
    side.halcmds(session)?;
    Ok(HalStartup {
        rules,
        io,
        io_pins,
        task_pins,
        table_path,
    })
}

/// What `halrun MACHINE.ini` does, as LinuxCNC's halrun: only the
/// `[HAL]TWOPASS` processing of the `[HAL]HALFILE`s (no task pins, no
/// planner or homing module, no `[HAL]HALCMD`). The caller checks that
/// the INI file asks for TWOPASS ([`asks_for_twopass`]).
pub fn run_twopass(
    session: &mut Session<'_>,
    ini: &Ini,
    opts: &Options,
) -> Result<(), LaunchError> {
    let rules = Rc::new(RefCell::new(Rules::default()));
    session.set_filter(rules.clone());
    let side = HalSide {
        ini,
        search: search_path(ini, &opts.halfile_dirs),
        rules,
        keep_going: opts.keep_going,
        verbose: opts.verbose,
        renames: None,
    };
    side.halfiles(session)
}

/// Whether the INI file sets `[HAL]TWOPASS` (to anything but nothing).
pub fn asks_for_twopass(ini: &Ini) -> bool {
    ini.get("HAL", "TWOPASS")
        .is_some_and(|v| !v.trim().is_empty())
}

/// Starts halui when `[HAL]HALUI` names it, as LinuxCNC's script does:
/// `loadusr -Wn halui halui -ini MACHINE.ini`. Another program named
/// there is not started (it is reported with the GUIs).
fn start_halui(session: &mut Session<'_>, ini: &Ini) -> Result<(), LaunchError> {
    let Some(e) = ini.entry("HAL", "HALUI") else {
        return Ok(());
    };
    if e.value.trim() != "halui" {
        return Ok(());
    }
    let path = ini
        .path()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| ini.name());
    let words: Vec<String> = ["loadusr", "-Wn", "halui", "halui", "-ini", &path]
        .iter()
        .map(|w| w.to_string())
        .collect();
    if session.run_words_at(Some(&e.origin.file), e.origin.line, &words) {
        Ok(())
    } else {
        Err(LaunchError::Failed(format!(
            "{}: [HAL]HALUI = halui: halui did not start",
            e.origin
        )))
    }
}

/// The HAL command that starts hal-web when `[HAL]HALWEB` asks for it:
/// `HALWEB = hal-web [OPTIONS]` becomes `loadusr -Wn hal-web hal-web
/// OPTIONS` (the launcher goes on once it serves). `None` when the key is
/// absent or names another program (reported with the GUIs).
fn halweb_words(ini: &Ini) -> Option<Vec<String>> {
    let e = ini.entry("HAL", "HALWEB")?;
    let mut words = e.value.split_whitespace();
    if words.next() != Some("hal-web") {
        return None;
    }
    let mut cmd: Vec<String> = ["loadusr", "-Wn", "hal-web", "hal-web"]
        .iter()
        .map(|w| w.to_string())
        .collect();
    cmd.extend(words.map(str::to_string));
    Some(cmd)
}

fn start_halweb(session: &mut Session<'_>, ini: &Ini) -> Result<(), LaunchError> {
    let (Some(e), Some(words)) = (ini.entry("HAL", "HALWEB"), halweb_words(ini)) else {
        return Ok(());
    };
    if session.run_words_at(Some(&e.origin.file), e.origin.line, &words) {
        Ok(())
    } else {
        Err(LaunchError::Failed(format!(
            "{}: [HAL]HALWEB = {}: hal-web did not start",
            e.origin, e.value
        )))
    }
}

/// Says what was not started and which pins that left alone.
pub fn report_skipped(ini: &Ini, rules: &Rules, inst: &Instance) {
    let mut lines = Vec::new();
    if let Some(e) = ini
        .entry("DISPLAY", "DISPLAY")
        .filter(|_| crate::display::display_program(ini).is_none())
    {
        lines.push(format!(
            "{}: GUI '{}' ([DISPLAY]DISPLAY)",
            e.origin, e.value
        ));
    }
    if let Some(e) = ini
        .entry("HAL", "HALUI")
        .filter(|e| !e.value.trim().is_empty() && e.value.trim() != "halui")
    {
        lines.push(format!("{}: halui ([HAL]HALUI = {})", e.origin, e.value));
    }
    if let Some(e) = ini
        .entry("HAL", "HALWEB")
        .filter(|e| halweb_words(ini).is_none() && !e.value.trim().is_empty())
    {
        lines.push(format!("{}: hal-web ([HAL]HALWEB = {})", e.origin, e.value));
    }
    for e in ini.all("APPLICATIONS", "APP") {
        lines.push(format!(
            "{}: application '{}' ([APPLICATIONS]APP)",
            e.origin, e.value
        ));
    }
    for s in &rules.skipped {
        let pins = if s.gui_pins.is_empty() {
            String::new()
        } else {
            // A GUI's pins, or halui pins this halui does not have yet.
            format!(" (pins not present here: {})", s.gui_pins.join(", "))
        };
        lines.push(format!("{}: {}{pins}", s.at, s.command));
    }
    if lines.is_empty() {
        return;
    }
    eprintln!("linuxcnc: not started on this headless machine:");
    for l in lines {
        eprintln!("  {l}");
    }
    let orphans = rules.orphans(inst);
    if !orphans.is_empty() {
        eprintln!("linuxcnc: pins left without the GUI partner they were connected to:");
        for (pin, signal, gui) in orphans {
            eprintln!("  {pin} (signal {signal}; {} not created)", gui.join(", "));
        }
    }
}

/// Starts `[DISPLAY]DISPLAY`'s program if it is one the launcher runs:
/// the child, and the status so far (1: it could not start).
fn start_display(ini: &Ini, instance: &str) -> (Option<std::process::Child>, i32) {
    let Some(d) = crate::display::display_program(ini) else {
        return (None, 0);
    };
    let ini_file = std::env::var_os("INI_FILE_NAME")
        .map(PathBuf::from)
        .or_else(|| ini.path().map(Path::to_path_buf))
        .unwrap_or_default();
    match crate::display::start(&d, ini, &ini_file, instance) {
        Ok(child) => (Some(child), 0),
        Err(e) => {
            eprintln!("linuxcnc: {e}");
            (None, 1)
        }
    }
}

/// Runs the machine until Ctrl-C or SIGTERM, or until the display
/// program ([`crate::display`]) exits. Returns the exit status: the
/// display's, as LinuxCNC's script does, else 0 (1 on an error).
pub fn run(opts: &Options) -> i32 {
    match run_machine(opts) {
        Ok(status) => status,
        Err(e) => {
            eprintln!("linuxcnc: {e}");
            1
        }
    }
}

fn run_machine(opts: &Options) -> Result<i32, LaunchError> {
    let ini = load_ini(&opts.ini_path)?;
    // A configuration for an older LinuxCNC runs converted, as
    // LinuxCNC's script runs update_ini on it; its files stay as they are.
    let converted = crate::old_format::convert(&ini, &search_path(&ini, &opts.halfile_dirs))?;
    if let Some(c) = &converted {
        crate::old_format::announce(c, &opts.ini_path);
    }
    let (ini, renames) = match converted {
        Some(c) => (c.ini, Some(c.renames)),
        None => (ini, None),
    };
    let instance = hal_core::instance_from_env();
    eprintln!(
        "Machine configuration directory is '{}'",
        ini.dir().display()
    );
    eprintln!(
        "Machine configuration file is '{}'",
        opts.ini_path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
    );
    let signals = hal_core::userspace::ExitSignals::install()?;
    let mut host = hal_lang::host_process::start_host_own_group(&instance)?;
    let result = run_on_host(&ini, renames.as_ref(), opts, &instance, &signals);
    if let Err(e) = hal_lang::host_process::stop_host(&instance, Duration::from_secs(20)) {
        eprintln!("linuxcnc: stopping the HAL host: {e}");
        let _ = host.kill();
    }
    let _ = host.wait();
    result
}

fn run_on_host(
    ini: &Ini,
    renames: Option<&HalRenames>,
    opts: &Options,
    instance: &str,
    signals: &hal_core::userspace::ExitSignals,
) -> Result<i32, LaunchError> {
    let inst = Instance::attach(instance)?;
    let (mut out, mut err) = (hal_core::stdio::stdout(), std::io::stderr());
    let hopts = HalcmdOptions {
        keep_going: opts.keep_going,
        verbose: opts.verbose,
        ini: Some(ini.clone()),
        // SIGTERM during start-up ends the start: no further command
        // runs, waits and Tcl files end.
        stop: Some(signals.clone()),
        ..HalcmdOptions::default()
    };
    let mut session = Session::new(inst.clone(), hopts, &mut out, &mut err);
    if opts.echo {
        session.run_words(&["echo".to_string()]);
    }
    // LinuxCNC's order: halui starts before the HAL files, which may
    // connect its pins.
    let startup = start_halui(&mut session, ini)
        .and_then(|()| start_hal_side(&mut session, ini, opts, renames));
    if signals.requested() {
        return Err(LaunchError::StoppedDuringStart);
    }
    let startup = startup?;
    if !session.run_words(&["start".to_string()]) {
        return Err(LaunchError::Failed(
            "starting the realtime threads failed".into(),
        ));
    }
    let motion = crate::motion_setup::MotionLink::connect(&inst);
    let mut motion = match motion {
        Some(mut m) => {
            for note in m.configure(ini)? {
                eprintln!("note: {note}");
            }
            Some(m)
        }
        None => {
            eprintln!("note: no motion controller (motmod) is loaded; motion is not configured");
            None
        }
    };
    let side = HalSide {
        ini,
        search: search_path(ini, &opts.halfile_dirs),
        rules: startup.rules.clone(),
        keep_going: opts.keep_going,
        verbose: opts.verbose,
        renames,
    };
    // LinuxCNC's GUIs run the POSTGUI files once their pins exist; its
    // script never does. Here they stand in for the GUI that is not
    // started, but a display program of the configuration's own runs
    // them itself if it wants them, as under LinuxCNC.
    if crate::display::display_program(ini).is_none() {
        side.files_of(&mut session, "POSTGUI_HALFILE")?;
    } else if let Some(e) = ini.entry("HAL", "POSTGUI_HALFILE") {
        eprintln!(
            "note: {}: [HAL]POSTGUI_HALFILE is left to the display program, as LinuxCNC does",
            e.origin
        );
    }
    start_halweb(&mut session, ini)?;
    report_skipped(ini, &startup.rules.borrow(), &inst);
    let mut server = crate::task_socket::TaskServer::bind(instance).map_err(|e| {
        let path = crate::task_socket::socket_path(instance).unwrap_or_default();
        LaunchError::read(&path, e)
    })?;
    if let Some(m) = &mut motion {
        // Task starts in e-stop with motion disabled, in MANUAL mode: as
        // LinuxCNC's task, it goes through its e-stop sequence, then asks
        // motion for free mode (teleop if every joint is homed).
        let _ = m.estop();
        let _ = m.command(crate::motion_setup::manual_mode(m.status().as_ref()));
    }
    // Programs and MDI run through task where there is a motion
    // controller to run them.
    let program = motion
        .is_some()
        .then(|| crate::program::ProgramConfig::from_ini(ini));
    let mut task = crate::task::Task::new(
        startup.io,
        startup.io_pins,
        startup.task_pins,
        motion,
        startup.table_path,
        program,
    );
    task.overrides = crate::task_manual::Overrides::from_ini(ini)?;
    task.spindle_limits = crate::task_spindle::SpindleLimits::from_ini(ini)?;
    task.traj_info = crate::task_stat::TrajInfo::from_ini(ini)?;
    task.joint_info = crate::task_stat_joint::JointInfo::all_from_ini(
        ini,
        task.traj_info.linear_units,
        task.traj_info.angular_units,
    )?;
    let machine = ini.get("EMC", "MACHINE").unwrap_or("(unnamed)");
    eprintln!(
        "linuxcnc: machine '{machine}' runs on HAL instance '{instance}' (e-stop); \
         task-cmd estop-reset, task-cmd machine-on; Ctrl-C stops it"
    );
    let (mut display, mut status) = start_display(ini, instance);
    let cycle = Duration::from_millis(10);
    // A display that could not start ends the run at once (status 1).
    while !signals.requested() && status == 0 {
        for (id, words) in server.poll() {
            task.handle(&mut server, id, &words);
        }
        task.step(&mut server);
        if !inst.host_alive() {
            if let Some(d) = &mut display {
                crate::display::stop(d, Duration::from_secs(5));
            }
            return Err(LaunchError::HostExited);
        }
        if let Some(Ok(Some(done))) = display.as_mut().map(std::process::Child::try_wait) {
            status = crate::display::exit_code(done);
            eprintln!("linuxcnc: the display program exited ({done}); stopping");
            display = None;
            break;
        }
        std::thread::sleep(cycle);
    }
    if let Some(d) = &mut display {
        // Stopped by a signal: the display goes first, as in LinuxCNC.
        crate::display::stop(d, Duration::from_secs(5));
    }
    eprintln!("linuxcnc: stopping: e-stop, motion disabled");
    task.shut_down(&mut server);
    drop(task);
    // The stop was asked for: SHUTDOWN files are how it is done.
    session.opts.stop = None;
    side.files_of(&mut session, "SHUTDOWN")?;
    Ok(status)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halweb_starts_hal_web_with_its_options_only() {
        let words = |text: &str| halweb_words(&Ini::parse(text));
        assert_eq!(
            words("[HAL]\nHALWEB = hal-web --read-only -p 8400\n").unwrap(),
            [
                "loadusr",
                "-Wn",
                "hal-web",
                "hal-web",
                "--read-only",
                "-p",
                "8400"
            ]
        );
        assert_eq!(
            words("[HAL]\nHALWEB = hal-web\n").unwrap(),
            ["loadusr", "-Wn", "hal-web", "hal-web"]
        );
        assert_eq!(words("[HAL]\nHALWEB = webgui --x\n"), None);
        assert_eq!(words("[HAL]\nHALUI = halui\n"), None);
    }
}
