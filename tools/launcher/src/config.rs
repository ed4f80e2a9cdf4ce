//! The machine settings task reads from the INI file at start-up
//! (`[KINS]`, `[TRAJ]`, `[JOINT_n]`, `[AXIS_L]`), with LinuxCNC's
//! defaults for missing keys. A value of the wrong type is an error that
//! names the file, line and key.

use hal_lang::ini::{Ini, IniError};
use motion::comp::CompEntry;
use motion::comp_file::{read_comp_file, CompFileType};

use crate::LaunchError;

/// "No limit" as LinuxCNC writes it.
pub const NO_LIMIT: f64 = 1e99;

/// The homing keys of a `[JOINT_n]` section.
#[derive(Debug, Clone, PartialEq)]
pub struct HomingIni {
    /// HOME_OFFSET.
    pub offset: f64,
    /// HOME.
    pub home: f64,
    /// HOME_SEARCH_VEL.
    pub search_vel: f64,
    /// HOME_LATCH_VEL.
    pub latch_vel: f64,
    /// HOME_FINAL_VEL (-1: the joint's maximum velocity).
    pub final_vel: f64,
    /// HOME_USE_INDEX.
    pub use_index: bool,
    /// HOME_INDEX_NO_ENCODER_RESET.
    pub index_no_encoder_reset: bool,
    /// HOME_IGNORE_LIMITS.
    pub ignore_limits: bool,
    /// HOME_IS_SHARED.
    pub is_shared: bool,
    /// HOME_ABSOLUTE_ENCODER: 0, 1 or 2.
    pub absolute_encoder: u8,
    /// HOME_SEQUENCE (999: not part of home-all).
    pub sequence: i32,
    /// VOLATILE_HOME.
    pub volatile_home: bool,
    /// LOCKING_INDEXER.
    pub locking_indexer: bool,
}

/// A `[JOINT_n]` section.
#[derive(Debug, Clone, PartialEq)]
pub struct JointLimits {
    /// The joint number.
    pub joint: usize,
    /// MIN_LIMIT.
    pub min_limit: f64,
    /// MAX_LIMIT.
    pub max_limit: f64,
    /// MAX_VELOCITY.
    pub max_velocity: f64,
    /// MAX_ACCELERATION.
    pub max_acceleration: f64,
    /// MAX_JERK (0: none).
    pub max_jerk: f64,
    /// BACKLASH.
    pub backlash: f64,
    /// FERROR.
    pub ferror: f64,
    /// MIN_FERROR (default: FERROR).
    pub min_ferror: f64,
    /// The homing keys.
    pub homing: HomingIni,
}

fn section_joint(j: usize) -> String {
    format!("JOINT_{j}")
}

/// A number, or `default` when the key is missing.
fn real(ini: &Ini, sec: &str, key: &str, default: f64) -> Result<f64, IniError> {
    Ok(ini.real(sec, key)?.unwrap_or(default))
}

fn yes_no(ini: &Ini, sec: &str, key: &str) -> Result<bool, IniError> {
    Ok(ini.boolean(sec, key)?.unwrap_or(false))
}

impl JointLimits {
    /// Reads `[JOINT_joint]`.
    pub fn from_ini(ini: &Ini, joint: usize) -> Result<JointLimits, LaunchError> {
        let sec = section_joint(joint);
        let s = sec.as_str();
        let ferror = real(ini, s, "FERROR", 1.0)?;
        let absolute_encoder = match ini.int(s, "HOME_ABSOLUTE_ENCODER")? {
            None => 0,
            Some(v @ 0..=2) => v as u8,
            Some(_) => {
                let e = ini.entry(s, "HOME_ABSOLUTE_ENCODER").cloned();
                return Err(IniError::BadValue {
                    origin: e
                        .as_ref()
                        .map(|e| e.origin.clone())
                        .unwrap_or_else(|| ini_origin(ini)),
                    section: sec.clone(),
                    key: "HOME_ABSOLUTE_ENCODER".into(),
                    value: e.map(|e| e.value).unwrap_or_default(),
                    expected: "0, 1 or 2",
                }
                .into());
            }
        };
        let sequence = match ini.int(s, "HOME_SEQUENCE")? {
            None => 999,
            Some(v) => i32::try_from(v).unwrap_or(999),
        };
        Ok(JointLimits {
            joint,
            min_limit: real(ini, s, "MIN_LIMIT", -NO_LIMIT)?,
            max_limit: real(ini, s, "MAX_LIMIT", NO_LIMIT)?,
            max_velocity: real(ini, s, "MAX_VELOCITY", 1.0)?,
            max_acceleration: real(ini, s, "MAX_ACCELERATION", 1.0)?,
            max_jerk: real(ini, s, "MAX_JERK", 0.0)?,
            backlash: real(ini, s, "BACKLASH", 0.0)?,
            ferror,
            min_ferror: real(ini, s, "MIN_FERROR", ferror)?,
            homing: HomingIni {
                offset: real(ini, s, "HOME_OFFSET", 0.0)?,
                home: real(ini, s, "HOME", 0.0)?,
                search_vel: real(ini, s, "HOME_SEARCH_VEL", 0.0)?,
                latch_vel: real(ini, s, "HOME_LATCH_VEL", 0.0)?,
                final_vel: real(ini, s, "HOME_FINAL_VEL", -1.0)?,
                use_index: yes_no(ini, s, "HOME_USE_INDEX")?,
                index_no_encoder_reset: yes_no(ini, s, "HOME_INDEX_NO_ENCODER_RESET")?,
                ignore_limits: yes_no(ini, s, "HOME_IGNORE_LIMITS")?,
                is_shared: yes_no(ini, s, "HOME_IS_SHARED")?,
                absolute_encoder,
                sequence,
                volatile_home: yes_no(ini, s, "VOLATILE_HOME")?,
                locking_indexer: yes_no(ini, s, "LOCKING_INDEXER")?,
            },
        })
    }
}

fn ini_origin(ini: &Ini) -> hal_lang::ini::Origin {
    hal_lang::ini::Origin {
        file: std::sync::Arc::from(ini.name().as_str()),
        line: 0,
    }
}

/// An `[AXIS_L]` section.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisLimits {
    /// MIN_LIMIT.
    pub min_limit: f64,
    /// MAX_LIMIT.
    pub max_limit: f64,
    /// MAX_VELOCITY.
    pub max_velocity: f64,
    /// MAX_ACCELERATION.
    pub max_acceleration: f64,
    /// MAX_JERK.
    pub max_jerk: f64,
}

impl AxisLimits {
    /// Reads `[AXIS_L]` (`letter` in either case).
    pub fn from_ini(ini: &Ini, letter: char) -> Result<AxisLimits, LaunchError> {
        let sec = format!("AXIS_{}", letter.to_ascii_uppercase());
        let s = sec.as_str();
        Ok(AxisLimits {
            min_limit: real(ini, s, "MIN_LIMIT", -NO_LIMIT)?,
            max_limit: real(ini, s, "MAX_LIMIT", NO_LIMIT)?,
            max_velocity: real(ini, s, "MAX_VELOCITY", 1.0)?,
            max_acceleration: real(ini, s, "MAX_ACCELERATION", 1.0)?,
            max_jerk: real(ini, s, "MAX_JERK", 0.0)?,
        })
    }
}

/// The `[TRAJ]` settings behind the `ini.traj_*` pins.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajSettings {
    /// ARC_BLEND_ENABLE.
    pub arc_blend_enable: bool,
    /// ARC_BLEND_FALLBACK_ENABLE.
    pub arc_blend_fallback_enable: bool,
    /// ARC_BLEND_GAP_CYCLES.
    pub arc_blend_gap_cycles: f64,
    /// ARC_BLEND_OPTIMIZATION_DEPTH.
    pub arc_blend_optimization_depth: f64,
    /// ARC_BLEND_RAMP_FREQ.
    pub arc_blend_ramp_freq: f64,
    /// DEFAULT_LINEAR_VELOCITY.
    pub default_velocity: f64,
    /// MAX_LINEAR_VELOCITY.
    pub max_velocity: f64,
    /// DEFAULT_LINEAR_ACCELERATION.
    pub default_acceleration: f64,
    /// MAX_LINEAR_ACCELERATION.
    pub max_acceleration: f64,
    /// MAX_LINEAR_JERK.
    pub max_jerk: f64,
    /// PLANNER_TYPE.
    pub planner_type: i32,
    /// HOME: the world home pose (X Y Z A B C U V W), if given.
    pub home: Option<[f64; 9]>,
}

/// The first of `keys` present in `[TRAJ]`, or `default`.
fn traj_real(ini: &Ini, keys: &[&str], default: f64) -> Result<f64, IniError> {
    for k in keys {
        if let Some(v) = ini.real("TRAJ", k)? {
            return Ok(v);
        }
    }
    Ok(default)
}

impl TrajSettings {
    /// Reads `[TRAJ]`.
    pub fn from_ini(ini: &Ini) -> Result<TrajSettings, LaunchError> {
        let home = match ini.entry("TRAJ", "HOME") {
            None => None,
            Some(e) => {
                let mut pose = [0.0; 9];
                for (i, w) in e.value.split_whitespace().enumerate() {
                    let v = w.parse::<f64>().ok().filter(|v| v.is_finite() && i < 9);
                    pose[i.min(8)] = v.ok_or_else(|| IniError::BadValue {
                        origin: e.origin.clone(),
                        section: "TRAJ".into(),
                        key: "HOME".into(),
                        value: e.value.clone(),
                        expected: "up to nine numbers (X Y Z A B C U V W)",
                    })?;
                }
                Some(pose)
            }
        };
        let planner_type = ini.int("TRAJ", "PLANNER_TYPE")?.unwrap_or(0);
        Ok(TrajSettings {
            arc_blend_enable: ini.boolean("TRAJ", "ARC_BLEND_ENABLE")?.unwrap_or(true),
            arc_blend_fallback_enable: ini
                .boolean("TRAJ", "ARC_BLEND_FALLBACK_ENABLE")?
                .unwrap_or(false),
            arc_blend_gap_cycles: traj_real(ini, &["ARC_BLEND_GAP_CYCLES"], 4.0)?,
            arc_blend_optimization_depth: traj_real(ini, &["ARC_BLEND_OPTIMIZATION_DEPTH"], 50.0)?,
            arc_blend_ramp_freq: traj_real(ini, &["ARC_BLEND_RAMP_FREQ"], 100.0)?,
            default_velocity: traj_real(
                ini,
                &["DEFAULT_LINEAR_VELOCITY", "DEFAULT_VELOCITY"],
                1.0,
            )?,
            max_velocity: traj_real(ini, &["MAX_LINEAR_VELOCITY", "MAX_VELOCITY"], NO_LIMIT)?,
            default_acceleration: traj_real(
                ini,
                &["DEFAULT_LINEAR_ACCELERATION", "DEFAULT_ACCELERATION"],
                NO_LIMIT,
            )?,
            max_acceleration: traj_real(
                ini,
                &["MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION"],
                NO_LIMIT,
            )?,
            max_jerk: traj_real(ini, &["MAX_LINEAR_JERK"], 1e9)?,
            planner_type: i32::try_from(planner_type).unwrap_or(0),
            home,
        })
    }
}

/// `[DISPLAY]MAX_FEED_OVERRIDE`: the largest feed override (default 1).
pub fn max_feed_override(ini: &Ini) -> Result<f64, LaunchError> {
    Ok(real(ini, "DISPLAY", "MAX_FEED_OVERRIDE", 1.0)?)
}

/// The screw-error compensation table of `[JOINT_joint]COMP_FILE`, read
/// with its COMP_FILE_TYPE (required with it: type 0 and type 1 read the
/// same numbers in opposite ways, so there is no safe default); `None`
/// without a COMP_FILE. A relative file name is taken from the INI
/// file's directory, where LinuxCNC's script runs task.
pub fn joint_comp(ini: &Ini, joint: usize) -> Result<Option<Vec<CompEntry>>, LaunchError> {
    let sec = section_joint(joint);
    let Some(file) = ini.entry(&sec, "COMP_FILE") else {
        return Ok(None);
    };
    let type_entry = ini.required(&sec, "COMP_FILE_TYPE")?;
    let kind = CompFileType::from_ini(&type_entry.value).map_err(|_| IniError::BadValue {
        origin: type_entry.origin.clone(),
        section: sec.clone(),
        key: "COMP_FILE_TYPE".into(),
        value: type_entry.value.clone(),
        expected: "0 or 1",
    })?;
    let name = file.value.trim();
    if name.is_empty() {
        return Err(IniError::BadValue {
            origin: file.origin.clone(),
            section: sec.clone(),
            key: "COMP_FILE".into(),
            value: file.value.clone(),
            expected: "a file name",
        }
        .into());
    }
    let entries =
        read_comp_file(&ini.dir().join(name), kind).map_err(|source| LaunchError::CompFile {
            at: format!("{}: [{sec}]COMP_FILE", file.origin),
            source,
        })?;
    Ok(Some(entries))
}

/// `[KINS]JOINTS` (LinuxCNC requires it).
pub fn joint_count(ini: &Ini) -> Result<usize, LaunchError> {
    let e = ini.required("KINS", "JOINTS")?;
    match ini.int("KINS", "JOINTS")? {
        Some(n @ 1..=16) => Ok(n as usize),
        _ => Err(IniError::BadValue {
            origin: e.origin.clone(),
            section: "KINS".into(),
            key: "JOINTS".into(),
            value: e.value.clone(),
            expected: "a number of joints from 1 to 16",
        }
        .into()),
    }
}

/// The world axes of `[TRAJ]COORDINATES` (`X Y Z` or `XYZ`), each once,
/// as (axis number, lower-case letter).
pub fn axis_letters(ini: &Ini) -> Vec<(usize, char)> {
    let mut out: Vec<(usize, char)> = Vec::new();
    let coords = ini.get("TRAJ", "COORDINATES").unwrap_or("");
    for c in coords.chars().filter(|c| !c.is_whitespace()) {
        let l = c.to_ascii_lowercase();
        if let Some(axis) = "xyzabcuvw".find(l) {
            if !out.iter().any(|(a, _)| *a == axis) {
                out.push((axis, l));
            }
        }
    }
    out.sort();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_values() {
        let ini = Ini::parse(
            "[KINS]\nJOINTS = 2\n[TRAJ]\nCOORDINATES = X Z X\nHOME = 0 0 1\n\
             [JOINT_0]\nMAX_VELOCITY = 5\nFERROR = 0.5\nHOME_SEQUENCE = -1\nHOME_USE_INDEX = YES\n\
             [JOINT_1]\nHOME_ABSOLUTE_ENCODER = 3\n",
        );
        assert_eq!(joint_count(&ini).unwrap(), 2);
        assert_eq!(axis_letters(&ini), [(0, 'x'), (2, 'z')]);
        let j = JointLimits::from_ini(&ini, 0).unwrap();
        assert_eq!((j.max_velocity, j.ferror, j.min_ferror), (5.0, 0.5, 0.5));
        assert_eq!((j.min_limit, j.max_acceleration), (-NO_LIMIT, 1.0));
        assert_eq!(
            (j.homing.sequence, j.homing.use_index, j.homing.final_vel),
            (-1, true, -1.0)
        );
        let e = JointLimits::from_ini(&ini, 1).unwrap_err().to_string();
        assert!(
            e.contains("[JOINT_1]HOME_ABSOLUTE_ENCODER = \"3\" is not 0, 1 or 2"),
            "{e}"
        );
        let t = TrajSettings::from_ini(&ini).unwrap();
        assert_eq!(t.home, Some([0., 0., 1., 0., 0., 0., 0., 0., 0.]));
        assert!(t.arc_blend_enable);
        assert!(joint_count(&Ini::parse("[KINS]\n")).is_err());
        assert_eq!(max_feed_override(&ini).unwrap(), 1.0);
    }

    #[test]
    fn a_comp_file_needs_its_type_and_a_name() {
        let comp = |joint: &str| {
            let ini = Ini::parse(&format!("[KINS]\nJOINTS = 1\n[JOINT_0]\n{joint}"));
            joint_comp(&ini, 0).map_err(|e| e.to_string())
        };
        assert_eq!(comp("BACKLASH = 0.1\n"), Ok(None));
        let e = comp("COMP_FILE = x.comp\n").unwrap_err();
        assert!(e.contains("[JOINT_0]COMP_FILE_TYPE"), "{e}");
        let e = comp("COMP_FILE = x.comp\nCOMP_FILE_TYPE = 2\n").unwrap_err();
        assert!(
            e.contains("<ini>:5: [JOINT_0]COMP_FILE_TYPE = \"2\" is not 0 or 1"),
            "{e}"
        );
        let e = comp("COMP_FILE =\nCOMP_FILE_TYPE = 1\n").unwrap_err();
        assert!(
            e.contains("<ini>:4: [JOINT_0]COMP_FILE = \"\" is not a file name"),
            "{e}"
        );
    }
}
