//! Request lines arriving on task's socket
//! ([`hal_launcher::fuzz::task_request`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "task_request",
    run: hal_launcher::fuzz::task_request,
    dictionary: &[
        "\u{1f}", "stat", "state", "status", "set-dout", "set-aout", "messages", "message",
        "error", "text", "display", "mode", "mdi", "run", "open", "home", "jog-incr",
        "spindle", "coolant", "on", "off", "all", "0", "63", "64", "-1", "1e308", "nan",
        "reset-interpreter", "x",
    ],
    generate: None,
};
