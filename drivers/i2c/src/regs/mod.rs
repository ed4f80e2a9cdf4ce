//! The register maps of the supported chips (hardware.md 7.2), as named
//! constants.

pub mod ads1115;
pub mod mcp23017;
pub mod pca9685;
