//! The Modbus RTU master on whatever the serial line answers
//! ([`hal_serial::fuzzing::modbus_reply`]): an accepted reply is a whole
//! frame from the slave asked, with a valid CRC.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "serial_modbus_reply",
    run: hal_serial::fuzzing::modbus_reply,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
