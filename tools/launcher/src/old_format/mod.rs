//! Configurations written for an older LinuxCNC, run unchanged. LinuxCNC's
//! `linuxcnc` script runs `update_ini` on an INI file whose `[EMC]VERSION`
//! is not 1.1, which rewrites the INI and HAL files in place. The launcher
//! makes the same changes in memory instead, says so on stderr, and never
//! writes the user's files:
//!
//! - before 1.0 (no VERSION, `$Revision$`, 0.x: joints and axes were one
//!   thing): [`ini_update`] makes `[KINS]`, `[JOINT_j]` and `[AXIS_L]`
//!   and 2.8's `[TRAJ]` names; the machine's own HAL files get the joint
//!   pin names and the `[JOINT_j]` references ([`hal_update`]);
//! - before 1.1 (also 1.0): the spindle pins get their number
//!   (`motion.spindle-on` is `spindle.0.on`).
//!
//! As update_ini, a file that has `[KINS]JOINTS` already is taken as
//! converted by hand and left as it is.

use std::path::Path;

use hal_lang::ini::Ini;

use crate::halfiles::SearchPath;
use crate::LaunchError;

mod hal_update;
mod ini_update;

pub use hal_update::HalRenames;

/// The format a configuration's `[EMC]VERSION` says it is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OldFormat {
    /// Before 1.0: joints and axes not yet apart (LinuxCNC before 2.8).
    BeforeJoints,
    /// 1.0: spindles not yet numbered.
    BeforeSpindleNumbers,
}

/// The old format of `ini`, if it is in one. Versions compare as
/// LinuxCNC's update_ini compares them: as text.
pub fn old_format(ini: &Ini) -> Option<OldFormat> {
    let version = ini.get("EMC", "VERSION").map_or("0.0", str::trim);
    if version.starts_with("$Revision") || version < "1.0" {
        Some(OldFormat::BeforeJoints)
    } else if version < "1.1" {
        Some(OldFormat::BeforeSpindleNumbers)
    } else {
        None
    }
}

/// A configuration converted in memory.
#[derive(Debug, Clone)]
pub struct Converted {
    /// The INI file in the current format.
    pub ini: Ini,
    /// The renames its own HAL files get.
    pub renames: HalRenames,
    /// What was done, for the note on stderr.
    pub summary: String,
}

/// The machine's own `.hal` files (not the standard library's) that
/// `[HAL]HALFILE` and `POSTGUI_HALFILE` name, read; files that cannot be
/// found or read are passed over here (running them reports that).
fn own_hal_texts(ini: &Ini, search: &SearchPath) -> Vec<String> {
    let mut texts = Vec::new();
    for key in ["HALFILE", "POSTGUI_HALFILE"] {
        for e in ini.all("HAL", key) {
            let Ok(f) = search.resolve(e) else { continue };
            if f.kind() != "hal" || search.in_library(&f.path) {
                continue;
            }
            if let Ok(text) = hal_lang::lexer::read_text(&f.path) {
                texts.push(text);
            }
        }
    }
    texts
}

/// `ini` in the current format if it is in an old one (`None` if not).
pub fn convert(ini: &Ini, search: &SearchPath) -> Result<Option<Converted>, LaunchError> {
    let Some(format) = old_format(ini) else {
        return Ok(None);
    };
    let version = ini
        .entry("EMC", "VERSION")
        .map(|e| format!("{}: [EMC]VERSION = {}", e.origin, e.value))
        .unwrap_or_else(|| format!("{}: no [EMC]VERSION", ini.name()));
    if let Some(e) = ini
        .entry("KINS", "JOINTS")
        .filter(|_| format == OldFormat::BeforeJoints)
    {
        eprintln!(
            "linuxcnc: note: {version}, but {}: [KINS]JOINTS is there: taken as converted \
             by hand (set [EMC]VERSION = 1.1 to silence this note)",
            e.origin
        );
        return Ok(None);
    }
    let converted = match format {
        OldFormat::BeforeSpindleNumbers => Converted {
            ini: ini.clone(),
            renames: HalRenames::default(),
            summary: format!(
                "{version}: LinuxCNC's format before numbered spindles; the machine's HAL \
                 files are read with motion.spindle-* as spindle.0.* and halui.spindle.* as \
                 halui.spindle.0.*"
            ),
        },
        OldFormat::BeforeJoints => {
            let update = ini_update::update_joints_axes(ini, &own_hal_texts(ini, search))?;
            Converted {
                ini: ini.with_entries(update.entries),
                renames: HalRenames {
                    joints: Some(update.renames),
                },
                summary: format!(
                    "{version}: LinuxCNC's format before joints and axes were apart (2.8); \
                     read as [KINS]KINEMATICS = {}, [KINS]JOINTS = {}, [AXIS_n] as \
                     [JOINT_n] and [AXIS_L], and the machine's HAL files with the new pin \
                     names (axis.N.* as joint.N.*, motion.spindle-* as spindle.0.*)",
                    update.kinematics, update.joints
                ),
            }
        }
    };
    Ok(Some(converted))
}

/// `ini` in the current format, for programs that read the machine's INI
/// file themselves (halui): the same conversion the launcher makes, quietly.
pub fn current_format(ini: Ini) -> Result<Ini, LaunchError> {
    match old_format(&ini) {
        None => return Ok(ini),
        Some(OldFormat::BeforeJoints) if ini.entry("KINS", "JOINTS").is_some() => return Ok(ini),
        Some(_) => {}
    }
    let search = SearchPath {
        extra: Vec::new(),
        ini_dir: ini.dir(),
        lib: crate::halfiles::hallib_dir(),
    };
    Ok(convert(&ini, &search)?.map_or(ini, |c| c.ini))
}

/// The note the launcher prints for a converted configuration.
pub fn announce(c: &Converted, ini_path: &Path) {
    eprintln!(
        "linuxcnc: note: {}; converted in memory as LinuxCNC's update_ini converts it \
         ({} is not changed)",
        c.summary,
        ini_path.display()
    );
}

/// The fuzz target's body: `data` read as an old-format INI file and as
/// its HAL file at once, converted both ways. Never panics.
pub fn fuzz_convert(data: &[u8]) {
    let text = String::from_utf8_lossy(data).into_owned();
    let ini = Ini::parse(&text);
    let _ = old_format(&ini);
    let _ = HalRenames::default().convert_text(&text);
    if let Ok(update) = ini_update::update_joints_axes(&ini, std::slice::from_ref(&text)) {
        let _ = ini.with_entries(update.entries);
        let renames = HalRenames {
            joints: Some(update.renames),
        };
        let _ = renames.convert_text(&text);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_compare_as_update_ini_compares_them() {
        let v = |text: &str| old_format(&Ini::parse(text));
        assert_eq!(v("[EMC]\nMACHINE = m\n"), Some(OldFormat::BeforeJoints));
        assert_eq!(
            v("[EMC]\nVERSION = $Revision$\n"),
            Some(OldFormat::BeforeJoints)
        );
        assert_eq!(v("[EMC]\nVERSION = 0.9\n"), Some(OldFormat::BeforeJoints));
        assert_eq!(
            v("[EMC]\nVERSION = 1.0\n"),
            Some(OldFormat::BeforeSpindleNumbers)
        );
        assert_eq!(v("[EMC]\nVERSION = 1.1\n"), None);
        assert_eq!(v("[EMC]\nVERSION = 2\n"), None);
    }

    #[test]
    fn a_file_with_kins_joints_is_taken_as_converted() {
        let ini = Ini::parse("[KINS]\nJOINTS = 3\n");
        assert!(convert(&ini, &SearchPath::default()).unwrap().is_none());
        let ini = Ini::parse("[EMC]\nVERSION = 1.0\n[KINS]\nJOINTS = 3\n");
        let c = convert(&ini, &SearchPath::default()).unwrap().unwrap();
        assert!(c.renames.joints.is_none());
    }
}
