//! LBP16 request datagrams from anyone on the network to the simulated
//! Ethernet board ([`hostmot2::fuzzing::lbp16_request`]): a refused one is
//! counted and answered with nothing, an answered one has exactly the
//! bytes its reads ask for.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_lbp16_request",
    run: hostmot2::fuzzing::lbp16_request,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
