//! Part programs through the G-code interpreter
//! ([`hal_launcher::fuzz::part_program`]): a refusal names a place
//! in the input, what is sent is finite.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "part_program",
    run: hal_launcher::fuzz::part_program,
    dictionary: &["G0 ", "G1 ", "G2 ", "G3 ", "G17", "G20", "G21", "G90", "G91", "G4 P", "X", "Y", "Z", "I", "J", "R", "F", "S", "T", "N", "M2", "M3", "M5", "M6", "M30", "%", "(", ")", ";", "\n", "99999999", "100000000"],
    generate: None,
};
