//! SII EEPROM images ([`hal_ethercat::fuzzing::sii`]): an accepted image
//! written again reads back the same.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ethercat_sii",
    run: hal_ethercat::fuzzing::sii,
    dictionary: &[],
    generate: Some(generate),
};

/// The image of a simulated device with a few random bytes written over
/// it; sometimes random bytes.
fn generate(rng: &mut fastrand::Rng) -> Vec<u8> {
    crate::edited_seed(rng, &hal_ethercat::fuzzing::seed_sii_images())
}
