//! `hal_input`: LinuxCNC's user-space program that makes HAL pins of
//! Linux input devices (evdev: keyboards, joysticks, jog wheels,
//! gamepads, mice), with its command line, component name and pin names.
//!
//! * [`regs`]: the evdev user API (records, ioctls);
//! * [`names`]: code names as LinuxCNC makes pins of them;
//! * [`device`]: what a device is to hal_input, [`evdev`] the kernel's
//!   event nodes, [`sim`] simulated devices;
//! * [`spec`]: the command line and how an inputspec picks a device;
//! * [`pins`]: one device's pins and how events drive them;
//! * [`run`]: the program.

pub mod device;
pub mod error;
pub mod evdev;
#[cfg(feature = "fuzzing")]
pub mod fuzzing;
pub mod names;
pub mod pins;
pub mod regs;
pub mod run;
pub mod sim;
pub mod spec;

pub use error::{InputError, Result, SimProblem};

/// An error and its sources on one line.
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cur = e.source();
    while let Some(c) = cur {
        s.push_str(": ");
        s.push_str(&c.to_string());
        cur = c.source();
    }
    s
}
