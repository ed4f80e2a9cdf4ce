//! z_level_compensation's probe map file, parsed and triangulated
//! ([`hal_launcher::fuzz::probe_points`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "probe_points",
    run: hal_launcher::fuzz::probe_points,
    dictionary: &[
        " ", "\n", "#", "0", "1", "-", ".", "e", "10", "0.5", "-0.25", "1e9", "nan", "inf",
    ],
    generate: None,
};
