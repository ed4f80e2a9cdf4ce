//! EtherCAT mailbox areas from either side
//! ([`hal_ethercat::fuzzing::mailbox`]): the CoE parsers, which must
//! round-trip what they accept, and the simulated SDO server, which must
//! answer only with mailboxes the master can parse.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ethercat_mailbox",
    run: hal_ethercat::fuzzing::mailbox,
    dictionary: &[],
    generate: Some(generate),
};

/// An SDO request or response, emergency or mailbox error, with a few
/// random bytes written over it; sometimes random bytes.
fn generate(rng: &mut fastrand::Rng) -> Vec<u8> {
    crate::edited_seed(rng, &hal_ethercat::fuzzing::seed_mailboxes())
}
