//! The XHC-HB04 pendant's input reports as hidraw gives them
//! ([`hal_usb::fuzzing::xhc_input_report`]): decoded from the bytes they
//! came from, or refused as short or of another report id.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "xhc_input_report",
    run: hal_usb::fuzzing::xhc_input_report,
    dictionary: &["\x04", "\x11", "\x12", "\x13", "\x14", "\x15", "\x18", "\x00\x00\x00\x00\x00"],
    generate: Some(crate::random_bytes),
};
