//! `sim-torch`: the plasma torch of LinuxCNC's QtPlasmaC sim
//! configurations, a user component whose `voltage-out` is the arc
//! voltage of a torch lit by `start` (see [`model`]). It runs every
//! millisecond until `close` is set, the HAL host ends or it is signalled.

pub mod model;

use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, In, Instance, Out, Pin};

use crate::error::LaunchError;
use model::{Torch, TorchInputs};

/// One cycle.
const CYCLE: Duration = Duration::from_millis(1);

/// `sim-torch`'s usage text.
pub const USAGE: &str = "\
usage: sim-torch [--instance NAME]

The simulated plasma torch of LinuxCNC's QtPlasmaC sim configurations, a
user component loaded with 'loadusr -Wn sim-torch sim-torch'. While start
is on, voltage-out rises to the cut voltage in on-delay-in cycles,
overshoots it by overshoot-in percent (peaking ramp-up-in percent of the
way through cycles-in cycles, with ramp-noise-in volts of noise), then
stays at voltage-in plus offset-in with cut-noise-in volts of noise; void
makes it climb by void_ramp volts a cycle up to 300 V. It is 0 while start
is off. One cycle a millisecond, until close is set.

options:
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

pins (sim-torch.*), with their defaults:
  start bit in                 the torch is on
  voltage-in float in 100      cut voltage, held to 50-150
  offset-in float in 0         added to the cut voltage, held to -10..10
  cut-noise-in float in 0.75   noise while cutting (volts)
  ramp-noise-in float in 5     noise during the overshoot (volts)
  cycles-in s32 in 200         cycles of the overshoot
  on-delay-in s32 in 10        cycles from start to the cut voltage (0-100)
  overshoot-in s32 in 50       overshoot, percent of the cut voltage (0-100)
  ramp-up-in s32 in 80         percent of cycles-in spent rising (0-100)
  void bit in                  the torch crosses a void
  void_ramp s32 in 0           volts a cycle a void adds
  close bit in                 ends the program
  voltage-out float out        the arc voltage";

/// The component's pins, with LinuxCNC's names.
struct Pins {
    start: Pin<bool, In>,
    voltage: Pin<f64, In>,
    offset: Pin<f64, In>,
    cut_noise: Pin<f64, In>,
    ramp_noise: Pin<f64, In>,
    cycles: Pin<i32, In>,
    on_delay: Pin<i32, In>,
    overshoot: Pin<i32, In>,
    ramp_up: Pin<i32, In>,
    void: Pin<bool, In>,
    void_ramp: Pin<i32, In>,
    close: Pin<bool, In>,
    out: Pin<f64, Out>,
}

impl Pins {
    fn create(inst: &Instance) -> hal_core::Result<(hal_core::Component, Pins)> {
        let comp = inst.new_component("sim-torch", ComponentKind::User)?;
        let n = |s: &str| format!("sim-torch.{s}");
        let d = TorchInputs::default();
        let pins = Pins {
            start: comp.pin(&n("start"))?,
            voltage: comp.pin_init(&n("voltage-in"), d.voltage)?,
            offset: comp.pin(&n("offset-in"))?,
            cut_noise: comp.pin_init(&n("cut-noise-in"), d.cut_noise)?,
            ramp_noise: comp.pin_init(&n("ramp-noise-in"), d.ramp_noise)?,
            cycles: comp.pin_init(&n("cycles-in"), d.cycles)?,
            on_delay: comp.pin_init(&n("on-delay-in"), d.on_delay)?,
            overshoot: comp.pin_init(&n("overshoot-in"), d.overshoot)?,
            ramp_up: comp.pin_init(&n("ramp-up-in"), d.ramp_up)?,
            void: comp.pin(&n("void"))?,
            void_ramp: comp.pin(&n("void_ramp"))?,
            close: comp.pin(&n("close"))?,
            out: comp.pin(&n("voltage-out"))?,
        };
        comp.ready()?;
        Ok((comp, pins))
    }

    fn read(&self) -> TorchInputs {
        TorchInputs {
            start: self.start.get(),
            voltage: self.voltage.get(),
            offset: self.offset.get(),
            cut_noise: self.cut_noise.get(),
            ramp_noise: self.ramp_noise.get(),
            cycles: self.cycles.get(),
            on_delay: self.on_delay.get(),
            overshoot: self.overshoot.get(),
            ramp_up: self.ramp_up.get(),
            void: self.void.get(),
            void_ramp: self.void_ramp.get(),
        }
    }
}

/// Runs the component with its command line (without the suite's common
/// options); returns the exit status.
pub fn main(args: &[String]) -> i32 {
    match run(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("sim-torch: {e}");
            1
        }
    }
}

fn run(args: &[String]) -> Result<(), LaunchError> {
    if let Some(a) = args.first() {
        return Err(LaunchError::SimTorchUsage {
            why: format!("unexpected argument '{a}' (see sim-torch --help)"),
        });
    }
    let signals = ExitSignals::install()?;
    let inst = Instance::attach(&hal_core::instance_from_env())?;
    let (_comp, pins) = Pins::create(&inst)?;
    let mut torch = Torch::default();
    while !signals.requested() && inst.host_alive() && !pins.close.get() {
        pins.out.set(torch.step(&pins.read()));
        std::thread::sleep(CYCLE);
    }
    Ok(())
}
