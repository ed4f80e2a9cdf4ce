//! `hy_vfd`: a Huanyang HY-series VFD over its own RS-485 protocol, with
//! LinuxCNC's options and pins.
//!
//! ```text
//! loadusr -Wn spindle-vfd hy_vfd -n spindle-vfd -d /dev/ttyUSB0 -p none -r 19200
//! setp spindle-vfd.enable 1
//! net spindle-cw    spindle.0.forward => spindle-vfd.spindle-forward
//! net spindle-ccw   spindle.0.reverse => spindle-vfd.spindle-reverse
//! net spindle-on    spindle.0.on      => spindle-vfd.spindle-on
//! net spindle-speed spindle.0.speed-out-abs => spindle-vfd.speed-command
//! net spindle-ready spindle-vfd.spindle-at-speed => spindle.0.at-speed
//! ```
//!
//! Nothing goes over the line until `enable` is set. Then the component
//! writes the parameters the command line gives (`-F -f -B -V -I -S -P`,
//! `-x PDnnn=value`) and reads the drive's set-up (PD005, PD004, PD011,
//! PD141..PD144) into the pins, retrying each cycle until that works;
//! from then on each cycle reads the eight status values, sends the
//! frequency when it changed and the control word, and sleeps.
//!
//! Defaults follow LinuxCNC's program where it and its manual page
//! disagree (19 200 baud, even parity: the page says 38 400, odd).
//!
//! Where this differs from LinuxCNC, on purpose:
//! * The control word sent is this cycle's (LinuxCNC sends the previous
//!   cycle's, so run and stop reach the drive one cycle late).
//! * The frequency is |speed-command| × max-freq / rated-motor-rev,
//!   rounded to 0.01 Hz (LinuxCNC adds 1 rpm in the running direction
//!   and truncates).
//! * When `enable` falls, and when the program ends, the drive is told
//!   to stop (LinuxCNC leaves it running).
//! * `error-count` counts failed transactions and `retval` shows the
//!   last cycle's result (LinuxCNC's increments miss their target).
//! * `-x` and `-y` work as short options (LinuxCNC accepts only
//!   `--register` and `--regdump`).
//! * A drive that was lost gets its frequency again when it answers.
//! * Extra pins `modbus-ok`, `fault`, `last-error`; options `--period`,
//!   `--response-timeout`, `--retries`; `-d sim` for a simulated drive.

mod cycle;
mod options;
mod pins;

pub use cycle::HyVfd;
pub use options::{component_name, parse_options, HyOptions, RATES, USAGE};
pub use pins::{HyPins, CNST_PINS, STATUS_PINS};

use super::{options_or_exit, serve};
use crate::sim::{Protocol, VfdSim};

/// The program's and component's default name.
pub const NAME: &str = "hy_vfd";

/// A simulated HY drive at the options' address, set up as the manual
/// page asks (a 24 000 rpm, 400 Hz spindle).
pub fn sim_drive(o: &HyOptions) -> VfdSim {
    VfdSim::new(Protocol::Hy, o.serial.slave, o.serial.settings)
}

/// The program: parses `args` (with the program name first), opens the
/// line, attaches to the HAL instance and runs until told to stop.
/// Returns the exit status.
pub fn main(args: &[String]) -> i32 {
    let parsed = parse_options(args.get(1..).unwrap_or(&[]));
    let o = match options_or_exit(NAME, USAGE, parsed) {
        Ok(o) => o,
        Err(status) => return status,
    };
    let banner = o.serial.master.debug.then(|| {
        format!(
            "{}: device='{}', {}, address={}, PID={}",
            o.name,
            o.serial.device,
            o.serial.settings,
            o.serial.slave,
            std::process::id()
        )
    });
    serve(
        NAME,
        &o.name,
        &o.serial,
        banner,
        || sim_drive(&o),
        |comp, line| HyVfd::new(comp, o.clone(), line),
    )
}
