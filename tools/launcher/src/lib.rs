//! The launcher: a machine's INI file run headless, as LinuxCNC's
//! `linuxcnc` script runs it ([`run`]): the HAL files in LinuxCNC's order
//! (with TWOPASS and the rules for GUI-only lines), the pins task and
//! iocontrol create, the motion controller configured from the INI file,
//! task's requests (`task-cmd`, [`request`]) and the safe state at the end.
//! [`part_program`] runs G-code through the interpreter on a live motion
//! controller (`gcode-run`). [`halui`] is LinuxCNC's HAL user interface,
//! a client of task. [`zlevel`] is `z_level_compensation`, the Z offset
//! from a probed surface map. [`sim_torch`] is `sim-torch`, the simulated
//! plasma torch of LinuxCNC's QtPlasmaC sim configurations. [`panelui`]
//! is LinuxCNC's operator panel, key matrix codes from a sampler turned
//! into button pins and task commands.

#![forbid(unsafe_code)]

mod config;
mod display;
mod error;
mod hal_side;
mod halfiles;
pub mod halui;
mod iocontrol;
mod machine;
mod motion_setup;
mod old_format;
pub mod panelui;
pub mod part_program;
mod position_file;
mod program;
mod rules;
pub mod sim_torch;
mod task;
mod task_help;
mod task_manual;
mod task_messages;
mod task_mode_filter;
mod task_motion;
mod task_panel;
mod task_pins;
mod task_program;
mod task_request;
mod task_socket;
mod task_spindle;
mod task_stat;
mod task_stat_joint;
mod task_tool_offset;
mod task_traj;
mod twopass;
pub mod zlevel;

pub use error::LaunchError;
pub use machine::{
    asks_for_twopass, load_ini, parse_args, report_skipped, run, run_twopass, search_path,
    HalStartup, Options, USAGE,
};
pub use program::{ProgramConfig, ProgramError, RunState};
pub use rules::Rules;
pub use task_help::REQUESTS;
pub use task_socket::{request, TaskAnswer, TaskClientError};

/// Entry points of the fuzz targets (fuzz/README.md) for the launcher's
/// parsers of outside bytes.
pub mod fuzz {
    pub use crate::halui::fuzz_state as task_state;
    pub use crate::iocontrol::tooltable::fuzz_parse as tool_table;
    pub use crate::old_format::fuzz_convert as old_format_config;
    pub use crate::panelui::fuzz_config as panelui_config;
    pub use crate::part_program::fuzz_program as part_program;
    pub use crate::position_file::fuzz_parse as position_file;
    pub use crate::task::fuzz_request as task_request;
    pub use crate::twopass::fuzz_gather as twopass_loadrt;
    pub use crate::zlevel::probe::fuzz_parse as probe_points;
}
