//! What a read of an evdev event node returns, as hal_input decodes it
//! ([`hal_input::fuzzing::event_records`]): whole `input_event` records
//! decoded one event each (and encoding back to their type, code and
//! value), any other length refused with nothing decoded.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "input_event_records",
    run: hal_input::fuzzing::event_records,
    dictionary: &["\x01\x00\x1e\x00\x01\x00\x00\x00", "\x02\x00\x08\x00\x7f\x7f\x7f\x7f", "\x00\x00\x03\x00"],
    generate: Some(crate::random_bytes),
};
