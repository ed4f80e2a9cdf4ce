//! The crate's error type: what can go wrong opening a line, in one
//! transaction, or on a component's command line.

use std::fmt;
use std::io;

use crate::regs::modbus::exception as ex;

/// A Modbus exception code, as the slave sent it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExceptionCode(pub u8);

impl ExceptionCode {
    /// The code's name in the Modbus specification, if it has one.
    pub fn name(self) -> Option<&'static str> {
        Some(match self.0 {
            ex::ILLEGAL_FUNCTION => "illegal function",
            ex::ILLEGAL_DATA_ADDRESS => "illegal data address",
            ex::ILLEGAL_DATA_VALUE => "illegal data value",
            ex::SERVER_DEVICE_FAILURE => "server device failure",
            ex::ACKNOWLEDGE => "acknowledge",
            ex::SERVER_DEVICE_BUSY => "server device busy",
            ex::MEMORY_PARITY_ERROR => "memory parity error",
            ex::GATEWAY_PATH_UNAVAILABLE => "gateway path unavailable",
            ex::GATEWAY_TARGET_FAILED => "gateway target device failed to respond",
            _ => return None,
        })
    }

    /// Whether asking again may succeed (the slave was busy, or accepted
    /// and is still working).
    pub fn is_transient(self) -> bool {
        matches!(self.0, ex::ACKNOWLEDGE | ex::SERVER_DEVICE_BUSY)
    }
}

impl fmt::Display for ExceptionCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.name() {
            Some(n) => write!(f, "{n} (exception {:#04x})", self.0),
            None => write!(f, "unknown exception {:#04x}", self.0),
        }
    }
}

/// LinuxCNC's result codes (`hy_comm.h`, after libmodbus), which
/// `hy_vfd.retval` and the `last-error` pins show.
pub mod code {
    /// No reply within the timeout.
    pub const COMM_TIME_OUT: i32 = -0x0C;
    /// The port failed (read error, device gone).
    pub const PORT_SOCKET_FAILURE: i32 = -0x0D;
    /// A reply longer than the function allows.
    pub const TOO_MANY_DATA: i32 = -0x0F;
    /// The reply's CRC does not match its bytes.
    pub const INVALID_CRC: i32 = -0x10;
    /// A reply that is not the answer to the request.
    pub const INVALID_EXCEPTION_CODE: i32 = -0x11;
    /// Writing the request failed.
    pub const PORT_FAILURE: i32 = -0x0B;
}

/// Everything that can go wrong in this crate.
#[derive(Debug, thiserror::Error)]
pub enum SerialError {
    /// The serial device could not be opened or set up.
    #[error("cannot open serial device {device}: {reason}")]
    Open {
        /// The device path.
        device: String,
        /// The system's answer, with a hint for permissions.
        reason: String,
    },
    /// Reading or writing the device failed: it is gone (USB adapter
    /// unplugged, pty closed) or broken.
    #[error("serial device {device}: {op} failed: {source}")]
    Io {
        /// The device path.
        device: String,
        /// "write" or "read".
        op: &'static str,
        /// The system's answer.
        #[source]
        source: io::Error,
    },
    /// The device failed earlier and could not be opened again yet.
    #[error("serial device {device} is not available: {reason}")]
    LineDown {
        /// The device path.
        device: String,
        /// Why the last attempt to reopen it failed.
        reason: String,
    },
    /// No reply started within the response timeout.
    #[error("slave {slave}: no reply to function {function:#04x} within {waited_ms} ms")]
    Timeout {
        /// The slave asked.
        slave: u8,
        /// The function asked for.
        function: u8,
        /// How long the master waited.
        waited_ms: u64,
    },
    /// A reply stopped before its end.
    #[error(
        "slave {slave}: reply to function {function:#04x} stopped after {got} of {expected} bytes"
    )]
    Truncated {
        /// The slave asked.
        slave: u8,
        /// The function asked for.
        function: u8,
        /// Bytes received.
        got: usize,
        /// Bytes the reply should have.
        expected: usize,
    },
    /// The reply's CRC does not match.
    #[error(
        "slave {slave}: reply with a bad CRC (carried {carried:#06x}, computed {computed:#06x})"
    )]
    Crc {
        /// The slave asked.
        slave: u8,
        /// The CRC in the frame.
        carried: u16,
        /// The CRC of its bytes.
        computed: u16,
    },
    /// A reply from another address.
    #[error("reply from slave {found}, expected slave {expected}")]
    WrongSlave {
        /// The slave asked.
        expected: u8,
        /// The address in the reply.
        found: u8,
    },
    /// A reply to another function.
    #[error("slave {slave}: reply has function {found:#04x}, expected {expected:#04x}")]
    WrongFunction {
        /// The slave asked.
        slave: u8,
        /// The function asked for.
        expected: u8,
        /// The function in the reply.
        found: u8,
    },
    /// The reply's contents do not answer the request.
    #[error("slave {slave}: bad reply to function {function:#04x}: {what}")]
    BadReply {
        /// The slave asked.
        slave: u8,
        /// The function asked for.
        function: u8,
        /// What is wrong with it.
        what: String,
    },
    /// The slave answered with a Modbus exception.
    #[error("slave {slave}: function {function:#04x} refused: {code}")]
    Exception {
        /// The slave asked.
        slave: u8,
        /// The function asked for.
        function: u8,
        /// The exception code.
        code: ExceptionCode,
    },
    /// A request the master refuses to send (bad count, bad address).
    #[error("bad request: {0}")]
    BadRequest(String),
    /// A command-line option with a bad value.
    #[error("invalid {option}: {value}{}", reason_suffix(.reason))]
    BadOption {
        /// The option, as the user wrote it.
        option: String,
        /// The value given.
        value: String,
        /// Why it is refused (may be empty).
        reason: String,
    },
    /// A command-line usage error (unknown option, missing value).
    #[error("{0}")]
    Usage(String),
    /// A Modbus TCP server could not be reached.
    #[error("cannot connect to Modbus TCP server {address}: {source}")]
    Connect {
        /// `IP:port`.
        address: String,
        /// The system's answer.
        #[source]
        source: io::Error,
    },
    /// Sending to or receiving from a Modbus TCP server failed, or it
    /// closed the connection.
    #[error("Modbus TCP server {address}: {op} failed: {source}")]
    Net {
        /// `IP:port`.
        address: String,
        /// "write" or "read".
        op: &'static str,
        /// The system's answer.
        #[source]
        source: io::Error,
    },
    /// A Modbus TCP reply whose MBAP header cannot be right (protocol
    /// identifier, length): the stream is out of step.
    #[error("Modbus TCP server {address}: bad reply header: {what}")]
    BadHeader {
        /// `IP:port`.
        address: String,
        /// What is wrong with it.
        what: String,
    },
    /// An INI file could not be read.
    #[error(transparent)]
    Ini(#[from] hal_lang::ini::IniError),
    /// A value in a configuration file that cannot be used.
    #[error("{at}: [{section}] {key} = {value}: {reason}")]
    Config {
        /// Where the value is: the file as it was named, and the line
        /// (`mb.ini:12`).
        at: String,
        /// The section.
        section: String,
        /// The key.
        key: String,
        /// The value as written.
        value: String,
        /// Why it is refused, and what would be accepted.
        reason: String,
    },
    /// A key (or, with an empty key, a section) that must be in a
    /// configuration file is not.
    #[error("{file}: [{section}]{}{} is missing{}", if .key.is_empty() { "" } else { " " }, .key, reason_suffix(.reason))]
    ConfigMissing {
        /// The file, as it was named.
        file: String,
        /// The section.
        section: String,
        /// The key (empty for the whole section).
        key: String,
        /// Why it is needed (may be empty).
        reason: String,
    },
    /// A HAL error (attaching, creating pins).
    #[error(transparent)]
    Hal(#[from] hal_core::HalError),
}

fn reason_suffix(reason: &str) -> String {
    if reason.is_empty() {
        String::new()
    } else {
        format!(" ({reason})")
    }
}

impl SerialError {
    /// LinuxCNC's code for this failure (see [`code`]): a Modbus
    /// exception is its code negated.
    pub fn code(&self) -> i32 {
        match self {
            // Exception 0 does not exist; a slave sending it answers
            // badly (found by the reply fuzz body).
            SerialError::Exception { code, .. } if code.0 == 0 => code::INVALID_EXCEPTION_CODE,
            SerialError::Exception { code, .. } => -i32::from(code.0),
            SerialError::Timeout { .. } | SerialError::Truncated { .. } => code::COMM_TIME_OUT,
            SerialError::Crc { .. } => code::INVALID_CRC,
            SerialError::WrongFunction { .. } => -i32::from(ex::ILLEGAL_FUNCTION),
            SerialError::WrongSlave { .. } | SerialError::BadReply { .. } => {
                code::INVALID_EXCEPTION_CODE
            }
            SerialError::Io { op: "write", .. } | SerialError::Net { op: "write", .. } => {
                code::PORT_FAILURE
            }
            _ => code::PORT_SOCKET_FAILURE,
        }
    }

    /// Whether the same request may succeed if sent again: lost, garbled
    /// or misdirected replies and busy slaves; not a refusal, and not a
    /// line that is gone.
    pub fn is_retryable(&self) -> bool {
        match self {
            SerialError::Timeout { .. }
            | SerialError::Truncated { .. }
            | SerialError::Crc { .. }
            | SerialError::WrongSlave { .. }
            | SerialError::WrongFunction { .. }
            | SerialError::BadReply { .. } => true,
            SerialError::Exception { code, .. } => code.is_transient(),
            _ => false,
        }
    }

    /// Whether the line itself failed (the device must be reopened).
    pub fn is_line_failure(&self) -> bool {
        matches!(
            self,
            SerialError::Io { .. }
                | SerialError::Open { .. }
                | SerialError::LineDown { .. }
                | SerialError::Connect { .. }
                | SerialError::Net { .. }
                | SerialError::BadHeader { .. }
        )
    }
}

/// The crate's result type.
pub type Result<T, E = SerialError> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exceptions_are_named_and_coded_as_linuxcnc_does() {
        let e = SerialError::Exception {
            slave: 1,
            function: 6,
            code: ExceptionCode(2),
        };
        assert_eq!(
            e.to_string(),
            "slave 1: function 0x06 refused: illegal data address (exception 0x02)"
        );
        assert_eq!(e.code(), -2);
        assert!(!e.is_retryable());
        let zero = SerialError::Exception {
            slave: 1,
            function: 6,
            code: ExceptionCode(0),
        };
        assert_eq!(zero.code(), code::INVALID_EXCEPTION_CODE);
        assert!(ExceptionCode(6).is_transient());
        assert_eq!(ExceptionCode(0x42).to_string(), "unknown exception 0x42");
        let t = SerialError::Timeout {
            slave: 1,
            function: 3,
            waited_ms: 100,
        };
        assert_eq!(t.code(), code::COMM_TIME_OUT);
        assert!(t.is_retryable() && !t.is_line_failure());
    }
}
