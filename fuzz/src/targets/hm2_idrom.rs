//! hostmot2's IDROM loader on register images decoded from the bytes
//! ([`hostmot2::fuzzing::idrom_image`]: a simulated board's image or a
//! test pattern with word edits, or a raw image): an accepted board's
//! pins, instances and registers are what the driver relies on, a
//! refusal says why.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_idrom",
    run: hostmot2::fuzzing::idrom_image,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
