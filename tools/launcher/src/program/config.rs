//! The interpreter's settings from the machine's INI file, as LinuxCNC's
//! task reads them: `[RS274NGC]PARAMETER_FILE` and `SUBROUTINE_PATH`,
//! `[EMCIO]` tool change options, `[DISPLAY]PROGRAM_PREFIX`, the
//! directories searched for user M-codes (`[RS274NGC]USER_M_PATH`),
//! `[TRAJ]LINEAR_UNITS` and `SPINDLES`, the axes of `[TRAJ]COORDINATES`
//! with their `[AXIS_L]` velocity and acceleration limits, and whether
//! AUTO needs homed joints (`[TRAJ]NO_FORCE_HOMING`).

use std::path::{Path, PathBuf};

use hal_lang::ini::Ini;
use rs274ngc::Config;

use super::canon::AxisRates;
use crate::config::axis_letters;

/// What the program side of task needs from the INI file.
#[derive(Debug, Clone)]
pub struct ProgramConfig {
    /// The interpreter's configuration.
    pub interp: Config,
    /// Machine units per millimetre (1 for mm, 1/25.4 for inch).
    pub user_per_mm: f64,
    /// The machine's axes, bit 0 X ... bit 8 W.
    pub axis_mask: u32,
    /// AUTO and MDI are allowed before homing.
    pub no_force_homing: bool,
    /// Where task looks for the user M-code programs M100 to M199, in
    /// order: the program prefix (`nc_files` beside the INI file without
    /// one), then the first five directories of `USER_M_PATH`.
    pub user_m_dirs: Vec<PathBuf>,
    /// `[TASK]IO_ERROR`: the text of a hard tool changer fault, its `%d`
    /// the reason (LinuxCNC's default "toolchanger error %d").
    pub io_error: String,
    /// `[EMCIO]TOOL_CHANGE_POSITION`: where M6 traverses before the
    /// change, machine coordinates and units, for X Y Z (3 numbers),
    /// X Y Z A B C (6) or all nine axes (9); the others stay where they
    /// are. None without one.
    pub tool_change_position: Option<[Option<f64>; 9]>,
    /// `RS274NGC_STARTUP_CODE` ([EMC] first, then [RS274NGC], as
    /// LinuxCNC's task looks): G-code the interpreter runs each time it
    /// starts, before anything else. None when unset or blank.
    pub startup_code: Option<String>,
    /// Each axis's `[AXIS_L]MAX_VELOCITY` and `MAX_ACCELERATION`, from
    /// which each move's path limits are worked out (no limit for an
    /// axis without them).
    pub axis_rates: AxisRates,
}

/// `[EMCIO]TOOL_CHANGE_POSITION` read as LinuxCNC reads it: 3, 6 or 9
/// numbers. Anything else is said (with where it is) and ignored, as
/// LinuxCNC ignores it.
fn tool_change_position(ini: &Ini) -> Option<[Option<f64>; 9]> {
    let e = ini.entry("EMCIO", "TOOL_CHANGE_POSITION")?;
    let numbers: Option<Vec<f64>> = e
        .value
        .split_whitespace()
        .map(|w| w.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect();
    match numbers {
        Some(v) if matches!(v.len(), 3 | 6 | 9) => {
            let mut p = [None; 9];
            for (slot, value) in p.iter_mut().zip(v) {
                *slot = Some(value);
            }
            Some(p)
        }
        _ => {
            eprintln!(
                "{}: warning: [EMCIO]TOOL_CHANGE_POSITION '{}' is not 3, 6 or 9 numbers: ignored",
                e.origin,
                e.value.trim()
            );
            None
        }
    }
}

fn flag(ini: &Ini, section: &str, key: &str) -> bool {
    ini.get(section, key).is_some_and(|v| {
        let v = v.trim();
        v == "1" || v.eq_ignore_ascii_case("true") || v.eq_ignore_ascii_case("yes")
    })
}

/// A path of the INI file, relative to its folder.
fn relative(dir: &Path, value: &str) -> PathBuf {
    let p = Path::new(value.trim());
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        dir.join(p)
    }
}

impl ProgramConfig {
    /// The settings of `ini`.
    pub fn from_ini(ini: &Ini) -> ProgramConfig {
        let dir = ini.dir();
        let mut interp = Config {
            parameter_file: ini
                .get("RS274NGC", "PARAMETER_FILE")
                .map(|v| relative(&dir, v)),
            random_toolchanger: flag(ini, "EMCIO", "RANDOM_TOOLCHANGER"),
            tool_change_quill_up: flag(ini, "EMCIO", "TOOL_CHANGE_QUILL_UP"),
            tool_change_at_g30: flag(ini, "EMCIO", "TOOL_CHANGE_AT_G30"),
            tool_change_with_spindle_on: flag(ini, "EMCIO", "TOOL_CHANGE_WITH_SPINDLE_ON"),
            features: rs274ngc::Features::from_ini_keys(|key| ini.get("RS274NGC", key)),
            ..Config::default()
        };
        if let Some(paths) = ini.get("RS274NGC", "SUBROUTINE_PATH") {
            interp.subroutine_path = paths
                .split(':')
                .filter(|s| !s.trim().is_empty())
                .map(|s| relative(&dir, s))
                .collect();
        }
        if let Some(n) = ini
            .get("TRAJ", "SPINDLES")
            .and_then(|v| v.trim().parse::<u32>().ok())
        {
            interp.spindles = n;
        }
        if let Some(prefix) = ini.get("DISPLAY", "PROGRAM_PREFIX") {
            interp.program_prefix = Some(relative(&dir, prefix));
        }
        let mut user_m_dirs = vec![interp
            .program_prefix
            .clone()
            .unwrap_or_else(|| dir.join("nc_files"))];
        if let Some(paths) = ini.get("RS274NGC", "USER_M_PATH") {
            user_m_dirs.extend(
                paths
                    .split(':')
                    .filter(|s| !s.trim().is_empty())
                    .take(super::user_m::MAX_USER_M_DIRS)
                    .map(|s| relative(&dir, s)),
            );
        }
        if let Some(v) = ini
            .get("RS274NGC", "ORIENT_OFFSET")
            .and_then(|v| v.trim().parse::<f64>().ok())
        {
            interp.orient_offset = v;
        }
        let units = ini.get("TRAJ", "LINEAR_UNITS").unwrap_or("mm").trim();
        let user_per_mm = match units {
            "inch" | "in" | "imperial" => 1.0 / 25.4,
            "cm" => 0.1,
            // A number is machine units per millimetre, as LinuxCNC reads it.
            _ => units
                .parse::<f64>()
                .ok()
                .filter(|v| *v > 0.0)
                .unwrap_or(1.0),
        };
        let mut axis_rates = AxisRates::default();
        for &(axis, letter) in &axis_letters(ini) {
            // A bad value is refused when motion is configured.
            if let Ok(l) = crate::config::AxisLimits::from_ini(ini, letter) {
                axis_rates.vel[axis] = l.max_velocity;
                axis_rates.acc[axis] = l.max_acceleration;
            }
        }
        let mut axis_mask = axis_letters(ini)
            .iter()
            .fold(0u32, |m, (axis, _)| m | (1 << axis));
        if axis_mask == 0 {
            axis_mask = 0b111;
        }
        ProgramConfig {
            interp,
            user_per_mm,
            axis_mask,
            axis_rates,
            no_force_homing: flag(ini, "TRAJ", "NO_FORCE_HOMING"),
            user_m_dirs,
            io_error: ini
                .get("TASK", "IO_ERROR")
                .map_or("toolchanger error %d", str::trim)
                .to_string(),
            tool_change_position: tool_change_position(ini),
            startup_code: ["EMC", "RS274NGC"]
                .iter()
                .filter_map(|section| ini.get(section, "RS274NGC_STARTUP_CODE"))
                .map(str::trim)
                .find(|code| !code.is_empty())
                .map(str::to_string),
        }
    }
}
