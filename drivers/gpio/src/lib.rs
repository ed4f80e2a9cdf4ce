//! `hal_gpio`: Linux GPIO lines as HAL pins, compatible with LinuxCNC's
//! driver of that name, on the GPIO character device's uAPI v2 (the
//! `gpiocdev` crate; no libgpiod).
//!
//! ```text
//! loadrt hal_gpio inputs=GPIO5,GPIO6 outputs=GPIO20,GPIO21,GPIO22 invert=GPIO20 reset=GPIO21,GPIO22
//! addf hal_gpio.read base-thread
//! addf stepgen.make-pulses base-thread
//! addf hal_gpio.write base-thread
//! addf hal_gpio.reset base-thread
//! ```
//!
//! # Module parameters
//!
//! LinuxCNC's, unchanged ([`cfg`](mod@cfg)): `inputs=`, `outputs=`, `invert=`,
//! `reset=`, `opendrain=`, `opensource=`, `biasdisable=`, `pulldown=`,
//! `pullup=`, each a comma-separated list of line names exactly as
//! `gpioinfo` prints them. This driver adds `backend=`:
//!
//! | token | backend |
//! |---|---|
//! | `cdev` (default) | `/dev/gpiochip*` ([`cdev`]); needs read/write access to the chip devices (udev rule `SUBSYSTEM=="gpio", KERNEL=="gpiochip[0-9]*", GROUP="hal", MODE="0660"` in `udev/60-hal-suite.rules`) |
//! | `sim` | a simulated chip `gpiochip0` with one line per name given ([`sim`]) |
//! | `simloop` | the same, the n-th output wired to the n-th input |
//!
//! # Pins, parameters, functions
//!
//! LinuxCNC's ([`hal`]): `hal_gpio.<line>-in`, `-in-not`, `-out`,
//! `hal_gpio.reset_ns`, functions `hal_gpio.read`, `hal_gpio.write`,
//! `hal_gpio.reset`. The lines are requested in one bulk request per chip
//! and direction (two when more than 64 lines of one direction are on one
//! chip, the kernel's limit per request), and each function makes one
//! value ioctl per request it touches. `reset` gives one pulse per
//! period ([`driver`]): it waits until `reset_ns` after `write` set a
//! `reset=` line and returns it to its inactive level; `reset_ns` above a
//! quarter of the thread's period is clamped and the clamped value written
//! back to the parameter.
//!
//! # Where this differs from LinuxCNC's hal_gpio
//!
//! Defects of LinuxCNC's driver (hardware.md 7.1) that this one does not
//! have:
//!
//! * LinuxCNC chooses between libgpiod 1 and 2 code paths with version
//!   tests that disagree (`> 200` for write and reset, `>= 200`
//!   elsewhere), so a build against libgpiod 2.0.0 mixes the two APIs.
//!   Here there is one code path, the kernel's uAPI v2, and no libgpiod.
//! * After looking up the output lines LinuxCNC re-checks the *input*
//!   chip count (a typo), so an output name that matches no line is not
//!   caught there. Here every name in every list is looked up before
//!   anything is requested, and a name that matches no line is a load
//!   error naming the list, the item and the name.
//! * A name that more than one line carries (on two chips, or twice on
//!   one) is a load error naming every line that has it, never "the first
//!   one found".
//!
//! Deliberate differences, each making a mistake visible instead of
//! silently ignored or unsafe:
//!
//! * A name in `invert=`, `reset=`, `opendrain=` or `opensource=` must be
//!   an output; a name in any modifier list must be in `inputs=` or
//!   `outputs=`; a line may not be listed twice, be both input and output,
//!   be open drain and open source, or have two bias settings; at least
//!   one line must be given. Each is a load error naming list and item.
//! * Inversion is done by the kernel (the line is requested active-low),
//!   and outputs are requested at their inactive level, so an inverted
//!   output sits at its inactive (high) level from the moment it is
//!   requested, not only after the first `write`.
//! * `write` writes a request only when one of its bits changed since the
//!   last write (the request's initial values count as written).
//! * A line access that fails (the chip was removed) sets every output
//!   inactive and says why once in the realtime log; outputs are left
//!   alone until the module is reloaded. The safe-state hook (fault,
//!   unload, exit) also sets every output inactive before the lines are
//!   released. There is no extra pin for this, so `show pin` lists
//!   exactly LinuxCNC's pins.
//! * `reset_ns` starts at 5000 ns (LinuxCNC's default is not in our
//!   reference; 5 µs is the pulse its documentation quotes for a
//!   Raspberry Pi 4).
//!
//! # Crate layout
//!
//! * [`regs`]: the uAPI v2 constants.
//! * [`chip`]: the bus traits, [`chip::ChipSet`] and
//!   [`chip::LineRequest`]; [`cdev`] and [`sim`] implement them.
//! * [`cfg`](mod@cfg): the module parameters; `resolve`: names to
//!   requests.
//! * [`driver`]: the read/write/reset algorithm on requests.
//! * [`hal`]: the HAL binding and [`MODULE`].
//! * `error`: the error type, [`GpioError`].

#![forbid(unsafe_code)]

pub mod cdev;
pub mod cfg;
pub mod chip;
pub mod driver;
mod error;
pub mod hal;
pub mod regs;
mod resolve;
pub mod sim;

pub use error::GpioError;
pub use hal::{load_on, MODULE};
