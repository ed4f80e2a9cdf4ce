//! Smart Serial cards' tables and records read from a memory given by
//! the bytes ([`hostmot2::fuzzing::sserial_records`]): a record or a
//! refusal with a reason, never an endless read.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_sserial_records",
    run: hostmot2::fuzzing::sserial_records,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
