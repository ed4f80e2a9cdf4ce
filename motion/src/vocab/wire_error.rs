//! Why a record read from the shared-memory channel was refused. A
//! rejection ([`super::Reject::Malformed`]) carries it, so it lives with
//! the refusals.

use std::fmt;

/// Why a record read from shared memory was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireError {
    /// The version word is not the one this build speaks.
    BadVersion {
        /// The version word found.
        found: u64,
    },
    /// The checksum does not match the other words.
    BadChecksum,
    /// Serial number zero (reserved for "none").
    ZeroSerial,
    /// An opcode no command has.
    UnknownOpcode {
        /// The opcode found.
        opcode: u64,
    },
    /// A joint word that is not a sign-extended i32, or non-zero for a
    /// command without a joint.
    BadJoint {
        /// The value.
        value: u64,
    },
    /// A word the command does not use is not zero.
    UnusedWordSet {
        /// The word's index in the record.
        index: usize,
    },
    /// A result or reason code no answer has.
    UnknownCode {
        /// The code found.
        code: u64,
    },
    /// The status snapshot's header is inconsistent.
    BadStatus,
    /// A word that carries a whole number holds a fraction or a value out
    /// of range.
    BadInteger {
        /// The word's index in the record.
        index: usize,
    },
}

impl WireError {
    /// The (code, detail) pair on the wire.
    pub fn code(self) -> (u64, u64) {
        match self {
            WireError::BadVersion { found } => (1, found),
            WireError::BadChecksum => (2, 0),
            WireError::ZeroSerial => (3, 0),
            WireError::UnknownOpcode { opcode } => (4, opcode),
            WireError::BadJoint { value } => (5, value),
            WireError::UnusedWordSet { index } => (6, index as u64),
            WireError::UnknownCode { code } => (7, code),
            WireError::BadStatus => (8, 0),
            WireError::BadInteger { index } => (9, index as u64),
        }
    }

    /// The error of a (code, detail) pair from the wire.
    pub fn from_code(code: u64, detail: u64) -> Option<WireError> {
        Some(match code {
            1 => WireError::BadVersion { found: detail },
            2 => WireError::BadChecksum,
            3 => WireError::ZeroSerial,
            4 => WireError::UnknownOpcode { opcode: detail },
            5 => WireError::BadJoint { value: detail },
            6 => WireError::UnusedWordSet {
                index: usize::try_from(detail).ok()?,
            },
            7 => WireError::UnknownCode { code: detail },
            8 => WireError::BadStatus,
            9 => WireError::BadInteger {
                index: usize::try_from(detail).ok()?,
            },
            _ => return None,
        })
    }
}

impl fmt::Display for WireError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            WireError::BadVersion { found } => write!(
                f,
                "version word {found:#018x} is not the one this build speaks (client and controller differ)"
            ),
            WireError::BadChecksum => f.write_str("checksum mismatch (corrupt record)"),
            WireError::ZeroSerial => f.write_str("serial number 0"),
            WireError::UnknownOpcode { opcode } => write!(f, "unknown opcode {opcode}"),
            WireError::BadJoint { value } => write!(f, "bad joint word {value:#x}"),
            WireError::UnusedWordSet { index } => write!(f, "unused word {index} is not zero"),
            WireError::UnknownCode { code } => write!(f, "unknown result code {code}"),
            WireError::BadStatus => f.write_str("inconsistent status snapshot"),
            WireError::BadInteger { index } => {
                write!(f, "word {index} does not hold a whole number in range")
            }
        }
    }
}

impl std::error::Error for WireError {}
