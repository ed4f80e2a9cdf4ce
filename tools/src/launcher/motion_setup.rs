//! Every exchange of the launcher with the motion controller, through its
//! public command channel: configuring it from the INI file as LinuxCNC's
//! task does at start-up (joint limits, following error, backlash,
//! homing, activation; axis limits; the world home), following the
//! `ini.*` pins, and enabling, disabling and aborting for the task
//! requests. Kept in this one module so changes of the motion API touch
//! the launcher in one place.

use hal_core::Instance;
use motion::homing::{HomeFlags, HomingConfig};
use motion::kins::Pose;
use motion::{Command, MotionClient, Reject};

use super::config::{axis_letters, joint_count, AxisLimits, HomingIni, JointLimits, TrajSettings};
use super::task_pins::IniChange;
use super::LaunchError;
use crate::ini::Ini;

/// `[TRAJ]` keys that wait for the coordinated planner: read and shown as
/// `ini.traj_*` pins, not yet sent to the motion controller.
const TRAJ_NOT_YET: &[&str] = &[
    "DEFAULT_LINEAR_VELOCITY",
    "DEFAULT_VELOCITY",
    "MAX_LINEAR_VELOCITY",
    "MAX_VELOCITY",
    "DEFAULT_LINEAR_ACCELERATION",
    "DEFAULT_ACCELERATION",
    "MAX_LINEAR_ACCELERATION",
    "MAX_ACCELERATION",
    "MAX_LINEAR_JERK",
    "PLANNER_TYPE",
    "ARC_BLEND_ENABLE",
    "ARC_BLEND_FALLBACK_ENABLE",
    "ARC_BLEND_OPTIMIZATION_DEPTH",
    "ARC_BLEND_GAP_CYCLES",
    "ARC_BLEND_RAMP_FREQ",
    "SPINDLES",
    "POSITION_FILE",
    "NO_FORCE_HOMING",
];

/// The motion controller of an instance.
pub struct MotionLink {
    client: MotionClient,
}

/// What a refusal means here.
fn refusal(reason: Reject) -> String {
    match reason {
        Reject::Timeout => "the motion controller did not answer: is motion-command-handler \
                            added to a running thread?"
            .to_string(),
        other => other.to_string(),
    }
}

/// The INI position to name for a setting made of `keys` of `section`.
fn at(ini: &Ini, section: &str, keys: &[&str]) -> String {
    keys.iter()
        .find_map(|k| ini.entry(section, k))
        .map(|e| format!("{}: [{section}]{}", e.origin, e.key))
        .unwrap_or_else(|| format!("{}: [{section}]", ini.name()))
}

/// HomingConfig from the INI keys.
fn homing_config(h: &HomingIni) -> HomingConfig {
    let mut flags = HomeFlags::empty();
    flags.set(HomeFlags::USE_INDEX, h.use_index);
    flags.set(HomeFlags::INDEX_NO_ENCODER_RESET, h.index_no_encoder_reset);
    flags.set(HomeFlags::IGNORE_LIMITS, h.ignore_limits);
    flags.set(HomeFlags::IS_SHARED, h.is_shared);
    flags.set(HomeFlags::UNLOCK_FIRST, h.locking_indexer);
    flags.set(
        HomeFlags::ABSOLUTE_ENCODER | HomeFlags::NO_REHOME,
        h.absolute_encoder > 0,
    );
    flags.set(HomeFlags::NO_FINAL_MOVE, h.absolute_encoder == 2);
    HomingConfig {
        offset: h.offset,
        home: h.home,
        final_vel: h.final_vel,
        search_vel: h.search_vel,
        latch_vel: h.latch_vel,
        flags,
        sequence: h.sequence,
        volatile_home: h.volatile_home,
    }
}

impl MotionLink {
    /// The command channel of the instance's `motmod`, or `None` if no
    /// motion controller is loaded.
    pub fn connect(inst: &Instance) -> Option<MotionLink> {
        MotionClient::open(inst).ok().map(|c| MotionLink {
            client: c.with_timeout(std::time::Duration::from_secs(2)),
        })
    }

    fn send(&mut self, cmd: Command) -> Result<(), String> {
        self.client
            .send(cmd)
            .map(|_| ())
            .map_err(|r| refusal(r.reason))
    }

    /// Sends what task sends at start-up; returns notes about settings the
    /// controller does not take yet.
    pub fn configure(&mut self, ini: &Ini) -> Result<Vec<String>, LaunchError> {
        let mut notes = Vec::new();
        for j in 0..joint_count(ini)? {
            let l = JointLimits::from_ini(ini, j)?;
            let sec = format!("JOINT_{j}");
            let joint = j as i32;
            let steps: [(Command, &[&str]); 8] = [
                (
                    Command::SetJointBacklash {
                        joint,
                        backlash: l.backlash,
                    },
                    &["BACKLASH"],
                ),
                (
                    Command::SetJointPositionLimits {
                        joint,
                        min: l.min_limit,
                        max: l.max_limit,
                    },
                    &["MIN_LIMIT", "MAX_LIMIT"],
                ),
                (
                    Command::SetJointMaxFerror {
                        joint,
                        ferror: l.ferror,
                    },
                    &["FERROR"],
                ),
                (
                    Command::SetJointMinFerror {
                        joint,
                        ferror: l.min_ferror,
                    },
                    &["MIN_FERROR", "FERROR"],
                ),
                (
                    Command::SetJointVelLimit {
                        joint,
                        vel: l.max_velocity,
                    },
                    &["MAX_VELOCITY"],
                ),
                (
                    Command::SetJointAccLimit {
                        joint,
                        acc: l.max_acceleration,
                    },
                    &["MAX_ACCELERATION"],
                ),
                (
                    Command::SetJointHomingParams {
                        joint,
                        config: homing_config(&l.homing),
                    },
                    &["HOME_SEARCH_VEL", "HOME_LATCH_VEL", "HOME_SEQUENCE", "HOME"],
                ),
                (Command::JointActivate { joint }, &[]),
            ];
            for (cmd, keys) in steps {
                self.send(cmd).map_err(|reason| LaunchError::Motion {
                    at: at(ini, &sec, keys),
                    reason,
                })?;
            }
            if l.max_jerk != 0.0 {
                notes.push(format!(
                    "{}: per-joint jerk limits are not supported by this motion controller yet",
                    at(ini, &sec, &["MAX_JERK"])
                ));
            }
            if ini.entry(&sec, "COMP_FILE").is_some() {
                notes.push(format!(
                    "{}: screw compensation files are not supported yet; the joint runs without",
                    at(ini, &sec, &["COMP_FILE"])
                ));
            }
        }
        for (axis, letter) in axis_letters(ini) {
            let l = AxisLimits::from_ini(ini, letter)?;
            let sec = format!("AXIS_{}", letter.to_ascii_uppercase());
            let a = axis as i32;
            let steps: [(Command, &[&str]); 3] = [
                (
                    Command::SetAxisPositionLimits {
                        axis: a,
                        min: l.min_limit,
                        max: l.max_limit,
                    },
                    &["MIN_LIMIT", "MAX_LIMIT"],
                ),
                (
                    Command::SetAxisVelLimit {
                        axis: a,
                        vel: l.max_velocity,
                    },
                    &["MAX_VELOCITY"],
                ),
                (
                    Command::SetAxisAccLimit {
                        axis: a,
                        acc: l.max_acceleration,
                    },
                    &["MAX_ACCELERATION"],
                ),
            ];
            for (cmd, keys) in steps {
                self.send(cmd).map_err(|reason| LaunchError::Motion {
                    at: at(ini, &sec, keys),
                    reason,
                })?;
            }
            if ini.entry(&sec, "LOCKING_INDEXER_JOINT").is_some() {
                notes.push(format!(
                    "{}: axis locking indexers wait for the coordinated planner; homing the joint still unlocks it",
                    at(ini, &sec, &["LOCKING_INDEXER_JOINT"])
                ));
            }
        }
        let traj = TrajSettings::from_ini(ini)?;
        if let Some(pose) = traj.home {
            self.send(Command::SetWorldHome { pose: Pose(pose) })
                .map_err(|reason| LaunchError::Motion {
                    at: at(ini, "TRAJ", &["HOME"]),
                    reason,
                })?;
        }
        let waiting: Vec<&str> = TRAJ_NOT_YET
            .iter()
            .copied()
            .filter(|k| ini.entry("TRAJ", k).is_some())
            .collect();
        if !waiting.is_empty() {
            notes.push(format!(
                "{}: [TRAJ] {} are read (ini.traj_* pins) but wait for the coordinated planner",
                ini.name(),
                waiting.join(", ")
            ));
        }
        Ok(notes)
    }

    /// Applies a changed `ini.*` pin.
    pub fn apply(&mut self, change: &IniChange) -> Result<(), String> {
        let cmd = match *change {
            IniChange::Backlash { joint, value } => Command::SetJointBacklash {
                joint: joint as i32,
                backlash: value,
            },
            IniChange::Ferror { joint, value } => Command::SetJointMaxFerror {
                joint: joint as i32,
                ferror: value,
            },
            IniChange::MinFerror { joint, value } => Command::SetJointMinFerror {
                joint: joint as i32,
                ferror: value,
            },
            IniChange::JointLimits { joint, min, max } => Command::SetJointPositionLimits {
                joint: joint as i32,
                min,
                max,
            },
            IniChange::JointVel { joint, value } => Command::SetJointVelLimit {
                joint: joint as i32,
                vel: value,
            },
            IniChange::JointAcc { joint, value } => Command::SetJointAccLimit {
                joint: joint as i32,
                acc: value,
            },
            IniChange::Homing {
                joint,
                home,
                offset,
                sequence,
            } => Command::UpdateJointHomingParams {
                joint: joint as i32,
                offset,
                home,
                sequence,
            },
            IniChange::AxisLimits { axis, min, max } => Command::SetAxisPositionLimits {
                axis: axis as i32,
                min,
                max,
            },
            IniChange::AxisVel { axis, value } => Command::SetAxisVelLimit {
                axis: axis as i32,
                vel: value,
            },
            IniChange::AxisAcc { axis, value } => Command::SetAxisAccLimit {
                axis: axis as i32,
                acc: value,
            },
            IniChange::NotApplied { pin } => {
                return Err(format!(
                    "{pin}: not applied, the motion controller does not take this setting yet"
                ))
            }
        };
        self.send(cmd)
    }

    /// Machine on: amplifiers enabled.
    pub fn enable(&mut self) -> Result<(), String> {
        self.send(Command::Enable)
    }

    /// Machine off or e-stop: planners stopped, amplifiers off.
    pub fn disable(&mut self) -> Result<(), String> {
        self.send(Command::Disable)
    }

    /// Abort: every move stops.
    pub fn abort(&mut self) -> Result<(), String> {
        self.send(Command::Abort)
    }

    /// Whether motion is enabled, if the status can be read.
    pub fn enabled(&self) -> Option<bool> {
        self.client.status().ok().map(|s| s.enabled)
    }

    /// A one-line summary for `task-cmd status`.
    pub fn summary(&self) -> String {
        match self.client.status() {
            Ok(s) => format!(
                "motion: {} ({}), {} joints, {}",
                if s.enabled { "enabled" } else { "disabled" },
                s.mode,
                s.joints.iter().filter(|j| j.active).count(),
                if s.all_homed {
                    "all homed"
                } else {
                    "not all homed"
                }
            ),
            Err(e) => format!("motion: status not readable: {e}"),
        }
    }
}
