//! Messages arriving at an SPI HostMot2 board through Mesa's SPI
//! framing ([`hostmot2::fuzzing::spi_frames`]): command words
//! round-trip, refusals say why and stop the message.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_spi_frames",
    run: hostmot2::fuzzing::spi_frames,
    dictionary: &[],
    generate: Some(crate::random_bytes),
};
