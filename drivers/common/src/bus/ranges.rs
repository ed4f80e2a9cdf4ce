//! The I/O port ranges a port backend is opened for. An access outside
//! them is refused in the accessor (counted, reads all ones), so a wrong
//! address in a driver can never reach another device's ports.

use crate::error::{DriverError, Result};

/// `len` consecutive I/O ports from `base`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortRange {
    /// The first port.
    pub base: u16,
    /// How many ports (at least 1).
    pub len: u16,
}

impl PortRange {
    /// The range `base .. base + len`, refused when empty or when it runs
    /// past port 0xffff.
    pub fn new(base: u16, len: u16) -> Result<PortRange> {
        if len == 0 || base.checked_add(len - 1).is_none() {
            return Err(DriverError::Unsupported {
                what: format!("I/O ports {base:#x}+{len:#x}"),
                reason: if len == 0 {
                    "an empty range".into()
                } else {
                    "the range runs past 0xffff".into()
                },
            });
        }
        Ok(PortRange { base, len })
    }

    /// The last port of the range.
    pub fn last(&self) -> u16 {
        self.base + (self.len - 1)
    }

    /// Whether the `width` bytes from `port` lie inside the range.
    #[inline]
    pub fn covers(&self, port: u16, width: u16) -> bool {
        port >= self.base && (port - self.base) as u32 + width as u32 <= self.len as u32
    }
}

impl std::fmt::Display for PortRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:#x}..{:#x}", self.base, self.last())
    }
}

/// Whether any of `ranges` holds the whole access.
#[inline]
pub(crate) fn allowed(ranges: &[PortRange], port: u16, width: u16) -> bool {
    ranges.iter().any(|r| r.covers(port, width))
}

/// The ranges, for messages: `0x378..0x37f, 0x778..0x77a`.
pub(crate) fn describe(ranges: &[PortRange]) -> String {
    ranges
        .iter()
        .map(|r| r.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covers_whole_accesses_only() {
        let r = PortRange::new(0x378, 8).unwrap();
        assert!(r.covers(0x378, 1) && r.covers(0x37f, 1) && r.covers(0x37c, 4));
        assert!(!r.covers(0x37e, 4), "runs past the end");
        assert!(!r.covers(0x377, 1) && !r.covers(0x380, 1));
        assert_eq!(r.to_string(), "0x378..0x37f");
        assert!(PortRange::new(0xfffc, 8).is_err());
        assert!(PortRange::new(0x300, 0).is_err());
        assert_eq!(PortRange::new(0xfff8, 8).unwrap().last(), 0xffff);
    }
}
