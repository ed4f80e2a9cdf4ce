//! hal_input's command line, arguments separated by NUL bytes
//! ([`hal_input::fuzzing::command_line`]): inputspecs with subset
//! options, or a refusal; every word through the shell-pattern matcher.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "input_command_line",
    run: hal_input::fuzzing::command_line,
    dictionary: &[
        "\0-K\0", "\0-R\0", "\0-A\0", "\0-L\0", "\0-KRAL\0", "\0-W\0", "\0--sim\0", "\0-h\0",
        "+", ":", ":1", "*", "?", "[", "]", "[!", "a-z", "Mouse", "/dev/input/event3", "0",
    ],
    generate: None,
};
