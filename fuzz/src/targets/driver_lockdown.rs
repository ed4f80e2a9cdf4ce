//! The kernel's lockdown file through the driver layer's parser
//! ([`hal_driver::fuzzing::lockdown_file`]): any text gives an answer.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "driver_lockdown",
    run: hal_driver::fuzzing::lockdown_file,
    dictionary: &["[none]", "[integrity]", "[confidentiality]", "none", "integrity", "confidentiality", "[", "]", " ", "\n"],
    generate: None,
};
