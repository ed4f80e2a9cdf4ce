//! MOTENC identification on fuzzed boardVersion and statusControl
//! words, and an ADC result word ([`hal_motenc::fuzzing::registers`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "motenc_registers",
    run: hal_motenc::fuzzing::registers,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
