//! hm2_modbus `.mbccb` command files ([`hostmot2::fuzzing::mbccb_file`]):
//! the parser (refusals name an offset in the file), the encoder's round
//! trip, and the Modbus engine running an accepted file against replies
//! cut from the same bytes.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_mbccb",
    run: hostmot2::fuzzing::mbccb_file,
    dictionary: &["MesaMB01", "\u{0}\u{0}\u{0}\u{20}", "\u{22}\u{2}\u{3}\u{0}"],
    generate: Some(generate),
};

/// A sample file with a few random bytes written over it; sometimes
/// random bytes.
fn generate(rng: &mut fastrand::Rng) -> Vec<u8> {
    crate::edited_seed(rng, &hostmot2::fuzzing::seed_mbccbs())
}
