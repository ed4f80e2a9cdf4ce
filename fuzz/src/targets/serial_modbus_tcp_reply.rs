//! mb2hal's Modbus TCP client on whatever the socket delivers
//! ([`hal_serial::fuzzing::modbus_tcp_reply`]): MBAP headers (protocol,
//! length, transaction id, unit) and the PDU of every data function;
//! an accepted reply answers the request with what it asked for.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "serial_modbus_tcp_reply",
    run: hal_serial::fuzzing::modbus_tcp_reply,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
