//! Request lines a linuxcncrsh client sends ([`hal_tools::rsh::fuzz::lines`]):
//! line splitting and its bound, hello/get/set/help parsing, the replies.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "linuxcncrsh_line",
    run: hal_tools::rsh::fuzz::lines,
    dictionary: &[
        "hello EMC x 1.0\n", "set enable EMCTOO\n", "get ", "set ", "help", "quit", "shutdown",
        "\r\n", "mdi", "spindle", "brake", "-1", "99", "on", "off", "abs_act_pos", "joint_limit",
        "mode", "mdi", "timeout", "1e308", "nan", "open", "home", "jog_incr", "program_codes",
        "error", "x",
    ],
    generate: None,
};
