//! The simulated spindle VFD on whatever reaches it, in pieces with
//! silences, for both protocols ([`hal_serial::fuzzing::slave_request`]):
//! every answer is a whole frame from the drive's address with a valid
//! CRC.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "serial_slave_request",
    run: hal_serial::fuzzing::slave_request,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
