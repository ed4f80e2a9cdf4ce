//! hm2_modbus: LinuxCNC's Modbus RTU master over a Mesa PktUART. A
//! compiled command file (`.mbccb`, [`mbccb`]) lists the init commands
//! sent once and the commands run in a loop; [`engine`] runs them one
//! step per servo period (send, wait for the reply within the command's
//! timeout, parse, next) and maps the replies to and from pin values
//! ([`values`], [`pins`]).

pub mod encode;
pub mod engine;
pub mod frame;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod line;
pub mod mbccb;
pub mod mbccs;
pub mod pins;
pub mod rtu;
pub mod values;
