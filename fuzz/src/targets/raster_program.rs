//! The bytes `raster` takes from its `program` port: the header fields
//! and the hex pixels, followed along a walk of positions
//! ([`hal_components::fuzz_raster_program`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "raster_program",
    run: hal_components::fuzz_raster_program,
    dictionary: &[";", "0", "1", "4", "8", "32", "-", ".", "e", "F", "FF", "nan", "inf"],
    generate: None,
};
