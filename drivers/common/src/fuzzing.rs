//! Bodies of the fuzz targets for the layer's parsers of outside bytes
//! (sysfs files, address tokens). Each takes arbitrary bytes, must never
//! panic, and checks that every rejection says what was wrong and where.
//! Until the workspace's `fuzz/` crate is on main they run from this
//! crate's proptest (`tests/fuzz_parsers.rs`); the fuzz crate can call
//! them as they are.

use std::path::Path;

use crate::error::DriverError;
use crate::params::{parse_hex, parse_number, NumberError};
use crate::pci::{self, resource};

/// A sysfs `resource` file: parsed, or refused naming the file and line;
/// parsed regions are self-consistent.
pub fn resource_file(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let path = Path::new("/sys/bus/pci/devices/0000:01:00.0/resource");
    match resource::parse(&text, path) {
        Ok(regions) => {
            assert_eq!(regions.len(), text.lines().count());
            for r in regions {
                if r.is_present() {
                    assert!(r.end >= r.start && r.len() == (r.end - r.start).saturating_add(1));
                    assert!(r.is_io() || r.is_mem());
                } else {
                    assert_eq!(r.len(), 0);
                }
            }
        }
        Err(DriverError::BadSysfs { path: p, reason }) => {
            assert_eq!(p, path);
            assert!(reason.starts_with("line "), "{reason}");
        }
        Err(e) => panic!("unexpected error kind: {e}"),
    }
}

/// A sysfs ID file (`vendor`, `device`, ...): a 16-bit value that prints
/// back to the same digits, or refused naming the file.
pub fn id_file(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let path = Path::new("/sys/bus/pci/devices/0000:01:00.0/vendor");
    match pci::parse_id(&text, path) {
        Ok(id) => {
            let digits = text.trim().trim_start_matches("0x");
            assert_eq!(u16::from_str_radix(digits, 16).ok(), Some(id));
        }
        Err(e) => assert!(
            e.to_string().contains("vendor: expected a 16-bit ID"),
            "{e}"
        ),
    }
}

/// The kernel's lockdown file: any text gives an answer, never a panic.
pub fn lockdown_file(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let active = crate::lockdown::parse(&text);
    if !text.contains('[') {
        assert!(!active);
    }
}

/// An address token in hex (hal_parport's `cfg`) and in C notation
/// (integer parameters): in range, or refused saying why.
pub fn number_token(bytes: &[u8]) {
    let token = String::from_utf8_lossy(bytes);
    let max = 0xFFFF;
    match parse_hex(&token, max) {
        Ok(v) => assert!(v <= max),
        Err(NumberError::BadHexDigit(c)) => assert!(token.contains(c)),
        Err(e) => assert!(!e.to_string().is_empty()),
    }
    match parse_number(&token, max) {
        Ok(v) => assert!(v <= max),
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}
