//! canservo's `loadrt` parameters parsed as the module does, up to
//! opening the bus ([`hal_canservo::fuzzing::module_params`]): every error
//! names the module; an accepted line has one node, scale and home per
//! drive, node ids 1..=127 without repeats, finite non-zero scales.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "canservo_module_params",
    run,
    dictionary: &[
        "nodes=", "scale=", "sim_home=", "drive_file=", "backend=sim", "backend=socketcan",
        "iface=", "period_ns=", "mode=", "sync=", "127", "128", "0", ",", " ",
    ],
    generate: None,
};

/// The body returns whether the line was accepted; only its panics
/// matter.
fn run(input: &[u8]) {
    hal_canservo::fuzzing::module_params(input);
}
