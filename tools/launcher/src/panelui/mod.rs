//! `panelui`: LinuxCNC's operator-panel program. It reads the keycodes a
//! Mesa 7I73 keypad or `sim_matrix_kb` reports from a `sampler` channel
//! (`loadrt sampler cfg=u`, the keycode netted to `sampler.0.pin.0`), as
//! `halsampler` reads its FIFO, and turns them into button states (see
//! [`panel`]) shown on HAL pins (see [`pins`]) and into commands to
//! task (see [`runner`]), as `_panelui.ini` (see [`config`]) describes.
//!
//! Started by a HAL file with `loadusr -W panelui`; it finds
//! `_panelui.ini` in `$CONFIG_DIR` (the configuration's directory, which
//! the launcher exports) or else in the home directory.

pub mod commands;
pub mod config;
pub mod dialect;
pub mod keys;
pub mod panel;
mod pins;
pub mod runner;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TrySendError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, HalType, Instance, RingReader};

use crate::error::LaunchError;
use commands::Command;
use keys::KeyDecoder;
use panel::Panel;
use runner::{Job, Runner};

pub use config::fuzz_config;

/// How often the FIFO is read when it was empty.
const POLL: Duration = Duration::from_millis(5);
/// How often the periodic check runs.
const PERIODIC: Duration = Duration::from_millis(100);
/// Commands that may wait for task.
const QUEUE: usize = 256;
/// The most bytes a handler file may have.
const HANDLER_LIMIT: u64 = 4 << 20;

/// `panelui`'s usage text.
pub const USAGE: &str = "\
usage: panelui [--instance NAME] [-c CHANNEL] [-n COUNT] [-t] [-d] [-v] [--config FILE]

LinuxCNC's operator panel: reads the keycodes of a Mesa 7I73 style key
matrix (or sim_matrix_kb) from sampler channel CHANNEL (default 0; load
it with 'loadrt sampler cfg=u' and net the keycode to sampler.0.pin.0),
and drives the buttons _panelui.ini describes: their HAL pins and their
commands to task. _panelui.ini is read from $CONFIG_DIR (the directory
of the machine's INI file, which linuxcnc exports), else from the home
directory. Start it from a HAL file with 'loadusr -W panelui'.

options:
  -c CHANNEL       the sampler channel (0..)
  -n COUNT         stop after COUNT samples
  -t               print the sample number before each key line
  -d               print each key and command
  -v               print that and each button read from the file
  --config FILE    read FILE instead of _panelui.ini
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

_panelui.ini:
  [HAL_PREFIX] NAME = PREFIX (default panelui)
  [TOGGLE_BUTTONS] / [MOMENTARY_BUTTONS]: a [[NAME]] section per button
  [RADIO_BUTTONS]: a [[GROUP]] section per group (OUTPUT = S32, U32,
    FLOAT or NONE; DEFAULT = a button of it) with a [[[NAME]]] per button
    (GROUP = GROUP, GROUP_OUTPUT = the group's value when it is chosen)
  a button: KEY = RnCm (row, column 0..7) or NONE; OUTPUT = BIT, S32,
    U32, FLOAT, COMMAND or NONE; TRUE_STATE, FALSE_STATE (the pin's
    values); TRUE_COMMAND, FALSE_COMMAND = NAME, ARGUMENTS...; STATUS_PIN
    = true|false; DEFAULT = true|false
  A toggle button flips on each press, a momentary one is true while
  held, a radio button is its group's one true button once pressed.
  Command names (not case sensitive): mist_on, mist_off, flood_on,
  flood_off, estop, estop_reset, machine_on, machine_off, home_all,
  unhome_all, home_selected J, unhome_selected J, jogging,
  override_limits, spindle_forward_adjust RPM, spindle_reverse_adjust
  RPM, spindle_forward RPM, spindle_reverse RPM, spindle_stop,
  spindle_faster, spindle_slower, set_linear_jog_velocity PER_MIN,
  set_angular_jog_velocity PER_MIN, continuous_jog AXIS DIR,
  incremental_jog AXIS DIR DIST, quill_up Z, feed_hold 0|1,
  feed_override S, rapid_override S, spindle_override S, max_velocity V,
  reload_tooltable, optional_stop 0|1, block_delete 0|1, abort, pause,
  resume, single_block 0|1, smart_cycle_start, re_start LINE,
  set_restart_line LINE, mdi LINE..., mdi_and_return LINE..., mdi_active.
  An unknown name stops panelui at start. Functions of the
  configuration's panelui_handler.py may be named; they are Python,
  which this panelui does not run: pressing their button says so.

pins (PREFIX.):
  NAME, NAME-not     out, a button with OUTPUT BIT/S32/U32/FLOAT:
                     TRUE_STATE and FALSE_STATE, and the other way round
  NAME-state, NAME-state-not
                     bit out, with STATUS_PIN = true: the button's state
  GROUP, GROUP-not   out, a radio group with OUTPUT S32/U32/FLOAT: the
                     chosen button's GROUP_OUTPUT, and it negated (0 for
                     U32)";

/// The command line.
#[derive(Debug, Clone, PartialEq, Default)]
struct Args {
    channel: usize,
    count: Option<u64>,
    tag: bool,
    debug: u8,
    config: Option<PathBuf>,
}

fn parse_args(args: &[String]) -> Result<Args, LaunchError> {
    let usage = |why: String| LaunchError::PaneluiUsage { why };
    let mut a = Args::default();
    let mut i = 0;
    while let Some(w) = args.get(i) {
        let value = |i: usize| {
            args.get(i + 1)
                .ok_or_else(|| usage(format!("{w} needs a value")))
        };
        match w.as_str() {
            "-c" => {
                let v = value(i)?;
                a.channel = v
                    .parse()
                    .map_err(|_| usage(format!("invalid channel number '{v}'")))?;
                i += 1;
            }
            "-n" => {
                let v = value(i)?;
                a.count = Some(
                    v.parse()
                        .map_err(|_| usage(format!("invalid sample count '{v}'")))?,
                );
                i += 1;
            }
            "--config" => {
                a.config = Some(PathBuf::from(value(i)?));
                i += 1;
            }
            "-t" => a.tag = true,
            "-d" => a.debug = a.debug.max(1),
            "-v" => a.debug = 2,
            o if o.starts_with('-') => {
                return Err(usage(format!("unknown option '{o}' (see panelui --help)")))
            }
            other => {
                return Err(usage(format!(
                    "unexpected argument '{other}': panelui prints on standard output \
                     (redirect it to write a file)"
                )))
            }
        }
        i += 1;
    }
    Ok(a)
}

/// The directory panelui reads its files from: `$CONFIG_DIR`, else home.
fn config_dir() -> Option<PathBuf> {
    ["CONFIG_DIR", "HOME"]
        .iter()
        .find_map(|v| std::env::var_os(v).filter(|d| !d.is_empty()))
        .map(PathBuf::from)
}

/// The function names of a handler file's text (`def NAME(`), without
/// private ones and `get_handlers`.
pub fn handler_names(text: &str) -> Vec<String> {
    let mut names: Vec<String> = text
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("def "))
        .filter_map(|rest| rest.split_once('('))
        .map(|(n, _)| n.trim().to_string())
        .filter(|n| !n.is_empty() && !n.starts_with('_') && n != "get_handlers")
        .collect();
    names.dedup();
    names
}

/// The panel file read and checked, with its path.
fn load(args: &Args) -> Result<(PathBuf, config::PanelConfig), LaunchError> {
    let dir = config_dir();
    let path = match (&args.config, &dir) {
        (Some(p), _) => p.clone(),
        (None, Some(d)) => d.join("_panelui.ini"),
        (None, None) => {
            return Err(LaunchError::PaneluiUsage {
                why: "no _panelui.ini: neither CONFIG_DIR nor HOME is set".into(),
            })
        }
    };
    let handler_dir = match &args.config {
        Some(p) => p.parent().map(Path::to_path_buf),
        None => dir,
    };
    let handlers = match handler_dir.map(|d| d.join("panelui_handler.py")) {
        Some(h) if h.is_file() => handler_names(&hal_core::files::read_user_text(
            &h,
            HANDLER_LIMIT,
            "panelui handler",
        )?),
        _ => Vec::new(),
    };
    let text = hal_core::files::read_user_text(&path, hal_core::files::limits::INI, "panel file")?;
    let cfg = config::read(&text, &handlers).map_err(|e| LaunchError::PaneluiConfig {
        path: path.clone(),
        line: e.line,
        why: e.why,
    })?;
    Ok((path, cfg))
}

/// Opens sampler channel `chan`'s FIFO: one u32 column, the keycode.
fn open_sampler(inst: &Instance, chan: usize) -> Result<RingReader, LaunchError> {
    let bad = |why: String| LaunchError::PaneluiSampler { chan, why };
    let first = format!("sampler.{chan}.pin.0");
    match inst.pin(&first)? {
        None => {
            return Err(bad(format!(
                "no pin {first}: load it with 'loadrt sampler cfg=u'"
            )))
        }
        Some(p) if p.hal_type != HalType::U32 => {
            return Err(bad(format!(
                "{first} is {:?}, not u32: panelui needs 'cfg=u'",
                p.hal_type
            )))
        }
        Some(_) => {}
    }
    if inst.pin(&format!("sampler.{chan}.pin.1"))?.is_some() {
        return Err(bad(
            "it samples more than one pin: panelui needs 'cfg=u'".into()
        ));
    }
    let ring = RingReader::open(inst, &format!("sampler.{chan}.fifo"))?;
    if ring.width() != 2 {
        return Err(bad(format!(
            "its FIFO holds {} words a sample, not 2 (number and keycode)",
            ring.width()
        )));
    }
    Ok(ring)
}

/// Runs panelui with its command line (without the suite's common
/// options); returns the exit status.
pub fn main(args: &[String]) -> i32 {
    match run(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("panelui: {e}");
            1
        }
    }
}

/// `[TRAJ]COORDINATES` of `$INI_FILE_NAME`, if it can be read.
fn coordinates() -> String {
    std::env::var_os("INI_FILE_NAME")
        .and_then(|p| hal_lang::ini::Ini::load(Path::new(&p)).ok())
        .and_then(|ini| ini.get("TRAJ", "COORDINATES").map(str::to_string))
        .unwrap_or_default()
}

fn run(args: &[String]) -> Result<(), LaunchError> {
    let args = parse_args(args)?;
    let signals = ExitSignals::install()?;
    let instance = hal_core::instance_from_env();
    let inst = Instance::attach(&instance)?;
    let (path, cfg) = load(&args)?;
    for s in &cfg.unknown_sections {
        println!(
            "panelui: {}: [{s}] is not a section panelui knows: passed over",
            path.display()
        );
    }
    note_handlers(&cfg);
    let (panel, fired) = Panel::new(cfg);
    let comp = inst.new_component("panelui", ComponentKind::User)?;
    let pins = pins::PanelPins::create(&comp, &panel)?;
    let mut ring = open_sampler(&inst, args.channel)?;
    comp.ready()?;
    if args.debug > 0 {
        print_keys(&panel, args.debug);
    }
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = sync_channel::<Job>(QUEUE);
    let mut runner = Runner::new(instance, &coordinates());
    runner.debug = args.debug > 0;
    let worker = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || work(runner, &rx, &stop))
    };
    for f in fired {
        send(&tx, Job::Run(f));
    }
    let mut keys = Keys {
        panel,
        pins,
        decoder: KeyDecoder::default(),
        last_sample: None,
        tag: args.tag,
        debug: args.debug > 0,
    };
    let mut record = [0u64; 2];
    let mut remaining = args.count;
    let mut last_periodic = Instant::now();
    while !signals.requested() && inst.host_alive() && remaining != Some(0) {
        let mut read_any = false;
        while remaining != Some(0) && ring.pop(&mut record) {
            read_any = true;
            remaining = remaining.map(|n| n - 1);
            keys.sample(record, &tx);
        }
        if last_periodic.elapsed() >= PERIODIC {
            last_periodic = Instant::now();
            // A periodic check that finds the queue full is not needed.
            let _ = tx.try_send(Job::Periodic);
        }
        if !read_any {
            std::thread::sleep(POLL);
        }
    }
    stop.store(true, Ordering::Relaxed);
    drop(tx);
    let _ = worker.join();
    Ok(())
}

/// The key side: samples to button states, pins and jobs.
struct Keys {
    panel: Panel,
    pins: pins::PanelPins,
    decoder: KeyDecoder,
    last_sample: Option<u32>,
    /// `-t`: the sample number before each key line.
    tag: bool,
    /// `-d`: a line per key.
    debug: bool,
}

impl Keys {
    /// One sample: its number and its keycode.
    fn sample(&mut self, record: [u64; 2], tx: &SyncSender<Job>) {
        let num = record[0] as u32;
        if self.last_sample.is_some_and(|l| num != l.wrapping_add(1)) {
            println!("overrun");
        }
        self.last_sample = Some(num);
        let Some(ev) = self.decoder.decode(record[1] as u32) else {
            return;
        };
        let tag = if self.tag {
            format!("{} ", num.wrapping_sub(1))
        } else {
            String::new()
        };
        let key = format!("R{}C{}", ev.row, ev.col);
        let Some(fired) = self.panel.key(ev.row, ev.col, ev.pressed) else {
            if self.debug {
                println!("{tag}panelui: no button or command assigned to keycode {key}");
            }
            return;
        };
        self.pins.write(&self.panel);
        if self.debug {
            let b = self
                .panel
                .button_at(ev.row, ev.col)
                .map_or("", |i| self.panel.config().buttons[i].name.as_str());
            let how = if ev.pressed { "Pressed" } else { "Released" };
            println!("{tag}{key} {b} {how}");
        }
        for f in fired {
            send(tx, Job::Run(f));
        }
    }
}

/// Queues a job; a full queue (task has not answered for a long time)
/// drops it, and says so.
fn send(tx: &SyncSender<Job>, job: Job) {
    if let Err(TrySendError::Full(Job::Run(f))) = tx.try_send(job) {
        eprintln!(
            "panelui: {}: task has not taken the commands before it: this one is dropped",
            f.button
        );
    }
}

/// The runner's thread: each job once task answers.
fn work(mut runner: Runner, rx: &Receiver<Job>, stop: &AtomicBool) {
    while let Ok(job) = rx.recv() {
        let snapshot = loop {
            if let Some(s) = runner.snapshot() {
                break s;
            }
            if stop.load(Ordering::Relaxed) {
                return;
            }
            std::thread::sleep(PERIODIC);
        };
        runner.job(job, &snapshot);
    }
}

/// Says which buttons name a handler function, which is not run.
fn note_handlers(cfg: &config::PanelConfig) {
    for b in &cfg.buttons {
        if let config::Output::Command { on, off } = &b.output {
            for c in [on, off].into_iter().flatten() {
                if let Command::Handler(name) = c {
                    println!(
                        "panelui: button {}: {name} is a function of panelui_handler.py \
                         (Python), which this panelui does not run",
                        b.name
                    );
                }
            }
        }
    }
}

/// The `-d` listing of keys and buttons (`-v`: with their outputs).
fn print_keys(panel: &Panel, level: u8) {
    for b in &panel.config().buttons {
        let key = b
            .key
            .map_or("NONE".to_string(), |(r, c)| format!("R{r}C{c}"));
        println!("Keycode: {key} <-> Widget: {}", b.name);
        if level > 1 {
            println!("      >> {:?} {:?}", b.kind, b.output);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn options_are_linuxcnc_s() {
        let a = parse_args(&words("-d -c 2 -n 10 -t")).unwrap();
        assert_eq!((a.channel, a.count, a.tag, a.debug), (2, Some(10), true, 1));
        assert_eq!(parse_args(&words("-v")).unwrap().debug, 2);
        let e = parse_args(&words("-c x")).unwrap_err().to_string();
        assert!(e.contains("invalid channel number 'x'"), "{e}");
        let e = parse_args(&words("-q")).unwrap_err().to_string();
        assert!(e.contains("unknown option '-q'"), "{e}");
        let e = parse_args(&words("-c")).unwrap_err().to_string();
        assert!(e.contains("-c needs a value"), "{e}");
    }

    #[test]
    fn handler_functions_are_found() {
        let text = "import hal\ndef get_handlers(a, b):\n    return []\nclass H:\n\
                    \x20   def __init__(self):\n        pass\n    def hello_world(self, w, m):\n\
                    \x20       pass\n    def cycle_mode(self, w, m):\n        pass\n";
        assert_eq!(handler_names(text), ["hello_world", "cycle_mode"]);
    }
}
