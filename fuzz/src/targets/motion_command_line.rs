//! `motion-cmd` command lines, words separated by NUL bytes
//! ([`motion::fuzzing::command_line`]): parsed by the command table into
//! a command whose own command line parses back to it, or refused with a
//! message.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "motion_command_line",
    run: motion::fuzzing::command_line,
    dictionary: &[
        "\0", "jog-cont\0", "axis-jog-incr\0", "set-homing-params\0", "set-world-home\0",
        "line\0", "rapid\0", "arc\0", "probe\0", "term-cond\0", "feed-scale-enable\0",
        "update-homing-params\0", "comp-entry\0", "X=", "y=", "W=", "center=", "normal=",
        "turns=", ",", "G38.2", "g38.5", "blend", "stop", "exact", "on", "no", "HOME_SEQUENCE=",
        "HOME_ABSOLUTE_ENCODER=", "HOME_USE_INDEX=YES", "VOLATILE_HOME=", "=", "-1", "0", "2.5",
        "1e99", "NaN", "inf", "-0", "2147483648", "x", "q",
    ],
    generate: None,
};
