//! The EPP transport and the IDROM loader of hm2_7i43/hm2_7i90 on a
//! parallel port whose reads the input edits
//! ([`hostmot2::fuzzing::epp_port`]): failures are EPP timeouts or bus
//! errors, refusals say why, and the board answers again afterwards.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_epp_port",
    run: hostmot2::fuzzing::epp_port,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
