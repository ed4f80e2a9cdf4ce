//! `setsserial`'s `cmd=` string ([`hostmot2::fuzzing::setsserial_cmd`]):
//! a command of three words or a refusal saying why.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_setsserial_cmd",
    run,
    dictionary: &["set ", "flash ", "hm2_5i25.0.7i77.0.0", ".nvbaudrate", " 0x", ".BIN", " -", " "],
    generate: None,
};

/// The command is text: bytes that are not UTF-8 become U+FFFD.
fn run(input: &[u8]) {
    hostmot2::fuzzing::setsserial_cmd(&String::from_utf8_lossy(input));
}
