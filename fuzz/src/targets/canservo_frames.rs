//! canservo's parsers of CAN frames ([`hal_canservo::fuzzing::frames`]):
//! frames decoded from the bytes through the realtime engine's reception,
//! the SDO client against a hostile server, the simulated drive and the
//! bring-up tool's decoder. A read never takes more frames than its
//! budget and an SDO transfer always ends.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "canservo_frames",
    run,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};

/// The body returns how many frames it used; only its panics matter.
fn run(input: &[u8]) {
    hal_canservo::fuzzing::frames(input);
}
