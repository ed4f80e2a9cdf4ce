//! The settings of each joint that `stat.joint` reports from the INI file
//! (LinuxCNC's `jointType`, `units`, `backlash`, `max_ferror` and
//! `min_ferror`): motion's snapshot carries the joint's state, not these.

use hal_lang::ini::{Ini, IniError};

use crate::config::JointLimits;
use crate::error::LaunchError;

/// LinuxCNC's `jointType` for a linear joint.
const LINEAR: i64 = 1;
/// LinuxCNC's `jointType` for a rotary joint.
const ANGULAR: i64 = 2;

/// One `[JOINT_n]` as `stat.joint[n]` reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct JointInfo {
    /// 1 for `TYPE = LINEAR` (the default), 2 for `ANGULAR`.
    pub joint_type: i64,
    /// Machine units per millimetre or per degree, after the type.
    pub units: f64,
    /// `BACKLASH`.
    pub backlash: f64,
    /// `FERROR`, the following-error limit at full speed.
    pub max_ferror: f64,
    /// `MIN_FERROR`, the limit at rest.
    pub min_ferror: f64,
}

impl JointInfo {
    /// `[JOINT_joint]` of `ini`; `linear` and `angular` are the machine's
    /// units per millimetre and per degree. A `TYPE` other than LINEAR
    /// or ANGULAR is refused, as LinuxCNC refuses it.
    pub(crate) fn from_ini(
        ini: &Ini,
        joint: usize,
        linear: f64,
        angular: f64,
    ) -> Result<JointInfo, LaunchError> {
        let limits = JointLimits::from_ini(ini, joint)?;
        let section = format!("JOINT_{joint}");
        let joint_type = match ini.entry(&section, "TYPE") {
            None => LINEAR,
            Some(e) if e.value.trim().eq_ignore_ascii_case("LINEAR") => LINEAR,
            Some(e) if e.value.trim().eq_ignore_ascii_case("ANGULAR") => ANGULAR,
            Some(e) => {
                return Err(IniError::BadValue {
                    origin: e.origin.clone(),
                    section,
                    key: "TYPE".into(),
                    value: e.value.clone(),
                    expected: "LINEAR or ANGULAR",
                }
                .into());
            }
        };
        Ok(JointInfo {
            joint_type,
            units: if joint_type == ANGULAR {
                angular
            } else {
                linear
            },
            backlash: limits.backlash,
            max_ferror: limits.ferror,
            min_ferror: limits.min_ferror,
        })
    }

    /// Every joint of `ini` ([KINS]JOINTS of them; none without the key).
    pub(crate) fn all_from_ini(
        ini: &Ini,
        linear: f64,
        angular: f64,
    ) -> Result<Vec<JointInfo>, LaunchError> {
        if ini.entry("KINS", "JOINTS").is_none() {
            return Ok(Vec::new());
        }
        let joints = crate::config::joint_count(ini)?;
        (0..joints)
            .map(|j| JointInfo::from_ini(ini, j, linear, angular))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ini(text: &str) -> Ini {
        Ini::parse(text)
    }

    #[test]
    fn joints_take_type_units_backlash_and_ferror_limits() {
        let i = ini(
            "[KINS]\nJOINTS = 2\n[JOINT_0]\nBACKLASH = 0.002\nFERROR = 0.05\n\
             MIN_FERROR = 0.01\n[JOINT_1]\nTYPE = ANGULAR\nFERROR = 2\n",
        );
        let j = JointInfo::all_from_ini(&i, 1.0 / 25.4, 1.0).unwrap();
        assert_eq!(
            j,
            [
                JointInfo {
                    joint_type: 1,
                    units: 1.0 / 25.4,
                    backlash: 0.002,
                    max_ferror: 0.05,
                    min_ferror: 0.01,
                },
                JointInfo {
                    joint_type: 2,
                    units: 1.0,
                    backlash: 0.0,
                    max_ferror: 2.0,
                    min_ferror: 2.0,
                },
            ]
        );
    }

    #[test]
    fn an_unknown_joint_type_is_refused_naming_it() {
        let i = ini("[KINS]\nJOINTS = 1\n[JOINT_0]\nTYPE = ROTARY\n");
        let e = JointInfo::all_from_ini(&i, 1.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("TYPE") && e.contains("ROTARY"), "{e}");
        assert!(JointInfo::all_from_ini(&ini("[EMC]\n"), 1.0, 1.0)
            .unwrap()
            .is_empty());
    }
}
