//! `xhc-hb04`: LinuxCNC's user component for the XHC-HB04 wireless MPG
//! pendant (USB 10ce:eb70): buttons, the jog wheel and the rotary switch
//! as HAL pins, positions, overrides and speeds to its display.
//!
//! Without `-x` the pins exist at once and `connected` stays false until
//! the pendant appears; the driver looks for it once a second, and looks
//! again when it goes away (its outputs then drop to "switch off, no
//! button"). With `-x` it waits for the pendant before making any pin.
//! Without `-H` it makes no pins and prints each report (to find a
//! pendant's button codes).

pub mod buttons;
pub mod device;
pub mod pins;
pub mod report;
pub mod state;
pub mod steps;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};

use crate::error::{Result, UsbError};
use buttons::Button;
use device::Device;
use pins::Pins;
use state::{Pendant, Velocity};
use steps::Stepper;

/// The component's name and pin prefix.
pub const NAME: &str = "xhc-hb04";
/// How often a missing pendant is looked for.
pub const SEARCH_INTERVAL: Duration = Duration::from_secs(1);
/// How long one wait for a report lasts (the loop's period when idle).
pub const READ_WAIT: Duration = Duration::from_millis(20);
/// How often the display is rewritten.
pub const DISPLAY_INTERVAL: Duration = Duration::from_millis(100);
/// How long `-x` waits for the pendant before giving up.
pub const REQUIRE_WAIT: Duration = Duration::from_secs(180);

/// The help text.
pub const USAGE: &str = "\
Usage: xhc-hb04 [-I button-cfg-file] [-h] [-H] [-x] [-s n] [--instance NAME]
  -I button-cfg-file  the pendant's button layout ([XHC-HB04] BUTTON=CODE:pin-name)
  -H                  run as a HAL component (without it: print the pendant's reports)
  -x                  wait for the pendant before creating HAL pins
  -s n                step sequence (times 0.001 unit):
                        1: 1,10,100,1000 (default)
                        2: 1,5,10,20
                        3: 1,10,100
                        4: 1,5,10,20,50,100
                        5: 1,10,50,100,1000
  --instance NAME     the HAL instance to join (default: $HAL_INSTANCE, or the default one)
  -h, --help          print this help and exit
      --version       print the version and exit
";

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// `-I`.
    pub buttons: Option<PathBuf>,
    /// `-H`.
    pub hal: bool,
    /// `-x`.
    pub require_pendant: bool,
    /// `-s`: the sequence number, 1..=5.
    pub sequence: usize,
}

/// A command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Run.
    Run(Options),
    /// `-h`.
    Help,
    /// `--version`.
    Version,
}

/// Reads the command line (without the program name).
pub fn parse_args(args: &[String]) -> Result<Command> {
    let mut o = Options {
        buttons: None,
        hal: false,
        require_pendant: false,
        sequence: 1,
    };
    let mut i = 0;
    while i < args.len() {
        if let Some(found) = hal_core::userspace::instance_option(args, i, true) {
            let (name, used) = found?;
            hal_core::userspace::select_instance(&name)?;
            i += used;
            continue;
        }
        let a = args[i].as_str();
        let value = |i: usize| {
            args.get(i + 1)
                .ok_or_else(|| UsbError::Usage(format!("option {a} needs a value")))
        };
        match a {
            "-h" | "--help" => return Ok(Command::Help),
            "--version" => return Ok(Command::Version),
            "-H" => o.hal = true,
            "-x" => o.require_pendant = true,
            "-I" => {
                o.buttons = Some(PathBuf::from(value(i)?));
                i += 1;
            }
            "-s" => {
                let v = value(i)?;
                o.sequence = v
                    .parse()
                    .ok()
                    .filter(|n| steps::sequence(*n).is_some())
                    .ok_or_else(|| UsbError::BadOption {
                        option: "-s",
                        value: v.clone(),
                        reason: "the step sequence is 1 to 5".into(),
                    })?;
                i += 1;
            }
            _ => return Err(UsbError::Usage(format!("unknown argument '{a}'"))),
        }
        i += 1;
    }
    Ok(Command::Run(o))
}

/// The program: returns its exit status.
pub fn main(args: &[String]) -> i32 {
    match parse_args(args.get(1..).unwrap_or_default()) {
        Ok(Command::Help) => {
            hal_core::out!("{USAGE}");
            0
        }
        Ok(Command::Version) => {
            hal_core::outln!("{}", hal_core::userspace::version_line(NAME));
            0
        }
        Ok(Command::Run(o)) => match run(&o) {
            Ok(()) => 0,
            Err(e) => {
                eprintln!("{NAME}: ERROR: {}", chain(&e));
                1
            }
        },
        Err(e) => {
            eprint!("{USAGE}");
            eprintln!("{NAME}: ERROR: {e}");
            1
        }
    }
}

/// An error and its sources on one line.
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cur = e.source();
    while let Some(c) = cur {
        s.push_str(": ");
        s.push_str(&c.to_string());
        cur = c.source();
    }
    s
}

/// The first pendant that opens, if any.
fn open_pendant() -> Option<Device> {
    for path in device::find(Path::new(device::SYS_HIDRAW), Path::new("/dev")) {
        match Device::open(&path) {
            Ok(d) => return Some(d),
            Err(e) => eprintln!("{NAME}: {}", chain(&e)),
        }
    }
    None
}

/// Waits (until `limit`, or a signal) for the pendant.
fn wait_for_pendant(exit: &ExitSignals, limit: Duration) -> Option<Device> {
    let start = Instant::now();
    eprintln!("{NAME}: waiting for XHC-HB04 device");
    while !exit.requested() && start.elapsed() < limit {
        if let Some(d) = open_pendant() {
            return Some(d);
        }
        std::thread::sleep(SEARCH_INTERVAL);
    }
    None
}

/// Runs as the options say.
pub fn run(o: &Options) -> Result<()> {
    let list = match &o.buttons {
        Some(p) => buttons::load(p)?,
        None => Vec::new(),
    };
    let seq = steps::sequence(o.sequence).unwrap_or(steps::SEQUENCES[0]);
    let exit = ExitSignals::install()?;
    if !o.hal {
        return print_reports(&exit, &list);
    }
    let mut dev = None;
    if o.require_pendant {
        dev = wait_for_pendant(&exit, REQUIRE_WAIT);
        if dev.is_none() {
            return Err(UsbError::Usage(format!(
                "no XHC-HB04 pendant within {} s (-x)",
                REQUIRE_WAIT.as_secs()
            )));
        }
    }
    let inst = Instance::attach_default()?;
    let comp = inst.new_component(NAME, ComponentKind::User)?;
    let pins = Pins::new(&comp, NAME, &list, o.require_pendant)?;
    comp.ready()?;
    serve(&exit, &inst, &pins, dev, Stepper::new(seq));
    Ok(())
}

/// The HAL loop: reports in, display out, the pendant looked for while
/// it is missing.
fn serve(
    exit: &ExitSignals,
    inst: &Instance,
    pins: &Pins,
    mut dev: Option<Device>,
    mut stepper: Stepper,
) {
    let mut pendant = Pendant::default();
    let mut velocity = Velocity::default();
    let mut last_search: Option<Instant> = None;
    let mut last_display: Option<Instant> = None;
    let mut buf = [0u8; device::READ_MAX];
    while !exit.requested() && inst.host_alive() {
        let stepsize = stepper.update(pins.stepsize_up.get(), pins.stepsize_down.get());
        pins.write_stepsize(stepsize);
        let Some(d) = dev.as_mut() else {
            pins.connected.set(false);
            if last_search.is_none_or(|t| t.elapsed() >= SEARCH_INTERVAL) {
                last_search = Some(Instant::now());
                dev = open_pendant();
                if let Some(d) = &dev {
                    eprintln!("{NAME}: found the pendant at {}", d.path().display());
                }
            } else {
                std::thread::sleep(READ_WAIT);
            }
            continue;
        };
        pins.connected.set(true);
        let mut failed = match d.read(&mut buf, READ_WAIT) {
            Ok(0) => None,
            Ok(n) => {
                match report::parse_input(&buf[..n]) {
                    Ok(r) => {
                        pendant.apply(&r);
                        pins.write_pendant(&pendant);
                    }
                    Err(e) => eprintln!("{NAME}: ignored a report: {e}"),
                }
                None
            }
            Err(e) => Some(e),
        };
        let (scale, max_v) = pins.velocity_inputs();
        velocity.update(pendant.counts, scale, max_v, Instant::now());
        pins.write_velocity(&pendant, &velocity);
        if failed.is_none() && last_display.is_none_or(|t| t.elapsed() >= DISPLAY_INTERVAL) {
            last_display = Some(Instant::now());
            for r in report::encode_display(&pins.display(&pendant, stepsize)) {
                if let Err(e) = d.send_feature(&r) {
                    failed = Some(e);
                    break;
                }
            }
        }
        if let Some(e) = failed {
            eprintln!("{NAME}: connection lost: {}", chain(&e));
            dev = None;
            last_search = Some(Instant::now());
            // No button held, switch off: nothing jogs while it is gone.
            pendant = Pendant {
                counts: pendant.counts,
                ..Pendant::default()
            };
            pins.write_pendant(&pendant);
            velocity = Velocity::default();
            pins.write_velocity(&pendant, &velocity);
        }
    }
}

/// Without `-H`: prints each report, by button name where the file
/// names the code.
fn print_reports(exit: &ExitSignals, list: &[Button]) -> Result<()> {
    let Some(mut d) = wait_for_pendant(exit, REQUIRE_WAIT) else {
        return Ok(());
    };
    let mut buf = [0u8; device::READ_MAX];
    while !exit.requested() {
        let n = d.read(&mut buf, Duration::from_millis(200))?;
        if n == 0 {
            continue;
        }
        let hex: Vec<String> = buf[..n].iter().map(|b| format!("{b:02X}")).collect();
        let line = match report::parse_input(&buf[..n]) {
            Ok(r) => {
                let name = list
                    .iter()
                    .find(|b| b.code == r.button)
                    .map(|b| b.name.as_str());
                format!(
                    "{} button {:02X}{} switch {:?} wheel {:+}",
                    hex.join(" "),
                    r.button,
                    name.map(|n| format!(" ({n})")).unwrap_or_default(),
                    r.switch,
                    r.wheel
                )
            }
            Err(e) => format!("{}: {e}", hex.join(" ")),
        };
        hal_core::outln!("{line}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn options_as_the_tcl_passes_them() {
        let c = parse_args(&words(&["-x", "-s", "2", "-I", "/l.cfg", "-H"])).unwrap();
        assert_eq!(
            c,
            Command::Run(Options {
                buttons: Some("/l.cfg".into()),
                hal: true,
                require_pendant: true,
                sequence: 2
            })
        );
        assert_eq!(parse_args(&words(&["-h"])).unwrap(), Command::Help);
    }

    #[test]
    fn refuses_bad_options() {
        for bad in [&["-s", "6"][..], &["-s", "x"], &["-s"], &["-I"], &["-q"]] {
            assert!(parse_args(&words(bad)).is_err(), "{bad:?}");
        }
    }
}
