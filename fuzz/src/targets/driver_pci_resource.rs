//! A sysfs PCI `resource` file through the driver layer's parser
//! ([`hal_driver::fuzzing::resource_file`]): parsed regions are
//! self-consistent, a refusal names the file and the line.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "driver_pci_resource",
    run: hal_driver::fuzzing::resource_file,
    dictionary: &["0x", "0x0000000000000000", "0x00000000f7e00000", "0x00000000f7e0ffff", "0x0000000000040200", "0x0000000000000101", " ", "\n"],
    generate: None,
};
