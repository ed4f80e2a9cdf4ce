//! A sysfs PCI ID file (`vendor`, `device`, ...) through the driver
//! layer's parser ([`hal_driver::fuzzing::id_file`]): a 16-bit ID that
//! prints back to its digits, or a refusal naming the file.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "driver_pci_id",
    run: hal_driver::fuzzing::id_file,
    dictionary: &["0x", "0x2718", "0x10b5", "0x9054", "ffff", "0x10000", "\n"],
    generate: None,
};
