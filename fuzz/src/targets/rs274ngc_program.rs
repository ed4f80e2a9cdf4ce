//! Programs through the RS274NGC interpreter
//! ([`rs274ngc::fuzzing::program`]): reading and executing never panic,
//! a refusal names a line and column of the input, loops are bounded.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "rs274ngc_program",
    run: rs274ngc::fuzzing::program,
    dictionary: &[
        "G0 ", "G1 ", "G2 ", "G3 ", "G5.2", "G10 L2 P", "G17", "G18", "G20", "G21", "G28", "G38.2", "G41.1 D", "G40",
        "G43 H", "G53", "G54", "G81 R", "G83 Q", "G90", "G91", "G92", "G93", "X", "Y", "Z", "I", "J", "R", "P", "Q",
        "L", "F", "S", "T", "M6", "M98 P", "M99", "#", "#<", ">", "[", "]", "**", " MOD ", " AND ", "SIN[", "ATAN[",
        "]/[", "EXISTS[", "o100 sub", "o100 endsub", "o100 call", "o1 while [", "o1 endwhile", "o2 if [", "o2 endif",
        "(MSG,", "(DEBUG,", "%", "(", ")", ";", "\n", "99999999", "1e300", "@", "^",
    ],
    generate: None,
};
