//! The spindle VFD components, user-space programs that `loadusr` starts
//! as LinuxCNC does: [`gt`] (`hy_gt_vfd`, Huanyang GT series over
//! standard Modbus) and [`hy`] (`hy_vfd`, the HY series' own protocol).
//!
//! Each attaches to the HAL instance named by `--instance` or `HAL_INSTANCE`, exports
//! LinuxCNC's pins under its name and runs a loop: a cycle of
//! transactions, then a sleep. The serial line is only ever touched by
//! this process, so a slow or dead line delays nothing but this loop.
//!
//! Shared here: the serial options both take ([`SerialOptions`]),
//! opening the line (a device, or `sim`: a simulated drive behind a
//! pseudo-terminal, [`open_line`]), the link-health pins ([`Link`]) and
//! the process loop ([`run`]).

pub mod gt;
pub mod hy;
mod link;

use std::io::Write as _;
use std::time::{Duration, Instant};

use hal_core::userspace::ExitSignals;
use hal_core::Instance;

pub use link::{Link, LINK_LOST, VFD_FAULT};

use crate::error::{Result, SerialError};
use crate::line::{LineSettings, Parity, SerialLine, TtyLine};
use crate::modbus::MasterConfig;
use crate::opts::{self, Found, OptSpec};
use crate::sim::{PtyVfd, VfdSim};

/// The device name that selects the simulated drive.
pub const SIM_DEVICE: &str = "sim";

/// The serial options both components take.
#[derive(Debug, Clone, PartialEq)]
pub struct SerialOptions {
    /// `-d`: the device path, or `sim`.
    pub device: String,
    /// `-r`, `-b`, `-p`, `-s`.
    pub settings: LineSettings,
    /// `-t`: the drive's address.
    pub slave: u8,
    /// Timeouts and retries (`--response-timeout`, `--retries`,
    /// `-g`/`-v` for frame dumps).
    pub master: MasterConfig,
    /// `--instance`: the HAL instance, instead of `$HAL_INSTANCE`'s.
    pub instance: Option<String>,
}

/// What a component's command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Parsed<O> {
    /// Run with these options.
    Run(O),
    /// `-h`/`--help`: print the usage.
    Help,
    /// `--version`: print the version.
    Version,
}

impl<O> Parsed<O> {
    /// The options to run with, if the command line asks for a run.
    pub fn into_run(self) -> Option<O> {
        match self {
            Parsed::Run(o) => Some(o),
            Parsed::Help | Parsed::Version => None,
        }
    }
}

/// The option specs of [`SerialOptions`].
pub const SERIAL_SPECS: &[OptSpec] = &[
    OptSpec::value('d', "device"),
    OptSpec::value('r', "rate"),
    OptSpec::value('b', "bits"),
    OptSpec::value('p', "parity"),
    OptSpec::value('s', "stopbits"),
    OptSpec::value('t', "target"),
    OptSpec::long_value("response-timeout"),
    OptSpec::long_value("retries"),
    OptSpec::long_value("instance"),
    OptSpec::long_flag("version"),
];

impl SerialOptions {
    /// Defaults: `/dev/ttyS0`, `settings`, slave 1, `master`.
    pub fn new(settings: LineSettings, master: MasterConfig) -> SerialOptions {
        SerialOptions {
            device: "/dev/ttyS0".into(),
            settings,
            slave: 1,
            master,
            instance: None,
        }
    }

    /// Takes `f` if it is one of the serial options; false if not.
    /// `rates` are the speeds the program accepts, `max_slave` its
    /// highest address.
    pub fn take(&mut self, f: &Found, rates: &[&'static str], max_slave: i64) -> Result<bool> {
        let v = opts::value(f);
        match f.long {
            "device" => {
                if v.is_empty() || v.len() > 4096 {
                    return Err(opts::bad(f, "not a device path"));
                }
                self.device = v.to_string();
            }
            "rate" => {
                let r = opts::choice(v, rates)
                    .ok_or_else(|| opts::bad(f, format!("one of {}", rates.join(", "))))?;
                self.settings.baud = r.parse().unwrap_or(9600);
            }
            "bits" => {
                let b = opts::choice(v, &["5", "6", "7", "8"])
                    .ok_or_else(|| opts::bad(f, "5 to 8 data bits"))?;
                self.settings.data_bits = b.parse().unwrap_or(8);
            }
            "parity" => {
                self.settings.parity = match opts::choice(v, &["even", "odd", "none"]) {
                    Some("even") => Parity::Even,
                    Some("odd") => Parity::Odd,
                    Some(_) => Parity::None,
                    None => return Err(opts::bad(f, "even, odd or none")),
                }
            }
            "stopbits" => {
                let s = opts::choice(v, &["1", "2"]).ok_or_else(|| opts::bad(f, "1 or 2"))?;
                self.settings.stop_bits = if s == "2" { 2 } else { 1 };
            }
            "target" => self.slave = opts::integer(f, 1, max_slave)? as u8,
            "response-timeout" => {
                let ms = opts::number(f, 1.0, 10_000.0)?;
                self.master.response_timeout = Duration::from_secs_f64(ms / 1000.0);
            }
            "retries" => self.master.retries = opts::integer(f, 0, 100)? as u32,
            "instance" => {
                hal_core::validate_instance_name(v).map_err(|e| opts::bad(f, e.to_string()))?;
                self.instance = Some(v.to_string());
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// An open line, and the simulated drive behind it when the device is
/// `sim`.
pub struct OpenLine {
    /// The line.
    pub line: Box<dyn SerialLine>,
    /// The simulator, kept running while the line is used.
    pub sim: Option<PtyVfd>,
}

/// Opens the device of `opts`. For `sim`, `make_sim` builds the drive;
/// it is served behind a pseudo-terminal and the line opens the pty's
/// other end through the real tty code.
pub fn open_line(opts: &SerialOptions, make_sim: impl FnOnce() -> VfdSim) -> Result<OpenLine> {
    if opts.device == SIM_DEVICE {
        let pty = PtyVfd::start(make_sim()).map_err(|e| SerialError::Open {
            device: SIM_DEVICE.into(),
            reason: format!("cannot make a pseudo-terminal: {e}"),
        })?;
        let line = TtyLine::open(&pty.pty_path(), opts.settings)?;
        return Ok(OpenLine {
            line: Box::new(line),
            sim: Some(pty),
        });
    }
    Ok(OpenLine {
        line: Box::new(TtyLine::open(&opts.device, opts.settings)?),
        sim: None,
    })
}

/// What the process loop drives.
pub trait Cycle {
    /// One round of transactions.
    fn cycle(&mut self);
    /// How long to sleep after a cycle.
    fn period(&self) -> Duration;
    /// Last words before exit (stop the spindle).
    fn shutdown(&mut self);
}

/// Longest sleep between looks at the exit flag.
const WAKE: Duration = Duration::from_millis(20);

/// Runs `comp` until SIGTERM/SIGINT/SIGHUP or until the HAL host is
/// gone, then lets it stop the spindle.
pub fn run(comp: &mut impl Cycle, inst: &Instance, exit: &ExitSignals) {
    while !exit.requested() && inst.host_alive() {
        comp.cycle();
        let until = Instant::now() + comp.period();
        loop {
            if exit.requested() {
                break;
            }
            let now = Instant::now();
            if now >= until {
                break;
            }
            std::thread::sleep((until - now).min(WAKE));
        }
    }
    comp.shutdown();
}

/// Prints `e` as LinuxCNC's components print fatal errors; exit status 1.
pub fn fatal(program: &str, e: &SerialError) -> i32 {
    eprintln!("{program}: ERROR: {e}");
    1
}

/// The parsed options, or the exit status when the usage or the version
/// was asked for (0) or the command line is refused (1, with the usage
/// and why).
pub fn options_or_exit<O>(program: &str, usage: &str, parsed: Result<Parsed<O>>) -> Result<O, i32> {
    // A reader that has gone (`hy_vfd -h | head -1`) ends it quietly:
    // print! would panic on the broken pipe.
    let print = |text: &str| {
        let _ = std::io::Write::write_all(&mut std::io::stdout(), text.as_bytes());
    };
    match parsed {
        Ok(Parsed::Run(o)) => Ok(o),
        Ok(Parsed::Help) => {
            print(usage);
            Err(0)
        }
        Ok(Parsed::Version) => {
            print(&format!("{}\n", hal_core::userspace::version_line(program)));
            Err(0)
        }
        Err(e) => {
            eprint!("{usage}");
            Err(fatal(program, &e))
        }
    }
}

/// The rest of a component program: opens the line (or the simulated
/// drive `make_sim` builds, for `-d sim`), prints `banner` if any,
/// attaches to the HAL instance, makes component `name` with `build`,
/// marks it ready and runs it until told to stop. The exit status.
pub fn serve<V: Cycle>(
    program: &str,
    name: &str,
    serial: &SerialOptions,
    banner: Option<String>,
    make_sim: impl FnOnce() -> VfdSim,
    build: impl FnOnce(&hal_core::Component, Box<dyn SerialLine>) -> hal_core::Result<V>,
) -> i32 {
    let run_it = || -> Result<()> {
        let exit = ExitSignals::install()?;
        let opened = open_line(serial, make_sim)?;
        if let Some(b) = banner {
            let _ = writeln!(std::io::stdout(), "{b}");
        }
        let inst = match &serial.instance {
            Some(name) => Instance::attach(name)?,
            None => Instance::attach_default()?,
        };
        let comp = inst.new_component(name, hal_core::ComponentKind::User)?;
        let mut vfd = build(&comp, opened.line)?;
        comp.ready()?;
        run(&mut vfd, &inst, &exit);
        drop(vfd);
        drop(opened.sim);
        Ok(())
    };
    match run_it() {
        Ok(()) => 0,
        Err(e) => fatal(program, &e),
    }
}
