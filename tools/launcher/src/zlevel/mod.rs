//! `z_level_compensation`: LinuxCNC's Z level compensation user
//! component. While `enable-in` is on it loads the probe map
//! (`probe_points.txt` in its working directory, the configuration
//! directory), finds the Z offset at the commanded X/Y (less the active
//! G5x offset) and writes it as `counts` of `scale` (0.001) for motion's
//! external offsets, faded out towards `fade-height`; when `enable-in`
//! goes off it zeroes `counts` and pulses `clear`.

pub mod interp;
mod machine;
pub mod probe;
mod state;

use std::path::PathBuf;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, In, Instance, Out, Pin};

use crate::error::LaunchError;
use state::{Controller, Inputs};

/// How often the offset is updated, as LinuxCNC's component does.
const UPDATE: Duration = Duration::from_millis(50);
/// How long `clear` stays on when compensation is switched off.
const CLEAR_PULSE: Duration = Duration::from_millis(100);

/// `z_level_compensation`'s usage text.
pub const USAGE: &str = "\
usage: z_level_compensation [--instance NAME]

LinuxCNC's Z level compensation: a user component that offsets Z by a
probed surface map through motion's external offsets. HAL files load it
with 'loadusr -Wn z_level_compensation z_level_compensation'.

When enable-in goes on it reads probe_points.txt from its working
directory (the configuration directory; re-read when the file's time
changes): one probed point a line, 'X Y Z' separated by spaces (further
columns are ignored, # starts a comment), at least 3 and at most 4096
points, at most 1 MiB. X and Y are rounded to 0.1. A file that cannot be
used is reported with its name and line, and compensation stays off
(counts 0) until enable-in is switched off and on again.

The offset is taken at the whole-unit point nearest the commanded X/Y
less the active G5x offset, held inside the probed area, by method:
  1  linear: barycentric on the Delaunay triangles of the points
  2  nearest: the nearest probed point's Z
  0  cubic is not available here: linear is used, and said once (values
     outside 0-2 ask for cubic in LinuxCNC, so they get linear too)
Where linear has no triangle (outside the points' convex hull) the
offset is 0, said once per map.

counts = trunc(trunc(offset / scale) * fade), scale = 0.001. fade is 1
when fade-height is 0, else (fade-height - z-pos) / fade-height held to
at most 1, and 0 at or above fade-height; it is read every cycle (LinuxCNC
2.9's script reads it once at start). counts is 0 while the machine is
not on. Every 50 ms.

options:
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

pins (z_level_compensation.*):
  enable-in bit in      compensation on
  x-pos, y-pos, z-pos float in   the commanded position (machine units)
  fade-height float in  0: no fade
  method s32 in         0 cubic (linear here), 1 linear, 2 nearest
  counts s32 out        the offset in counts of scale
  scale float out       0.001 once compensating
  clear bit in          pulsed on for 0.1 s when compensation goes off
                        (an input pin the component writes, as LinuxCNC's)";

/// The component's pins, with LinuxCNC's names.
struct Pins {
    enable: Pin<bool, In>,
    scale: Pin<f64, Out>,
    counts: Pin<i32, Out>,
    clear: Pin<bool, In>,
    x: Pin<f64, In>,
    y: Pin<f64, In>,
    z: Pin<f64, In>,
    fade_height: Pin<f64, In>,
    method: Pin<i32, In>,
}

impl Pins {
    fn create(inst: &Instance) -> hal_core::Result<(hal_core::Component, Pins)> {
        let comp = inst.new_component("z_level_compensation", ComponentKind::User)?;
        let n = |s: &str| format!("z_level_compensation.{s}");
        let pins = Pins {
            enable: comp.pin(&n("enable-in"))?,
            scale: comp.pin(&n("scale"))?,
            counts: comp.pin(&n("counts"))?,
            clear: comp.pin(&n("clear"))?,
            x: comp.pin(&n("x-pos"))?,
            y: comp.pin(&n("y-pos"))?,
            z: comp.pin(&n("z-pos"))?,
            fade_height: comp.pin(&n("fade-height"))?,
            method: comp.pin(&n("method"))?,
        };
        comp.ready()?;
        Ok((comp, pins))
    }
}

/// Runs the component with its command line (without the suite's common
/// options); returns the exit status.
pub fn main(args: &[String]) -> i32 {
    match run(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("z_level_compensation: {e}");
            1
        }
    }
}

fn run(args: &[String]) -> Result<(), LaunchError> {
    if let Some(a) = args.first() {
        return Err(LaunchError::ZLevelUsage {
            why: format!("unexpected argument '{a}' (see z_level_compensation --help)"),
        });
    }
    let dir =
        std::env::current_dir().map_err(|e| LaunchError::read(std::path::Path::new("."), e))?;
    let file: PathBuf = dir.join(probe::FILE_NAME);
    let signals = ExitSignals::install()?;
    let instance = hal_core::instance_from_env();
    let inst = Instance::attach(&instance)?;
    let (_comp, pins) = Pins::create(&inst)?;
    let mut ctl = Controller::new(file);
    let mut task = machine::TaskWatch::new(instance);
    while !signals.requested() && inst.host_alive() {
        let enabled = pins.enable.get();
        // Task is asked only while compensating.
        let machine = if enabled && ctl.compensating() {
            task.read()
        } else {
            None
        };
        let out = ctl.step(&Inputs {
            enable: enabled,
            x: pins.x.get(),
            y: pins.y.get(),
            z: pins.z.get(),
            fade_height: pins.fade_height.get(),
            method: pins.method.get(),
            machine,
        });
        pins.counts.set(out.counts);
        if let Some(s) = out.scale {
            pins.scale.set(s);
        }
        if out.pulse_clear {
            pins.clear.overwrite(true);
            std::thread::sleep(CLEAR_PULSE);
            pins.clear.overwrite(false);
        }
        std::thread::sleep(UPDATE);
    }
    Ok(())
}
