//! hal_stg's `dio=` parameter ([`hal_stg::fuzzing::dio_param`]): what
//! parses prints back as given.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "stg_dio_param",
    run: hal_stg::fuzzing::dio_param,
    dictionary: &["I", "O", "i", "o", "IIOO", "OOII", "IOIO"],
    generate: None,
};
