//! Tool tables as the RS274NGC interpreter's rs274 reads them
//! ([`rs274ngc::fuzzing::tool_table`]): lettered and old formats, the
//! size limit on the number of tools.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "rs274ngc_tool_table",
    run: rs274ngc::fuzzing::tool_table,
    dictionary: &["T", "P", "D", "X", "Z", "I", "J", "Q", " ", ";", "\n", "99999", "-1", "0.5"],
    generate: None,
};
