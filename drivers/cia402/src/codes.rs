//! The two code spaces a user reads in messages: SDO abort codes
//! (hardware.md §6.5) and CANopen error codes, shared by EMCY, 0x603F
//! and the error history (§6.10). Each comes with its meaning, so every
//! message says what a number means.

use std::fmt;

/// An SDO abort code with its meaning.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct AbortCode(pub u32);

impl AbortCode {
    /// Toggle bit not alternated.
    pub const TOGGLE: AbortCode = AbortCode(0x0503_0000);
    /// SDO protocol timed out.
    pub const TIMEOUT: AbortCode = AbortCode(0x0504_0000);
    /// Command specifier not valid or unknown.
    pub const BAD_COMMAND: AbortCode = AbortCode(0x0504_0001);
    /// Out of memory.
    pub const OUT_OF_MEMORY: AbortCode = AbortCode(0x0504_0005);
    /// Unsupported access to an object.
    pub const UNSUPPORTED_ACCESS: AbortCode = AbortCode(0x0601_0000);
    /// Attempt to read a write-only object.
    pub const WRITE_ONLY: AbortCode = AbortCode(0x0601_0001);
    /// Attempt to write a read-only object.
    pub const READ_ONLY: AbortCode = AbortCode(0x0601_0002);
    /// Object does not exist.
    pub const NO_OBJECT: AbortCode = AbortCode(0x0602_0000);
    /// Object cannot be mapped to the PDO.
    pub const NOT_MAPPABLE: AbortCode = AbortCode(0x0604_0041);
    /// Mapped objects would exceed the PDO length.
    pub const PDO_TOO_LONG: AbortCode = AbortCode(0x0604_0042);
    /// General parameter incompatibility.
    pub const INCOMPATIBLE: AbortCode = AbortCode(0x0604_0043);
    /// Data type or length does not match.
    pub const LENGTH_MISMATCH: AbortCode = AbortCode(0x0607_0010);
    /// Length too high.
    pub const LENGTH_HIGH: AbortCode = AbortCode(0x0607_0012);
    /// Length too low.
    pub const LENGTH_LOW: AbortCode = AbortCode(0x0607_0013);
    /// Sub-index does not exist.
    pub const NO_SUBINDEX: AbortCode = AbortCode(0x0609_0011);
    /// Invalid value.
    pub const INVALID_VALUE: AbortCode = AbortCode(0x0609_0030);
    /// Value too high.
    pub const VALUE_HIGH: AbortCode = AbortCode(0x0609_0031);
    /// Value too low.
    pub const VALUE_LOW: AbortCode = AbortCode(0x0609_0032);
    /// General error.
    pub const GENERAL: AbortCode = AbortCode(0x0800_0000);
    /// Data cannot be stored.
    pub const CANNOT_STORE: AbortCode = AbortCode(0x0800_0020);
    /// Not in the present device state.
    pub const WRONG_STATE: AbortCode = AbortCode(0x0800_0022);

    /// What the code means (CiA 301).
    pub fn meaning(self) -> &'static str {
        match self.0 {
            0x0503_0000 => "toggle bit not alternated",
            0x0504_0000 => "SDO protocol timed out",
            0x0504_0001 => "command specifier not valid or unknown",
            0x0504_0002 => "invalid block size",
            0x0504_0003 => "invalid sequence number",
            0x0504_0004 => "CRC error",
            0x0504_0005 => "out of memory",
            0x0601_0000 => "unsupported access to an object",
            0x0601_0001 => "attempt to read a write-only object",
            0x0601_0002 => "attempt to write a read-only object",
            0x0602_0000 => "object does not exist in the object dictionary",
            0x0604_0041 => "object cannot be mapped to the PDO",
            0x0604_0042 => "number and length of mapped objects would exceed PDO length",
            0x0604_0043 => "general parameter incompatibility",
            0x0604_0047 => "general internal incompatibility in the device",
            0x0606_0000 => "access failed due to a hardware error",
            0x0607_0010 => "data type does not match, length of service parameter does not match",
            0x0607_0012 => "data type does not match, length of service parameter too high",
            0x0607_0013 => "data type does not match, length of service parameter too low",
            0x0609_0011 => "sub-index does not exist",
            0x0609_0030 => "invalid value for parameter",
            0x0609_0031 => "value of parameter written too high",
            0x0609_0032 => "value of parameter written too low",
            0x0609_0036 => "maximum value is less than minimum value",
            0x060A_0023 => "resource not available: SDO connection",
            0x0800_0000 => "general error",
            0x0800_0020 => "data cannot be transferred or stored to the application",
            0x0800_0021 => "data cannot be transferred or stored because of local control",
            0x0800_0022 => {
                "data cannot be transferred or stored because of the present device state"
            }
            0x0800_0023 => {
                "object dictionary dynamic generation failed or no object dictionary present"
            }
            0x0800_0024 => "no data available",
            _ => "unknown abort code",
        }
    }
}

impl fmt::Display for AbortCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:#010x} ({})", self.0, self.meaning())
    }
}

impl fmt::Debug for AbortCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// A CANopen error code (EMCY, 0x603F, 0x1003) with its meaning.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct ErrorCode(pub u16);

impl ErrorCode {
    /// No error / error reset.
    pub const NONE: ErrorCode = ErrorCode(0x0000);
    /// Continuous over-current.
    pub const OVER_CURRENT: ErrorCode = ErrorCode(0x2310);
    /// DC-link under-voltage.
    pub const UNDER_VOLTAGE: ErrorCode = ErrorCode(0x3220);
    /// PDO not processed due to length error.
    pub const PDO_LENGTH: ErrorCode = ErrorCode(0x8210);
    /// PDO length exceeded.
    pub const PDO_TOO_LONG: ErrorCode = ErrorCode(0x8220);
    /// Life guard / heartbeat error.
    pub const HEARTBEAT: ErrorCode = ErrorCode(0x8130);
    /// Following error.
    pub const FOLLOWING_ERROR: ErrorCode = ErrorCode(0x8611);
    /// Device software (used for a homing error).
    pub const SOFTWARE: ErrorCode = ErrorCode(0x6000);

    /// What the code means: the exact code where CiA 301/402 names it,
    /// else its category by first digit.
    pub fn meaning(self) -> &'static str {
        match self.0 {
            0x0000 => "no error",
            0x1000 => "generic error",
            0x2310 => "continuous over-current",
            0x2320 => "short circuit / earth leakage",
            0x3210 => "DC-link over-voltage",
            0x3220 => "DC-link under-voltage",
            0x4210 => "excess device temperature",
            0x4310 => "excess drive temperature",
            0x5000 => "device hardware",
            0x6000 => "device software",
            0x7300 => "sensor",
            0x7305 => "incremental sensor 1 fault",
            0x8100 => "communication",
            0x8110 => "CAN overrun",
            0x8120 => "CAN error passive",
            0x8130 => "life guard or heartbeat error",
            0x8140 => "recovered from bus-off",
            0x8210 => "PDO not processed due to length error",
            0x8220 => "PDO length exceeded",
            0x8611 => "following error",
            0x9000 => "external error",
            0xFF00 => "device specific",
            c => match c >> 12 {
                0x1 => "generic error",
                0x2 => "current",
                0x3 => "voltage",
                0x4 => "temperature",
                0x5 => "device hardware",
                0x6 => "device software",
                0x7 => "additional modules",
                0x8 => "monitoring / communication",
                0x9 => "external error",
                0xF => "device specific",
                _ => "unknown error code",
            },
        }
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:#06x} ({})", self.0, self.meaning())
    }
}

impl fmt::Debug for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meanings() {
        assert_eq!(
            AbortCode::NO_OBJECT.to_string(),
            "0x06020000 (object does not exist in the object dictionary)"
        );
        assert_eq!(AbortCode(0x1234).meaning(), "unknown abort code");
        assert_eq!(
            ErrorCode(0x2310).to_string(),
            "0x2310 (continuous over-current)"
        );
        assert_eq!(ErrorCode(0x4321).meaning(), "temperature");
        assert_eq!(ErrorCode(0xA000).meaning(), "unknown error code");
    }
}
