//! The crate's error type. Parsers of outside bytes (frames, mailbox
//! replies, SII images, the XML configuration, segment files) return it
//! with what was wrong and where; the realtime side never returns errors
//! (it counts and trips fault latches, [`crate::master`]).

use std::path::PathBuf;

use crate::wire::coe::AbortCode;

/// Everything that can fail outside the realtime functions.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bytes too short for what they should hold.
    #[error("{what}: {got} bytes, at least {need} needed")]
    Truncated {
        /// What was being read ("EtherCAT datagram header at byte 16").
        what: String,
        /// Bytes needed.
        need: usize,
        /// Bytes there.
        got: usize,
    },
    /// A field holds a value the protocol does not allow.
    #[error("{what}: {reason}")]
    Malformed {
        /// What was being read.
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A number on the command line that is not one.
    #[error("'{given}' is not a number (decimal or 0x hexadecimal)")]
    NotANumber {
        /// The word as given.
        given: String,
        /// Why it did not parse.
        #[source]
        source: std::num::ParseIntError,
    },
    /// A number on the command line too large for its field.
    #[error("'{given}' is over {max}")]
    NumberTooLarge {
        /// The word as given.
        given: String,
        /// The field's largest value.
        max: u64,
    },
    /// An Ethernet frame that is not EtherCAT.
    #[error("not an EtherCAT frame: EtherType {ethertype:#06x} (EtherCAT is 0x88a4)")]
    NotEtherCat {
        /// The frame's EtherType.
        ethertype: u16,
    },
    /// An SII EEPROM image that cannot be used.
    #[error("SII image{}: {reason} (word {word:#06x})", name_suffix(.source_name))]
    Sii {
        /// Where the image came from (a file, a slave), if known.
        source_name: Option<String>,
        /// The word address where the problem is.
        word: usize,
        /// What is wrong.
        reason: String,
    },
    /// A slave aborted an SDO transfer.
    #[error("slave {slave}: SDO {what} aborted: {code}")]
    SdoAbort {
        /// The slave (position or name).
        slave: String,
        /// The request: "upload of 0x1018:01".
        what: String,
        /// The abort code and its meaning.
        code: AbortCode,
    },
    /// A configuration file (XML, segment description, SDO data) with an
    /// error at a place in it.
    #[error("{}:{line}: <{element}>: {reason}", .file.display())]
    Config {
        /// The file.
        file: PathBuf,
        /// The line (1-based).
        line: u32,
        /// The element (XML) or keyword (segment file) at fault.
        element: String,
        /// What is wrong and, where it helps, what is allowed.
        reason: String,
    },
    /// A file could not be read.
    #[error("cannot read {}: {source}", .path.display())]
    ReadFile {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The network interface cannot be used.
    #[error("network interface '{iface}': {reason}")]
    Interface {
        /// The interface name.
        iface: String,
        /// Why, with what to do about it.
        reason: String,
        /// The system error, if one.
        #[source]
        source: Option<std::io::Error>,
    },
    /// The master failed at a step of bring-up or service.
    #[error("EtherCAT master on '{iface}': {step}: {reason}")]
    Master {
        /// The interface (or "sim").
        iface: String,
        /// The step: "bringing the segment to OP".
        step: String,
        /// What EtherCrab or a slave said.
        reason: String,
    },
    /// The segment found differs from the configuration.
    #[error("slave {position} ({name}): {reason}")]
    SlaveMismatch {
        /// Position on the segment.
        position: u16,
        /// The configured name.
        name: String,
        /// What differs.
        reason: String,
    },
}

fn name_suffix(s: &Option<String>) -> String {
    s.as_ref().map(|s| format!(" of {s}")).unwrap_or_default()
}

impl Error {
    /// A truncation error.
    pub fn truncated(what: impl Into<String>, need: usize, got: usize) -> Error {
        Error::Truncated {
            what: what.into(),
            need,
            got,
        }
    }

    /// A malformed-field error.
    pub fn malformed(what: impl Into<String>, reason: impl Into<String>) -> Error {
        Error::Malformed {
            what: what.into(),
            reason: reason.into(),
        }
    }
}

/// The crate's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
