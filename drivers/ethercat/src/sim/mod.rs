//! The simulated segment: ESCs with their devices, behaving as the real
//! ones do at the register level ([`esc`]), the devices themselves
//! ([`catalog`], [`servo`]), their object dictionaries and mailboxes
//! ([`od`], `mailbox`), and the line of slaves a frame passes
//! ([`segment`]).

pub mod catalog;
pub mod clock;
pub mod control;
pub mod device;
pub mod esc;
pub mod file;
pub(crate) mod mailbox;
pub mod od;
pub mod segment;
pub mod servo;

pub use device::Device;
pub use segment::{Outcome, Segment};

/// A device by its type name as segment files and lcec configurations
/// write it (EK1100, EL1008, EL1018, EL2008, EL2088, EL3102, EL4102,
/// EL5101, EL7041, servo); None for an unknown name.
pub fn device_by_name(kind: &str, serial: u32) -> Option<Device> {
    Some(match kind.to_ascii_uppercase().as_str() {
        "EK1100" => catalog::ek1100(serial),
        "EL1008" => catalog::el1008(serial),
        "EL1018" => catalog::el1018(serial),
        "EL2008" => catalog::el2008(serial),
        "EL2088" => catalog::el2088(serial),
        "EL3102" => catalog::el3102(serial),
        "EL4102" => catalog::el4102(serial),
        "EL5101" => catalog::el5101(serial),
        "EL7041" | "EL7041-0052" => catalog::el7041(serial),
        "SERVO" | "BASIC_CIA402" | "CIA402" => servo::servo(serial),
        _ => return None,
    })
}

/// The type names [`device_by_name`] knows.
pub const DEVICE_NAMES: &[&str] = &[
    "EK1100", "EL1008", "EL1018", "EL2008", "EL2088", "EL3102", "EL4102", "EL5101", "EL7041",
    "servo",
];
