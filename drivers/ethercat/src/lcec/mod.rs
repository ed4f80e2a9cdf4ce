//! linuxcnc-ethercat (`lcec`) compatibility: its configuration file
//! ([`conf`]), read with the same rules, so an lcec user keeps theirs,
//! and the pins and functions it exports ([`pins`]), as data for the HAL
//! binding.

pub mod conf;
pub mod pins;

pub use conf::{read, Config};
pub use pins::{full_name, master_pins, slave_pins, slave_state_pins, Kind, PinSpec, PinType};
