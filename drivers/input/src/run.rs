//! The program: open the devices, make the component `hal_input` with
//! pins `input.N.*`, mark it ready (`loadusr -W hal_input` waits for
//! that), then every 10 ms apply what the devices sent and write the
//! LEDs.
//!
//! A device that goes away (unplugged) makes hal_input exit with status
//! 1, as LinuxCNC's does (it does not look for the device again); before
//! it goes, every key of every device is shown released and every
//! absolute axis centred, so that nothing netted to them (a jog button,
//! a joystick's jog velocity) stays on. The pins keep those values in
//! their signals when the component is gone. SIGTERM (unloadusr) ends it
//! the same way, with status 0.

use std::path::PathBuf;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};

use crate::device::{Catalogue, InputDevice};
use crate::error::{InputError, Result};
use crate::pins::DevicePins;
use crate::spec::{parse_args, Command, Options};
use crate::{chain, evdev, sim, spec};

/// The HAL component's name (`loadusr -W hal_input` waits for it).
pub const COMPONENT: &str = "hal_input";
/// The program's name in messages.
pub const NAME: &str = "hal_input";
/// How long one wait for events lasts: LinuxCNC's cycle.
pub const CYCLE: Duration = Duration::from_millis(10);
/// The environment variable naming a simulated devices' description,
/// as `--sim` does.
pub const SIM_ENV: &str = "HAL_INPUT_SIM";

/// The help text.
pub const USAGE: &str = "\
Usage: hal_input [--instance NAME] [--sim FILE] [-KRAL] inputspec ...
Makes HAL pins input.N.* of Linux input devices (keyboards, joysticks, jog
wheels, gamepads, mice): component hal_input, device N the Nth inputspec.

An inputspec is
  PATH            an event node (/dev/input/by-id/...-event-joystick)
  N               /dev/input/eventN
  TEXT[:N]        a substring or shell pattern of a device's name, its phys,
                  its id ('Bus=BUS_USB Vendor=046d Product=c21d Version=0111')
                  or 'vendor:product'; :N picks the Nth match (from 0)
  +SPEC           the same, and the device for hal_input alone (EVIOCGRAB)
A subset option before an inputspec picks its features (default all):
  -K keys and buttons, -R relative axes, -A absolute axes, -L LEDs

NAME below is the kernel's name of a code in lower case, with '-' for '_'
(key-a, btn-trigger, abs-x, rel-wheel, led-numl).

Pins of device N:
  input.N.KEY, input.N.KEY-not                        bit out
  input.N.ABS-counts s32 out, -position float out, -is-pos/-is-neg bit out,
    -scale/-offset float in, -fuzz/-flat s32 in; -min/-max s32 params (r)
  input.N.REL-counts s32 out, -position float out, -reset bit in, -scale float in
  input.N.LED, input.N.LED-invert                     bit in
A device that goes away (unplugged) releases every key, centres every
absolute axis and ends hal_input with status 1.

Options:
  --sim FILE         look the inputspecs up among the simulated devices FILE
                     describes (also HAL_INPUT_SIM=FILE)
  --instance NAME    the HAL instance to join (default: $HAL_INSTANCE, or the default one)
  -h, --help         print this help and exit
      --version      print the version and exit
";

/// The program: returns its exit status.
pub fn main(args: &[String]) -> i32 {
    match parse_args(args) {
        Ok(Command::Help) => {
            hal_core::out!("{USAGE}");
            0
        }
        Ok(Command::Version) => {
            hal_core::outln!("{}", hal_core::userspace::version_line(NAME));
            0
        }
        Ok(Command::Run(o)) => {
            for w in &o.warnings {
                eprintln!("{NAME}: warning: {w}");
            }
            match run(&o) {
                Ok(()) => 0,
                Err(e) => {
                    eprintln!("{NAME}: ERROR: {}", chain(&e));
                    1
                }
            }
        }
        Err(e) => {
            eprintln!("{NAME}: ERROR: {}", chain(&e));
            eprintln!("{NAME}: see '{NAME} --help'");
            1
        }
    }
}

/// The catalogue the options ask for.
fn catalogue(o: &Options) -> Result<Box<dyn Catalogue>> {
    let sim = o
        .sim
        .clone()
        .or_else(|| std::env::var_os(SIM_ENV).map(PathBuf::from));
    Ok(match sim {
        Some(file) => Box::new(sim::SimCatalogue::load(&file)?),
        None => Box::new(evdev::Nodes),
    })
}

/// Opens the device an inputspec names, taking it alone for `+`.
pub fn open(cat: &dyn Catalogue, inputspec: &str) -> Result<Box<dyn InputDevice>> {
    let (exclusive, rest) = match inputspec.strip_prefix('+') {
        Some(r) => (true, r),
        None => (false, inputspec),
    };
    let mut dev = spec::find(cat, rest)?;
    if exclusive {
        dev.grab()?;
    }
    Ok(dev)
}

/// A device and its pins.
pub struct Bound {
    /// The device.
    pub dev: Box<dyn InputDevice>,
    /// Its pins.
    pub pins: DevicePins,
    events: Vec<crate::regs::Event>,
}

impl Bound {
    /// Makes device `index`'s pins on `comp`.
    pub fn new(
        comp: &hal_core::Component,
        index: usize,
        mut dev: Box<dyn InputDevice>,
        parts: spec::Parts,
    ) -> Result<Bound> {
        let pins = DevicePins::new(comp, index, dev.as_mut(), parts)?;
        Ok(Bound {
            dev,
            pins,
            events: Vec::with_capacity(64),
        })
    }

    /// One cycle: the events that arrived, then positions and LEDs.
    /// Returns the notes to print (events no pin takes).
    pub fn step(&mut self) -> Result<Vec<String>> {
        self.events.clear();
        self.dev.read_available(&mut self.events)?;
        let mut notes = Vec::new();
        for e in &self.events {
            if let Some(n) = self.pins.apply(self.dev.as_mut(), e)? {
                notes.push(n);
            }
        }
        self.pins.cycle(self.dev.as_mut())?;
        Ok(notes)
    }
}

/// Runs as the options say.
pub fn run(o: &Options) -> Result<()> {
    let cat = catalogue(o)?;
    let mut devs = Vec::with_capacity(o.devices.len());
    for d in &o.devices {
        devs.push((open(cat.as_ref(), &d.spec)?, d.parts));
    }
    let exit = ExitSignals::install()?;
    let inst = Instance::attach_default()?;
    let comp = inst.new_component(COMPONENT, ComponentKind::User)?;
    let mut bound = Vec::with_capacity(devs.len());
    for (i, (dev, parts)) in devs.into_iter().enumerate() {
        bound.push(Bound::new(&comp, i, dev, parts)?);
    }
    comp.ready()?;
    let result = serve(&exit, &inst, &mut bound);
    for b in &bound {
        b.pins.safe_state();
    }
    result
}

/// Waits up to one cycle for any device's file to have events.
fn wait(bound: &[Bound]) {
    use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
    let mut fds: Vec<PollFd<'_>> = bound
        .iter()
        .filter_map(|b| b.dev.fd())
        .map(|fd| PollFd::new(fd, PollFlags::POLLIN))
        .collect();
    if fds.is_empty() {
        std::thread::sleep(CYCLE);
        return;
    }
    let ms = u16::try_from(CYCLE.as_millis()).unwrap_or(u16::MAX);
    // An error (EINTR) or a hang-up ends the wait early; the reads that
    // follow say what happened.
    let _ = poll(&mut fds, PollTimeout::from(ms));
}

/// The loop, until a signal, the host's end, or a device's failure.
pub fn serve(exit: &ExitSignals, inst: &Instance, bound: &mut [Bound]) -> Result<()> {
    while !exit.requested() && inst.host_alive() {
        wait(bound);
        for b in bound.iter_mut() {
            match b.step() {
                Ok(notes) => {
                    for n in notes {
                        eprintln!("{NAME}: {n}");
                    }
                }
                Err(e @ InputError::Gone { .. }) => {
                    return Err(InputError::Lost {
                        prefix: b.pins.prefix().to_string(),
                        source: Box::new(e),
                    });
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok(())
}
