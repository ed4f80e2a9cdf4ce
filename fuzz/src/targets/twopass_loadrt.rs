//! TWOPASS's merging of `loadrt` lines
//! ([`hal_tools::launcher::twopass::fuzz_gather`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "twopass_loadrt",
    run: hal_tools::launcher::twopass::fuzz_gather,
    dictionary: &["loadrt ", "count=", "names=", ",", "\n", "and2", "or2", "pid", "threads", "#NOTWOPASS", "#notwopass", " "],
    generate: None,
};
