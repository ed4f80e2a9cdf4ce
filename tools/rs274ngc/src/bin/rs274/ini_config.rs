//! The INI keys rs274 takes from `-i`: `[RS274NGC]` `SUBROUTINE_PATH`,
//! `USER_M_PATH`, the feature keys (`INI_VARS`, `OWORD_NARGS`, ...),
//! tolerances, G92 persistence, Fanuc subroutines, `ORIENT_OFFSET`;
//! `[EMCIO]` tool change options and
//! `RANDOM_TOOLCHANGER`; `[DISPLAY]PROGRAM_PREFIX`; `[TRAJ]SPINDLES`;
//! every entry for `#<_ini[section]key>`. The only use of the INI parser
//! in this crate is here.

use std::path::{Path, PathBuf};

use hal_lang::Ini;
use rs274ngc::{Config, Features};

/// Largest INI file (or included file) read: the suite's limit for INI
/// files, as `linuxcnc` reads them.
const MAX_INI_BYTES: u64 = hal_core::files::limits::INI;

/// Paths in a colon-separated list that exist, as absolute paths.
fn path_list(value: &str) -> Vec<PathBuf> {
    value
        .split(':')
        .filter(|s| !s.is_empty())
        .filter_map(|s| std::fs::canonicalize(expand_tilde(s)).ok())
        .collect()
}

fn expand_tilde(s: &str) -> PathBuf {
    match (s.strip_prefix("~/"), std::env::var_os("HOME")) {
        (Some(rest), Some(home)) => Path::new(&home).join(rest),
        _ => PathBuf::from(s),
    }
}

fn flag(ini: &Ini, section: &str, key: &str) -> bool {
    ini.get(section, key)
        .map(|v| {
            let v = v.trim();
            v == "1" || v.eq_ignore_ascii_case("true") || v.eq_ignore_ascii_case("yes")
        })
        .unwrap_or(false)
}

fn number(ini: &Ini, section: &str, key: &str) -> Option<f64> {
    ini.get(section, key).and_then(|v| v.trim().parse().ok())
}

/// Read the interpreter's options from an INI file into `config`; false
/// if the file cannot be read.
pub fn apply(path: &Path, config: &mut Config) -> bool {
    // Regular files of bounded size only (an INI of /dev/zero is refused,
    // not read forever), includes too.
    let mut read = |file: &Path| -> std::io::Result<String> {
        let bytes = rs274ngc::read_bounded(file, MAX_INI_BYTES, "INI file")
            .map_err(std::io::Error::other)?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    };
    let Ok(ini) = Ini::parse_with(path, &mut read) else {
        return false;
    };
    // Standalone rs274 takes its parameter file from -v only; LinuxCNC's
    // [RS274NGC]PARAMETER_FILE is for task.
    config.lazy_close = true;
    for e in ini.entries() {
        let key = (e.section.clone(), e.key.clone());
        config
            .ini_values
            .entry(key)
            .or_insert_with(|| e.value.clone());
    }
    if let Some(value) = ini.get("RS274NGC", "SUBROUTINE_PATH") {
        config.subroutine_path = path_list(value);
    }
    if let Some(value) = ini.get("RS274NGC", "USER_M_PATH") {
        config.user_m_path = path_list(value);
    }
    if let Some(value) = ini.get("DISPLAY", "PROGRAM_PREFIX") {
        config.program_prefix = std::fs::canonicalize(expand_tilde(value.trim())).ok();
    }
    // LinuxCNC 2.9 reads a key per feature and ignores FEATURES.
    config.features = Features::from_ini_keys(|key| ini.get("RS274NGC", key));
    if let Some(v) = number(&ini, "RS274NGC", "CENTER_ARC_RADIUS_TOLERANCE_INCH") {
        if (0.00004..=config.center_arc_radius_tolerance_inch).contains(&v) {
            config.center_arc_radius_tolerance_inch = v;
        }
    }
    if let Some(v) = number(&ini, "RS274NGC", "CENTER_ARC_RADIUS_TOLERANCE_MM") {
        if (0.001..=config.center_arc_radius_tolerance_mm).contains(&v) {
            config.center_arc_radius_tolerance_mm = v;
        }
    }
    config.disable_g92_persistence = flag(&ini, "RS274NGC", "DISABLE_G92_PERSISTENCE");
    config.disable_fanuc_style_sub = flag(&ini, "RS274NGC", "DISABLE_FANUC_STYLE_SUB");
    config.orient_offset = number(&ini, "RS274NGC", "ORIENT_OFFSET").unwrap_or(0.0);
    if let Some(n) = ini
        .get("TRAJ", "SPINDLES")
        .and_then(|v| v.trim().parse::<u32>().ok())
    {
        config.spindles = n;
    }
    config.random_toolchanger = flag(&ini, "EMCIO", "RANDOM_TOOLCHANGER");
    config.tool_change_at_g30 = flag(&ini, "EMCIO", "TOOL_CHANGE_AT_G30");
    config.tool_change_quill_up = flag(&ini, "EMCIO", "TOOL_CHANGE_QUILL_UP");
    config.tool_change_with_spindle_on = flag(&ini, "EMCIO", "TOOL_CHANGE_WITH_SPINDLE_ON");
    true
}
