//! TWOPASS's merging of `loadrt` lines
//! ([`hal_launcher::fuzz::twopass_loadrt`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "twopass_loadrt",
    run: hal_launcher::fuzz::twopass_loadrt,
    dictionary: &["loadrt ", "count=", "names=", ",", "\n", "and2", "or2", "pid", "threads", "#NOTWOPASS", "#notwopass", " "],
    generate: None,
};
