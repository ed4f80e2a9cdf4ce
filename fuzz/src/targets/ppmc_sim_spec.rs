//! hal_ppmc's `sim=` board list ([`hal_ppmc::fuzzing::sim_spec`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ppmc_sim_spec",
    run: hal_ppmc::fuzzing::sim_spec,
    dictionary: &["ppmc", "usc", "upc", "encoder", "dac", "dio", "+", ":2", ":4"],
    generate: None,
};
