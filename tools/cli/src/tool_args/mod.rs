//! The clap definitions of the tools that are not LinuxCNC-compatible by
//! contract, in the library so tools/cli/tests/man_pages.rs builds their man
//! pages (packaging/man/) from the same definitions as `--help`.

pub mod gcode_run;
pub mod linuxcncrsh;
pub mod motion_cmd;
pub mod motion_plot;
