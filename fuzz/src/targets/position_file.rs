//! `[TRAJ]POSITION_FILE`'s saved joint positions, parsed, written back
//! and read again ([`hal_launcher::fuzz::position_file`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "position_file",
    run: hal_launcher::fuzz::position_file,
    dictionary: &[
        " ", "\n", "\t", "0", "1", "-", ".", "e", "0.50000000000000000", "1e308", "nan", "inf",
    ],
    generate: None,
};
