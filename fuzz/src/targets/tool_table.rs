//! Tool tables, random-toolchanger or not, parsed, written and parsed
//! again ([`hal_launcher::fuzz::tool_table`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "tool_table",
    run: hal_launcher::fuzz::tool_table,
    dictionary: &["T", "P", "D", "X", "Y", "Z", "A", "I", "J", "Q", ";", " ", "\n", "T1 P1 D0.125 Z+0.511 ;1/8 end mill\n"],
    generate: None,
};
