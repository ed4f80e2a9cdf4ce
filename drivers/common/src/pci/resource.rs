//! The sysfs `resource` file of a PCI device: one line per region (BARs
//! 0..5, the expansion ROM, bridge windows), each `start end flags` as
//! `0x`-prefixed hex numbers. An unused region is all zeros.

use std::path::Path;

use crate::error::{DriverError, Result};

/// Flag bit of an I/O-port region (the kernel's `IORESOURCE_IO`).
pub const IORESOURCE_IO: u64 = 0x100;
/// Flag bit of a memory region (`IORESOURCE_MEM`).
pub const IORESOURCE_MEM: u64 = 0x200;
/// Flag bit of a prefetchable memory region (`IORESOURCE_PREFETCH`).
pub const IORESOURCE_PREFETCH: u64 = 0x2000;

/// One region of a device, as the `resource` file lists it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Resource {
    /// First address (bus address of a memory BAR, first port of an I/O
    /// BAR).
    pub start: u64,
    /// Last address (inclusive).
    pub end: u64,
    /// The kernel's resource flags.
    pub flags: u64,
}

impl Resource {
    /// Whether the region exists (a BAR the device implements).
    pub fn is_present(&self) -> bool {
        self.flags & (IORESOURCE_IO | IORESOURCE_MEM) != 0
            && self.end >= self.start
            && self.end != 0
    }

    /// Its size in bytes (0 when absent). A region claiming the whole
    /// 64-bit space (a corrupt file: found by the fuzz target) reads as
    /// u64::MAX bytes, which no mapping accepts.
    pub fn len(&self) -> u64 {
        if self.is_present() {
            (self.end - self.start).saturating_add(1)
        } else {
            0
        }
    }

    /// Whether it is absent.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether it is an I/O-port region.
    pub fn is_io(&self) -> bool {
        self.is_present() && self.flags & IORESOURCE_IO != 0
    }

    /// Whether it is a memory region.
    pub fn is_mem(&self) -> bool {
        self.is_present() && self.flags & IORESOURCE_MEM != 0
    }

    /// "an I/O BAR", "a memory BAR" or "unused", for messages.
    pub fn kind(&self) -> &'static str {
        if self.is_io() {
            "an I/O BAR"
        } else if self.is_mem() {
            "a memory BAR"
        } else {
            "unused"
        }
    }
}

fn hex(word: &str) -> Option<u64> {
    let digits = word
        .strip_prefix("0x")
        .or_else(|| word.strip_prefix("0X"))?;
    // from_str_radix alone would also take a sign.
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u64::from_str_radix(digits, 16).ok()
}

/// Parses the text of a `resource` file read from `path`.
pub fn parse(text: &str, path: &Path) -> Result<Vec<Resource>> {
    text.lines()
        .enumerate()
        .map(|(i, line)| {
            let nums: Vec<Option<u64>> = line.split_whitespace().map(hex).collect();
            match nums[..] {
                [Some(start), Some(end), Some(flags)] => Ok(Resource { start, end, flags }),
                _ => Err(DriverError::BadSysfs {
                    path: path.to_path_buf(),
                    reason: format!(
                        "line {}: expected three hex numbers (start end flags), found '{line}'",
                        i + 1
                    ),
                }),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_region_over_the_whole_address_space_does_not_overflow() {
        let r = Resource {
            start: 0,
            end: u64::MAX,
            flags: IORESOURCE_MEM,
        };
        assert_eq!(r.len(), u64::MAX);
    }

    #[test]
    fn parses_the_kernel_format() {
        let text = "0x00000000fea00000 0x00000000fea0ffff 0x0000000000040200\n\
                    0x000000000000e000 0x000000000000e0ff 0x0000000000040101\n\
                    0x0000000000000000 0x0000000000000000 0x0000000000000000\n";
        let r = parse(text, Path::new("resource")).unwrap();
        assert_eq!(r.len(), 3);
        assert!(r[0].is_mem() && !r[0].is_io());
        assert_eq!(r[0].len(), 0x10000);
        assert!(r[1].is_io());
        assert_eq!((r[1].start, r[1].len()), (0xe000, 0x100));
        assert!(!r[2].is_present());
        assert_eq!(r[2].len(), 0);
        assert_eq!(r[2].kind(), "unused");
    }

    #[test]
    fn garbage_names_the_line() {
        let e = parse("0x0 0x0 0x0\n0x10 zz 0x200\n", Path::new("/x/resource"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/x/resource: line 2"), "{e}");
        assert!(parse("0x0 0x0\n", Path::new("r")).is_err());
        assert!(
            parse("0x+1 0x2 0x200\n", Path::new("r")).is_err(),
            "no signs"
        );
        assert!(parse("0x1 0x10000000000000000 0x200\n", Path::new("r")).is_err());
    }
}
