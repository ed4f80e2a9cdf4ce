//! INI files, `#INCLUDE`s served from the same bytes
//! ([`hal_lang::ini::fuzz_parse`]): include depth and recursion limits,
//! escapes, every value read as a number.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ini_file",
    run: hal_lang::ini::fuzz_parse,
    dictionary: &["[", "]", "[HAL]", "[EMCMOT]", "[JOINT_0]", "=", " = ", "#", ";", "\\", "\\\n", "\n", "#INCLUDE ", "#INCLUDE a.inc\n", "\\x41", "\\u0041", "\\U0001f600", "\\ud83d", "\\0", "\\377", "\r"],
    generate: None,
};
