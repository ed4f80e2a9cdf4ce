//! Joint compensation files of both kinds
//! ([`motion::comp_file::fuzz_comp_file`]): an accepted table loads
//! whole into a joint.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "comp_file",
    run: motion::comp_file::fuzz_comp_file,
    dictionary: &[" ", "\t", "\n", "#", "-", "e-3", "0.001"],
    generate: None,
};
