//! The I2C chip drivers against a bus whose every reply and failure comes
//! from the bytes ([`hal_i2c::fuzzing::random_replies`]): they write
//! only their own registers and report every failure.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "i2c_replies",
    run: hal_i2c::fuzzing::random_replies,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
