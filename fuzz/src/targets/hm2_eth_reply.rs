//! hm2_eth's handling of a datagram that comes while it waits for a
//! cycle's reply ([`hostmot2::fuzzing::eth_reply`]), without a socket: only
//! a datagram of the expected length echoing the cycle's read tag is
//! taken, and a lost write is told exactly when the write tag differs.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_eth_reply",
    run: hostmot2::fuzzing::eth_reply,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
