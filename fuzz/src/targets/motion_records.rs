//! The motion channel's command, answer and status records as read from
//! shared memory ([`motion::fuzzing::records`]): refused with a reason,
//! or decoded into a record that encodes and decodes to itself.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "motion_records",
    run: motion::fuzzing::records,
    // Whole words: zero, small integers (opcodes, codes, joint numbers).
    dictionary: &[
        "\0\0\0\0\0\0\0\0",
        "\x01\0\0\0\0\0\0\0",
        "\x02\0\0\0\0\0\0\0",
        "\x07\0\0\0\0\0\0\0",
        "\x1b\0\0\0\0\0\0\0",
    ],
    generate: Some(crate::random_bytes),
};
