//! Xilinx bitfiles for the PLX-bridged Mesa cards
//! ([`hostmot2::fuzzing::bitfile`]): the header parser, then an
//! accepted file's bitstream clocked into simulated 5i20 and 5i22
//! bridges; accepted headers round-trip, DONE means a running design.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_bitfile",
    run: hostmot2::fuzzing::bitfile,
    dictionary: &["\u{0}\u{9}", "\u{0}\u{1}a", "2s200pq208", "3s1000fg320", "HM2S"],
    generate: Some(generate),
};

/// A simulator bitfile with a few random bytes written over it;
/// sometimes random bytes.
fn generate(rng: &mut fastrand::Rng) -> Vec<u8> {
    crate::edited_seed(rng, &hostmot2::fuzzing::seed_bitfiles())
}
