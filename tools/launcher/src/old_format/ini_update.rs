//! The INI side of the update of a configuration from before joints and
//! axes were separate (LinuxCNC 2.8; [EMC]VERSION older than 1.0): the
//! same changes LinuxCNC's `update_ini` makes to the file, made to the
//! entries in memory. `[AXIS_n]` sections become `[JOINT_j]` sections
//! and `[AXIS_L]` limits, `[KINS]` gets the kinematics module found in
//! the HAL files and the joint count, `[TRAJ]` gets the names of 2.8,
//! `[RS274NGC]FEATURES` becomes its separate keys. Every entry keeps the
//! file and line it was read from, so errors name the user's line.

use std::sync::Arc;

use hal_lang::ini::{Entry, Ini, Origin};

use super::hal_update::{JointRenames, AXIS_LETTERS};
use crate::LaunchError;

/// The converted entries, and what the HAL files need to follow them.
#[derive(Debug, Clone, PartialEq)]
pub struct IniUpdate {
    /// Every entry of the configuration in the 2.8 format.
    pub entries: Vec<Entry>,
    /// The HAL renames that go with them.
    pub renames: JointRenames,
    /// `[KINS]KINEMATICS` as made.
    pub kinematics: String,
    /// `[KINS]JOINTS` as made.
    pub joints: usize,
}

/// The kinematics of the old HAL files: the module, its `coordinates=`
/// and `kinstype=` if given.
#[derive(Debug, Default)]
struct OldKins {
    module: Option<String>,
    coordinates: Option<String>,
    kinstype: Option<String>,
    /// gantrykins' `setp gantrykins.joint-N AXIS` lines.
    gantry_joints: Vec<(usize, usize)>,
}

fn param<'a>(words: &[&'a str], name: &str) -> Option<&'a str> {
    words
        .iter()
        .find_map(|w| w.strip_prefix(name)?.strip_prefix('='))
}

/// The first `loadrt ...kins` of the HAL files (and gantrykins' map).
fn find_kins(hal_texts: &[String]) -> OldKins {
    let mut k = OldKins::default();
    for text in hal_texts {
        for line in text.lines() {
            let code = hal_lang::lexer::without_comment(line);
            let words: Vec<&str> = code.split_whitespace().collect();
            match words.as_slice() {
                ["loadrt", module, rest @ ..] if k.module.is_none() && module.ends_with("kins") => {
                    k.module = Some(module.to_string());
                    k.coordinates = param(rest, "coordinates").map(str::to_uppercase);
                    k.kinstype = param(rest, "kinstype").map(str::to_string);
                }
                ["setp", pin, value, ..] => {
                    let joint = pin
                        .strip_prefix("gantrykins.joint-")
                        .and_then(|j| j.parse::<usize>().ok());
                    if let (Some(j), Ok(a)) = (joint, value.parse::<usize>()) {
                        if j < 16 && a < AXIS_LETTERS.len() {
                            k.gantry_joints.push((j, a));
                        }
                    }
                }
                _ => {}
            }
        }
    }
    k
}

/// Where a made entry says it comes from.
fn made_at(ini: &Ini, keys: &[(&str, &str)]) -> Origin {
    keys.iter()
        .find_map(|(s, k)| ini.entry(s, k))
        .map(|e| e.origin.clone())
        .unwrap_or_else(|| Origin {
            file: Arc::from(ini.name().as_str()),
            line: 0,
        })
}

fn made(section: &str, key: &str, value: String, origin: &Origin) -> Entry {
    Entry {
        section: section.to_string(),
        key: key.to_string(),
        value,
        origin: origin.clone(),
    }
}

/// The axis letters (upper case) of the joints, and the joint count.
fn joints_and_letters(ini: &Ini, kins: &mut OldKins) -> Result<(Vec<char>, usize), LaunchError> {
    let coordinates: Option<Vec<char>> = ini
        .get("TRAJ", "COORDINATES")
        .map(|c| {
            c.chars()
                .filter(|c| !c.is_whitespace())
                .map(|c| c.to_ascii_uppercase())
                .collect::<Vec<char>>()
        })
        .filter(|c| !c.is_empty());
    let mut joints = match &coordinates {
        Some(c) => c.len(),
        None => ini
            .int("TRAJ", "AXES")?
            .map_or(3, |n| n.clamp(1, 9) as usize),
    };
    let mut letters = coordinates.unwrap_or_else(|| AXIS_LETTERS.to_uppercase().chars().collect());
    if let Some(c) = &kins.coordinates {
        letters = c.chars().collect();
    }
    if kins.module.as_deref() == Some("gantrykins") {
        // gantrykins is gone: trivkins with a joint per axis letter.
        for &(j, a) in &kins.gantry_joints {
            while letters.len() <= j {
                letters.push('X');
            }
            letters[j] = AXIS_LETTERS.to_uppercase().as_bytes()[a] as char;
            joints = joints.max(j + 1);
        }
        kins.module = Some("trivkins".into());
        kins.kinstype = Some("BOTH".into());
    }
    letters.retain(|c| AXIS_LETTERS.to_uppercase().contains(*c));
    letters.truncate(joints);
    Ok((letters.clone(), letters.len().max(1)))
}

/// The `[TRAJ]` entries with 2.8's names (and no AXES or CYCLE_TIME).
fn traj_entries(ini: &Ini, letters: &[char], out: &mut Vec<Entry>) {
    let traj: Vec<&Entry> = ini
        .entries()
        .iter()
        .filter(|e| e.section == "TRAJ")
        .collect();
    let has = |k: &str| traj.iter().any(|e| e.key == k);
    let renames = [
        ("MAX_VELOCITY", "MAX_LINEAR_VELOCITY"),
        ("DEFAULT_VELOCITY", "DEFAULT_LINEAR_VELOCITY"),
        ("MAX_ACCELERATION", "MAX_LINEAR_ACCELERATION"),
        ("DEFAULT_ACCELERATION", "DEFAULT_LINEAR_ACCELERATION"),
    ];
    for e in &traj {
        let mut e = (*e).clone();
        match e.key.as_str() {
            "AXES" | "CYCLE_TIME" => continue,
            "COORDINATES" => e.value = letters.iter().collect(),
            k => {
                if let Some((_, new)) = renames.iter().find(|(old, new)| *old == k && !has(new)) {
                    e.key = new.to_string();
                }
            }
        }
        out.push(e);
    }
    if !has("MAX_LINEAR_VELOCITY") && !has("MAX_VELOCITY") {
        // As update_ini: the fastest single axis.
        let fastest = ini
            .entries()
            .iter()
            .filter(|e| e.key == "MAX_VELOCITY")
            .filter_map(|e| Some((e.value.parse::<f64>().ok()?, e)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, e)) = fastest {
            out.push(made(
                "TRAJ",
                "MAX_LINEAR_VELOCITY",
                e.value.clone(),
                &e.origin,
            ));
        }
    }
}

/// `[RS274NGC]FEATURES` as the separate keys it became.
fn features_entries(e: &Entry, out: &mut Vec<Entry>) -> Result<(), LaunchError> {
    let bits = hal_lang::ini::parse_int(e.value.split_whitespace().next().unwrap_or(""))
        .ok_or_else(|| hal_lang::ini::IniError::BadValue {
            origin: e.origin.clone(),
            section: e.section.clone(),
            key: e.key.clone(),
            value: e.value.clone(),
            expected: "a number (a bit mask of interpreter features)",
        })?;
    let flag = |bit: i64| if bits & bit != 0 { "1" } else { "0" }.to_string();
    for (key, value) in [
        ("RETAIN_G43", Some(flag(0x1))),
        ("INI_VARS", Some(flag(0x4))),
        ("HAL_PIN_VARS", Some(flag(0x8))),
        ("OWORD_NARGS", (bits & 0x2 != 0).then(|| "1".into())),
        ("NO_DOWNCASE_OWORD", (bits & 0x10 != 0).then(|| "1".into())),
        ("OWORD_WARNONLY", (bits & 0x20 != 0).then(|| "1".into())),
    ] {
        if let Some(v) = value {
            out.push(made("RS274NGC", key, v, &e.origin));
        }
    }
    Ok(())
}

/// Whether a section is an old numbered `[AXIS_n]`.
fn old_axis_section(section: &str) -> bool {
    section
        .strip_prefix("AXIS_")
        .is_some_and(|n| n.len() == 1 && n.as_bytes()[0].is_ascii_digit())
}

/// The `[AXIS_L]` and `[JOINT_j]` sections made from the `[AXIS_n]` ones.
fn axis_and_joint_entries(ini: &Ini, letters: &[char], out: &mut Vec<Entry>) -> JointRenames {
    let mut renames = JointRenames::default();
    let upper = AXIS_LETTERS.to_uppercase();
    for (axis, letter) in upper.chars().enumerate() {
        // The joints of this letter that are not [JOINT_j] already.
        let joints: Vec<usize> = (0..letters.len())
            .filter(|&j| letters[j] == letter && !ini.has_section(&format!("JOINT_{j}")))
            .collect();
        let Some(&first) = joints.first() else {
            continue;
        };
        let old = format!("AXIS_{axis}");
        let axis_sec = format!("AXIS_{letter}");
        for key in ["MIN_LIMIT", "MAX_LIMIT", "MAX_VELOCITY", "MAX_ACCELERATION"] {
            if let Some(e) = ini.entry(&old, key) {
                out.push(made(&axis_sec, key, e.value.clone(), &e.origin));
            }
        }
        if let Some(e) = ini
            .entry(&old, "LOCKING_INDEXER")
            .filter(|e| hal_lang::ini::parse_bool(e.value.trim()) == Some(true))
        {
            out.push(made(
                &axis_sec,
                "LOCKING_INDEXER_JOINT",
                first.to_string(),
                &e.origin,
            ));
            if first < 32 {
                renames.unlock_joints_mask |= 1 << first;
            }
        }
        let sequence = ini
            .get(&old, "HOME_SEQUENCE")
            .map(str::trim)
            .filter(|s| *s != "-1");
        for &j in &joints {
            // A joint's section: [AXIS_j] if there is one, else its axis's.
            let own = format!("AXIS_{j}");
            let from = if ini.has_section(&own) {
                own
            } else {
                old.clone()
            };
            let joint_sec = format!("JOINT_{j}");
            for e in ini.entries().iter().filter(|e| e.section == from) {
                let mut e = e.clone();
                e.section = joint_sec.clone();
                if e.key == "HOME_SEQUENCE" {
                    let Some(s) = sequence else { continue };
                    // Joints of one axis home together (a negative sequence).
                    e.value = if joints.len() > 1 && !s.starts_with('-') {
                        format!("-{s}")
                    } else {
                        s.to_string()
                    };
                }
                out.push(e);
            }
            // HAL files name the first joint of an axis by the axis's
            // old number, a further one by its own.
            let old_ref = if j == first {
                format!("[{old}]")
            } else {
                format!("[AXIS_{j}]")
            };
            renames.sections.push((old_ref, format!("[{joint_sec}]")));
            if j == first && axis != j {
                renames.joint_of_axis.push((axis, j));
            }
        }
    }
    renames
}

/// Converts a configuration from before [EMC]VERSION 1.0; `hal_texts`
/// are its own HAL files, where the kinematics module is found.
pub fn update_joints_axes(ini: &Ini, hal_texts: &[String]) -> Result<IniUpdate, LaunchError> {
    let mut kins = find_kins(hal_texts);
    let (letters, joints) = joints_and_letters(ini, &mut kins)?;
    let module = match kins.module.as_deref() {
        None | Some("gentrivkins") => "trivkins".to_string(),
        Some(m) => m.to_string(),
    };
    let mut kinematics = module.clone();
    if module == "trivkins" {
        kinematics.push_str(&format!(
            " coordinates={}",
            letters.iter().collect::<String>()
        ));
    }
    if let Some(t) = &kins.kinstype {
        kinematics.push_str(&format!(" kinstype={t}"));
    }
    let mut out = Vec::new();
    let mut traj_done = false;
    for e in ini.entries() {
        match (e.section.as_str(), e.key.as_str()) {
            ("EMC", "VERSION") => out.push(made("EMC", "VERSION", "1.1".into(), &e.origin)),
            ("RS274NGC", "FEATURES") => features_entries(e, &mut out)?,
            ("EMCMOT", "COMM_WAIT") => {}
            ("TRAJ", _) => {
                if !traj_done {
                    traj_entries(ini, &letters, &mut out);
                    traj_done = true;
                }
            }
            (s, _) if old_axis_section(s) => {}
            _ => out.push(e.clone()),
        }
    }
    let at = made_at(
        ini,
        &[
            ("TRAJ", "COORDINATES"),
            ("TRAJ", "AXES"),
            ("EMC", "VERSION"),
        ],
    );
    out.push(made("KINS", "KINEMATICS", kinematics.clone(), &at));
    out.push(made("KINS", "JOINTS", joints.to_string(), &at));
    let renames = axis_and_joint_entries(ini, &letters, &mut out);
    Ok(IniUpdate {
        entries: out,
        renames,
        kinematics,
        joints,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const LATHE: &str = "[EMC]\nVERSION = $Revision$\n[RS274NGC]\nFEATURES = 12\n\
        [TRAJ]\nAXES = 3\nCOORDINATES = X Z\nMAX_VELOCITY = 5\nDEFAULT_VELOCITY = 1\n\
        CYCLE_TIME = 0.01\n\
        [AXIS_0]\nMAX_VELOCITY = 4\nMIN_LIMIT = -1\nHOME_SEQUENCE = 1\nSCALE = 100\n\
        [AXIS_2]\nMAX_VELOCITY = 3\nHOME_SEQUENCE = -1\nLOCKING_INDEXER = 1\n";

    #[test]
    fn a_lathe_gets_two_joints_and_its_axes() {
        let ini = Ini::parse(LATHE);
        let u = update_joints_axes(&ini, &["loadrt trivkins\n".into()]).unwrap();
        let new = ini.with_entries(u.entries.clone());
        assert_eq!(u.kinematics, "trivkins coordinates=XZ");
        assert_eq!(new.get("KINS", "JOINTS"), Some("2"));
        assert_eq!(new.get("EMC", "VERSION"), Some("1.1"));
        assert_eq!(new.get("TRAJ", "COORDINATES"), Some("XZ"));
        assert_eq!(new.get("TRAJ", "MAX_LINEAR_VELOCITY"), Some("5"));
        assert_eq!(new.get("TRAJ", "DEFAULT_LINEAR_VELOCITY"), Some("1"));
        assert_eq!(
            (new.get("TRAJ", "AXES"), new.get("TRAJ", "CYCLE_TIME")),
            (None, None)
        );
        assert_eq!(new.get("RS274NGC", "INI_VARS"), Some("1"));
        assert_eq!(new.get("RS274NGC", "RETAIN_G43"), Some("0"));
        assert_eq!(new.get("AXIS_X", "MIN_LIMIT"), Some("-1"));
        assert_eq!(new.get("AXIS_Z", "MAX_VELOCITY"), Some("3"));
        assert_eq!(new.get("AXIS_Z", "LOCKING_INDEXER_JOINT"), Some("1"));
        assert_eq!(new.get("JOINT_0", "SCALE"), Some("100"));
        assert_eq!(new.get("JOINT_0", "HOME_SEQUENCE"), Some("1"));
        assert_eq!(new.get("JOINT_1", "MAX_VELOCITY"), Some("3"));
        assert_eq!(new.get("JOINT_1", "HOME_SEQUENCE"), None);
        assert!(!new.has_section("AXIS_0") && !new.has_section("AXIS_2"));
        assert_eq!(u.renames.joint_of_axis, [(2, 1)]);
        assert_eq!(u.renames.unlock_joints_mask, 2);
        assert!(u
            .renames
            .sections
            .contains(&("[AXIS_2]".to_string(), "[JOINT_1]".to_string())));
        // Each entry still names the line it was read from.
        assert_eq!(new.entry("JOINT_0", "SCALE").unwrap().origin.line, 15);
    }

    #[test]
    fn gantrykins_becomes_trivkins_with_a_joint_per_letter() {
        let ini = Ini::parse(
            "[TRAJ]\nCOORDINATES = X Y Z\n[AXIS_0]\nHOME_SEQUENCE = 0\n\
             [AXIS_1]\nHOME_SEQUENCE = 1\n[AXIS_2]\nHOME_SEQUENCE = 2\n[AXIS_3]\nSCALE = 7\n",
        );
        let hal = "loadrt gantrykins\nsetp gantrykins.joint-0 0\nsetp gantrykins.joint-1 1\n\
                   setp gantrykins.joint-2 2\nsetp gantrykins.joint-3 1\n";
        let u = update_joints_axes(&ini, &[hal.into()]).unwrap();
        let new = ini.with_entries(u.entries);
        assert_eq!(u.kinematics, "trivkins coordinates=XYZY kinstype=BOTH");
        assert_eq!(u.joints, 4);
        assert_eq!(new.get("JOINT_1", "HOME_SEQUENCE"), Some("-1"));
        assert_eq!(new.get("JOINT_3", "HOME_SEQUENCE"), None);
        assert_eq!(new.get("JOINT_3", "SCALE"), Some("7"));
        assert_eq!(new.get("JOINT_2", "HOME_SEQUENCE"), Some("2"));
    }

    #[test]
    fn a_bad_features_value_names_its_line() {
        let ini = Ini::parse("[RS274NGC]\nFEATURES = lots\n[TRAJ]\nCOORDINATES = X\n");
        let e = update_joints_axes(&ini, &[]).unwrap_err().to_string();
        assert!(e.contains("<ini>:2: [RS274NGC]FEATURES = \"lots\""), "{e}");
    }
}
