//! `ethercat-sim`'s segment files and fault commands
//! ([`hal_ethercat::fuzzing::segment_file`]): an accepted file builds a
//! segment of its slaves; a command applies or says why not.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ethercat_segment_file",
    run: hal_ethercat::fuzzing::segment_file,
    dictionary: &[
        "EK1100", "EL1008", "EL1018", "EL2008", "EL2088", "EL3102", "EL4102", "EL5101", "EL7041",
        "servo", "generic", "serial=", "vid=", "pid=", "out=", "in=", "7000:01:16", "6000:01:8",
        "0x", "#", "\n", "link down", "cut ", "reset ", "al-error ", "drive-fault ", "shaft ",
    ],
    generate: None,
};
