//! mesambccc's XML command sources ([`hostmot2::fuzzing::mbccs_source`]):
//! refusals name a line of the text, accepted sources compile to files
//! hm2_modbus loads back unchanged.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_mbccs",
    run: hostmot2::fuzzing::mbccs_source,
    dictionary: &[
        "<command ", "</command>", "<pin ", "device=\"dev\"", "function=\"W_REGISTER\"",
        "modbustype=\"F_AB\"", "haltype=\"HAL_S64\"", "count=\"125\"", "skip=\"24\"",
        "interval=\"once\"", "value=\"0xff00\"", "address=\"65535\"",
    ],
    generate: Some(generate),
};

/// The sample source with a few random bytes written over it.
fn generate(rng: &mut fastrand::Rng) -> Vec<u8> {
    crate::edited_seed(rng, &[hostmot2::fuzzing::SEED_MBCCS.as_bytes().to_vec()])
}
