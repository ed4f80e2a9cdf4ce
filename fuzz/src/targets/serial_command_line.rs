//! The command lines of `hy_vfd` and `hy_gt_vfd`, arguments separated by
//! NUL bytes ([`hal_serial::fuzzing::command_line`]): parsed into
//! options in range, or refused with a message.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "serial_command_line",
    run: hal_serial::fuzzing::command_line,
    dictionary: &[
        "\0-d\0", "\0-n\0", "\0-r\0", "\0-F\0", "\0-f\0", "\0-B\0", "\0-V\0", "\0-I\0",
        "\0--period\0", "\0--register\0", "\0--retries\0", "sim", "/dev/ttyUSB0", "19200",
        "-1", "0", "255", "65536",
    ],
    generate: None,
};
