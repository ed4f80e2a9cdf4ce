//! Address and number tokens of module parameters through the driver
//! layer's parsers ([`hal_driver::fuzzing::number_token`]): in range,
//! or refused saying why.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "driver_number_token",
    run: hal_driver::fuzzing::number_token,
    dictionary: &["0x", "0X", "378", "0x378", "ffff", "10000", "0xffff", "0x10000", "-", "+", "0", "07", "08"],
    generate: None,
};
