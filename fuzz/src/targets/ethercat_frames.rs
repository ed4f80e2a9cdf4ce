//! EtherCAT frames from the wire ([`hal_ethercat::fuzzing::frames`]): the
//! frame parser, the simulated segment processing them, and EtherCrab's
//! reception with a frame of its own in flight. Spans stay inside the
//! frame, the segment keeps the frame's length and returns only frames
//! that parse.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ethercat_frames",
    run: hal_ethercat::fuzzing::frames,
    dictionary: &[],
    generate: Some(generate),
};

/// A frame a master sends (or the segment's answer to it), with a few
/// random bytes written over it; sometimes random bytes.
fn generate(rng: &mut fastrand::Rng) -> Vec<u8> {
    crate::edited_seed(rng, &hal_ethercat::fuzzing::seed_frames())
}
