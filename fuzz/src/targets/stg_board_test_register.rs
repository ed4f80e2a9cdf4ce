//! Servo-To-Go probing on fuzzed board test register reads
//! ([`hal_stg::fuzzing::board_test_register`]): a model exactly for a
//! true signature, "nothing answers" only for all 0xff.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "stg_board_test_register",
    run: hal_stg::fuzzing::board_test_register,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
