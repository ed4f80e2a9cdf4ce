//! linuxcnc-ethercat (`lcec`) compatibility: its configuration file
//! ([`conf`]), read with the same rules, so an lcec user keeps theirs.

pub mod conf;

pub use conf::{read, Config};
