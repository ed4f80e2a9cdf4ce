//! Parameter (`.var`) files ([`rs274ngc::fuzzing::parameter_file`]):
//! accepted numbers are in range and ascending.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "rs274ngc_parameter_file",
    run: rs274ngc::fuzzing::parameter_file,
    dictionary: &["\t", " ", "\n", "5161", "5220", "5221", "5390", "5399", "5601", "-0.0", "1.000000", "nan"],
    generate: None,
};
