//! Every exchange of the launcher with the motion controller, through its
//! public command channel: configuring it from the INI file as LinuxCNC's
//! task does at start-up, in its order (the coordinated planner's limits
//! and type and the world home; then per joint backlash, limits,
//! following error, homing, velocity, acceleration, jerk, screw-error
//! table, activation; then per axis limits, jerk, the external offsets'
//! share (`OFFSET_AV_RATIO`) and the locking indexer), following the
//! `ini.*` pins, and enabling, disabling, aborting and e-stop for the
//! task requests. `[TRAJ]` keys without a motion setting are listed with
//! why. Kept in this one module so changes of the motion API touch the
//! launcher in one place.

use hal_core::Instance;
use hal_lang::ini::Ini;
use motion::homing::{HomeFlags, HomingConfig};
use motion::kins::Pose;
use motion::{eoffset, Command, MotionClient, Reject};

use crate::config::{
    axis_letters, joint_comp, joint_count, max_feed_override, AxisLimits, HomingIni, JointLimits,
    TrajSettings,
};
use crate::task_pins::IniChange;
use crate::LaunchError;

/// `[TRAJ]` keys the motion controller has no setting for, with why:
/// read (and shown as `ini.traj_*` pins where LinuxCNC has one), never
/// sent.
const TRAJ_READ_ONLY: &[(&[&str], &str)] = &[(
    &["DEFAULT_LINEAR_ACCELERATION", "DEFAULT_ACCELERATION"],
    "LinuxCNC's SET_ACC (teleop jogs, and a cap on joint accelerations in free mode); here \
     jogs keep the [JOINT_n] and [AXIS_L] MAX_ACCELERATION and coordinated moves \
     MAX_LINEAR_ACCELERATION",
)];

/// The upper position limit LinuxCNC's task has for a joint or axis
/// before the INI's: it sets the lower limit first, with this upper one,
/// then both.
const TASK_FIRST_UPPER_LIMIT: f64 = 0.0;

/// Whether the lower limit `min` is sent on its own first, as LinuxCNC's
/// task sends it: only where it is not above [`TASK_FIRST_UPPER_LIMIT`]
/// (motion refuses reversed limits; LinuxCNC's took them for a moment).
fn lower_limit_first(min: f64) -> bool {
    min <= TASK_FIRST_UPPER_LIMIT
}

/// The motion controller of an instance.
pub struct MotionLink {
    client: MotionClient,
    /// `[TRAJ]POSITION_FILE`, written at exit.
    position_file: Option<std::path::PathBuf>,
    /// `[KINS]JOINTS`: the joints an abort stops one by one.
    joints: usize,
    /// The spindles motion was told of (`[TRAJ]SPINDLES`).
    spindles: usize,
}

/// Motion's mode for task's MANUAL mode: teleop once every joint is
/// homed, free before (and when motion's status cannot be read).
pub fn manual_mode(status: Option<&motion::MotionStatus>) -> Command {
    if status.is_some_and(|s| s.all_homed) {
        Command::Teleop
    } else {
        Command::Free
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
            position_file: None,
            joints: 0,
            spindles: 1,
        })
    }

    fn send(&mut self, cmd: Command) -> Result<(), Reject> {
        self.client.send(cmd).map(|_| ()).map_err(|r| r.reason)
    }

    /// Sends `cmd` for the INI setting of `keys` in `section`; a refusal
    /// names them.
    fn setting(
        &mut self,
        ini: &Ini,
        section: &str,
        keys: &[&str],
        cmd: Command,
    ) -> Result<(), LaunchError> {
        self.send(cmd).map_err(|source| LaunchError::Motion {
            at: at(ini, section, keys),
            source,
        })
    }

    /// Sends what task sends at start-up; returns notes about settings the
    /// controller does not take.
    /// The order is LinuxCNC 2.9 task's: the trajectory planner's settings
    /// first, then each joint, then each axis.
    pub fn configure(&mut self, ini: &Ini) -> Result<Vec<String>, LaunchError> {
        let mut notes = Vec::new();
        self.joints = joint_count(ini)?;
        self.configure_traj(ini, &mut notes)?;
        for j in 0..self.joints {
            self.configure_joint(ini, j, &mut notes)?;
        }
        for (axis, letter) in axis_letters(ini) {
            self.configure_axis(ini, axis, letter, &mut notes)?;
        }
        for spindle in 0..self.spindles {
            self.configure_spindle(ini, spindle)?;
        }
        self.restore_positions(ini, &mut notes)?;
        Ok(notes)
    }

    /// `[TRAJ]POSITION_FILE`: each joint reads the position saved at the
    /// last exit where its motor is now (its motor offset is set to the
    /// negated position), as LinuxCNC's task does before anything moves.
    /// A missing file restores nothing; an unreadable one is said in a
    /// note and not used.
    fn restore_positions(&mut self, ini: &Ini, notes: &mut Vec<String>) -> Result<(), LaunchError> {
        self.position_file = crate::position_file::path_of(ini);
        let Some(path) = &self.position_file else {
            return Ok(());
        };
        let positions = match crate::position_file::load(path) {
            Ok(crate::position_file::Loaded::Positions(p)) => p,
            Ok(crate::position_file::Loaded::Missing) => return Ok(()),
            Err(e) => {
                notes.push(e.to_string());
                return Ok(());
            }
        };
        let joints = joint_count(ini)?.min(positions.len());
        for (j, pos) in positions.iter().enumerate().take(joints) {
            self.setting(
                ini,
                "TRAJ",
                &["POSITION_FILE"],
                Command::SetJointMotorOffset {
                    joint: j as i32,
                    offset: -pos,
                },
            )?;
        }
        Ok(())
    }

    /// Writes every joint's feedback position to `[TRAJ]POSITION_FILE`,
    /// if the INI names one (at exit, after motion is disabled).
    pub fn save_positions(&self) -> Result<(), LaunchError> {
        let Some(path) = &self.position_file else {
            return Ok(());
        };
        let status = self.client.status().map_err(|e| LaunchError::Io {
            path: path.clone(),
            source: std::io::Error::other(format!(
                "joint positions not saved: motion's status is not readable ({e})"
            )),
        })?;
        let positions: Vec<f64> = status.joints.iter().map(|j| j.pos_fb).collect();
        crate::position_file::save(path, &positions)
    }

    /// `[JOINT_j]`: backlash, limits, following error, homing, velocity,
    /// acceleration and jerk, the compensation table, then activation (in
    /// LinuxCNC's order).
    fn configure_joint(
        &mut self,
        ini: &Ini,
        j: usize,
        notes: &mut Vec<String>,
    ) -> Result<(), LaunchError> {
        let l = JointLimits::from_ini(ini, j)?;
        let sec = format!("JOINT_{j}");
        let joint = j as i32;
        let mut steps: Vec<(Command, &[&str])> = vec![
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
                Command::SetJointHomingParams {
                    joint,
                    config: homing_config(&l.homing),
                },
                &["HOME_SEARCH_VEL", "HOME_LATCH_VEL", "HOME_SEQUENCE", "HOME"],
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
        ];
        if lower_limit_first(l.min_limit) {
            let cmd = Command::SetJointPositionLimits {
                joint,
                min: l.min_limit,
                max: TASK_FIRST_UPPER_LIMIT,
            };
            steps.insert(1, (cmd, &["MIN_LIMIT"]));
        }
        for (cmd, keys) in steps {
            self.setting(ini, &sec, keys, cmd)?;
        }
        // Jerk (S-curve planning) is ours, not LinuxCNC 2.9's: sent only
        // when the INI sets it; motion's default (no limit) stands else.
        if ini.entry(&sec, "MAX_JERK").is_some() {
            let cmd = Command::SetJointJerkLimit {
                joint,
                jerk: l.max_jerk,
            };
            self.setting(ini, &sec, &["MAX_JERK"], cmd)?;
        }
        if let Some(entries) = joint_comp(ini, j)? {
            self.setting(ini, &sec, &["COMP_FILE"], Command::ClearJointComp { joint })?;
            for e in entries {
                let cmd = Command::SetJointComp {
                    joint,
                    nominal: e.nominal,
                    forward: e.forward,
                    reverse: e.reverse,
                };
                self.setting(ini, &sec, &["COMP_FILE"], cmd)?;
            }
            if l.backlash != 0.0 {
                notes.push(format!(
                    "{}: not used: the joint has a COMP_FILE (as in LinuxCNC)",
                    at(ini, &sec, &["BACKLASH"])
                ));
            }
        }
        self.setting(ini, &sec, &[], Command::JointActivate { joint })
    }

    /// `[AXIS_L]`: position, velocity, acceleration and jerk limits, and the
    /// external offset's share of them.
    fn configure_axis(
        &mut self,
        ini: &Ini,
        axis: usize,
        letter: char,
        notes: &mut Vec<String>,
    ) -> Result<(), LaunchError> {
        let l = AxisLimits::from_ini(ini, letter)?;
        let sec = format!("AXIS_{}", letter.to_ascii_uppercase());
        let a = axis as i32;
        if lower_limit_first(l.min_limit) {
            let cmd = Command::SetAxisPositionLimits {
                axis: a,
                min: l.min_limit,
                max: TASK_FIRST_UPPER_LIMIT,
            };
            self.setting(ini, &sec, &["MIN_LIMIT"], cmd)?;
        }
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
            self.setting(ini, &sec, keys, cmd)?;
        }
        if ini.entry(&sec, "MAX_JERK").is_some() {
            let cmd = Command::SetAxisJerkLimit {
                axis: a,
                jerk: l.max_jerk,
            };
            self.setting(ini, &sec, &["MAX_JERK"], cmd)?;
        }
        self.configure_eoffset(ini, &sec, a, notes)?;
        self.configure_indexer(ini, &sec, a)
    }

    /// `[AXIS_L]LOCKING_INDEXER_JOINT`: the joint that drives the axis as
    /// a locking indexer (motion unlocks it around each rapid of the
    /// axis). Motion refuses a joint without unlock pins (motmod's
    /// `unlock_joints_mask`), naming the entry.
    fn configure_indexer(&mut self, ini: &Ini, sec: &str, axis: i32) -> Result<(), LaunchError> {
        // Without one, -1 (an ordinary axis) is sent, as LinuxCNC's task
        // sends it for every axis.
        let joint = match ini.int(sec, "LOCKING_INDEXER_JOINT")? {
            Some(joint) => i32::try_from(joint).unwrap_or(i32::MAX),
            None => -1,
        };
        let cmd = Command::SetAxisLockingIndexer { axis, joint };
        self.setting(ini, sec, &["LOCKING_INDEXER_JOINT"], cmd)
    }

    /// `[AXIS_L]OFFSET_AV_RATIO`: the share of the axis's velocity and
    /// acceleration limits its external offset (`axis.L.eoffset-*`) gets;
    /// planned moves keep the rest. As LinuxCNC does, a value outside
    /// 0..=0.9 is replaced by 0.1, with a note.
    fn configure_eoffset(
        &mut self,
        ini: &Ini,
        sec: &str,
        axis: i32,
        notes: &mut Vec<String>,
    ) -> Result<(), LaunchError> {
        let Some(given) = ini.real(sec, "OFFSET_AV_RATIO")? else {
            return Ok(());
        };
        let ratio = if eoffset::ratio_ok(given) {
            given
        } else {
            notes.push(format!(
                "{}: {given} is outside 0 to {}: {} is used instead, as LinuxCNC does",
                at(ini, sec, &["OFFSET_AV_RATIO"]),
                eoffset::MAX_RATIO,
                eoffset::FALLBACK_RATIO
            ));
            eoffset::FALLBACK_RATIO
        };
        let cmd = Command::SetAxisEoffsetRatio { axis, ratio };
        self.setting(ini, sec, &["OFFSET_AV_RATIO"], cmd)
    }

    /// `[SPINDLE_n]`: the speed range, rpm (MAX_FORWARD_VELOCITY,
    /// default no limit; MIN_FORWARD_VELOCITY, default 0; the reverse
    /// ones default to the forward ones, as in LinuxCNC).
    fn configure_spindle(&mut self, ini: &Ini, spindle: usize) -> Result<(), LaunchError> {
        let sec = format!("SPINDLE_{spindle}");
        let max_fwd = ini.real(&sec, "MAX_FORWARD_VELOCITY")?.unwrap_or(1e99);
        let min_fwd = ini.real(&sec, "MIN_FORWARD_VELOCITY")?.unwrap_or(0.0);
        let max_rev = ini.real(&sec, "MAX_REVERSE_VELOCITY")?.unwrap_or(max_fwd);
        let min_rev = ini.real(&sec, "MIN_REVERSE_VELOCITY")?.unwrap_or(min_fwd);
        // Reverse speeds are negative (0 - v keeps a 0 positive).
        let cmd = Command::SetSpindleParams {
            spindle: spindle as i32,
            max_pos: max_fwd,
            min_pos: min_fwd,
            max_neg: 0.0 - max_rev,
            min_neg: 0.0 - min_rev,
        };
        let keys = [
            "MAX_FORWARD_VELOCITY",
            "MIN_FORWARD_VELOCITY",
            "MAX_REVERSE_VELOCITY",
            "MIN_REVERSE_VELOCITY",
        ];
        self.setting(ini, &sec, &keys, cmd)
    }

    /// `[KINS]JOINTS` and `[TRAJ]SPINDLES` (default 1): the joints and
    /// spindles motion uses. More spindles than motmod's num_spindles is
    /// said in a note and motmod's number used, as LinuxCNC does.
    fn configure_counts(&mut self, ini: &Ini, notes: &mut Vec<String>) -> Result<(), LaunchError> {
        let joints = i32::try_from(self.joints).unwrap_or(i32::MAX);
        self.setting(ini, "KINS", &["JOINTS"], Command::SetNumJoints { joints })?;
        let asked = ini.int("TRAJ", "SPINDLES")?.unwrap_or(1);
        let spindles = i32::try_from(asked).unwrap_or(i32::MAX);
        self.spindles = match self.send(Command::SetNumSpindles { spindles }) {
            Ok(()) => asked as usize,
            Err(Reject::BadSpindleCount { loaded, .. }) if spindles > 0 => {
                notes.push(format!(
                    "{}: {spindles} spindles, but motion has {loaded} (motmod's num_spindles): \
                     {loaded} used",
                    at(ini, "TRAJ", &["SPINDLES"])
                ));
                loaded
            }
            Err(source) => {
                return Err(LaunchError::Motion {
                    at: at(ini, "TRAJ", &["SPINDLES"]),
                    source,
                })
            }
        };
        Ok(())
    }

    /// `[TRAJ]` (and `[DISPLAY]MAX_FEED_OVERRIDE`): the joints and
    /// spindles, the default velocity, the coordinated planner's limits,
    /// arc blends and type, and the world home.
    fn configure_traj(&mut self, ini: &Ini, notes: &mut Vec<String>) -> Result<(), LaunchError> {
        self.configure_counts(ini, notes)?;
        let traj = TrajSettings::from_ini(ini)?;
        // LinuxCNC's task gives the planner velocity 0 and the default
        // velocity as its INI velocity.
        let vel = Command::SetVel {
            vel: 0.0,
            ini_maxvel: traj.default_velocity,
        };
        self.setting(
            ini,
            "TRAJ",
            &["DEFAULT_LINEAR_VELOCITY", "DEFAULT_VELOCITY"],
            vel,
        )?;
        let vel = Command::SetVelLimit {
            vel: traj.max_velocity,
        };
        self.setting(ini, "TRAJ", &["MAX_LINEAR_VELOCITY", "MAX_VELOCITY"], vel)?;
        let acc = Command::SetAccLimit {
            acc: traj.max_acceleration,
        };
        self.setting(
            ini,
            "TRAJ",
            &["MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION"],
            acc,
        )?;
        // Whole numbers in LinuxCNC; `as` saturates, and motion refuses
        // a negative one naming the entry.
        let blends = Command::SetupArcBlends {
            enable: traj.arc_blend_enable,
            fallback: traj.arc_blend_fallback_enable,
            depth: traj.arc_blend_optimization_depth as i32,
            gap_cycles: traj.arc_blend_gap_cycles as i32,
            ramp_freq: traj.arc_blend_ramp_freq,
        };
        let keys = [
            "ARC_BLEND_ENABLE",
            "ARC_BLEND_FALLBACK_ENABLE",
            "ARC_BLEND_OPTIMIZATION_DEPTH",
            "ARC_BLEND_GAP_CYCLES",
            "ARC_BLEND_RAMP_FREQ",
        ];
        self.setting(ini, "TRAJ", &keys, blends)?;
        // LinuxCNC takes a jerk below 1 as "no S-curve": the planner falls
        // back to trapezoidal with a message rather than refusing the
        // configuration.
        // Jerk and the planner's type are not LinuxCNC 2.9's: sent only
        // when the INI names them (motion's defaults are no jerk limit and
        // the trapezoidal planner).
        let jerk_ok = traj.max_jerk >= 1.0;
        let named = ini.entry("TRAJ", "MAX_LINEAR_JERK").is_some();
        if named && traj.max_jerk > 0.0 {
            let jerk = Command::SetJerkLimit {
                jerk: traj.max_jerk,
            };
            self.setting(ini, "TRAJ", &["MAX_LINEAR_JERK"], jerk)?;
        } else if named {
            notes.push(format!(
                "{}: {} is no jerk limit; not sent (the controller keeps LinuxCNC's default, 1e9)",
                at(ini, "TRAJ", &["MAX_LINEAR_JERK"]),
                traj.max_jerk
            ));
        }
        let planner = if traj.planner_type == 1 && !jerk_ok {
            notes.push(format!(
                "{}: the S-curve planner needs [TRAJ]MAX_LINEAR_JERK of at least 1 (it is {}); \
                 the trapezoidal planner runs",
                at(ini, "TRAJ", &["PLANNER_TYPE"]),
                traj.max_jerk
            ));
            0
        } else {
            traj.planner_type
        };
        if ini.entry("TRAJ", "PLANNER_TYPE").is_some() {
            let cmd = Command::SetPlannerType { planner };
            self.setting(ini, "TRAJ", &["PLANNER_TYPE"], cmd)?;
        }
        let scale = max_feed_override(ini)?;
        let cmd = Command::SetMaxFeedOverride { scale };
        self.setting(ini, "DISPLAY", &["MAX_FEED_OVERRIDE"], cmd)?;
        let cmd = Command::SetProbeErrInhibit {
            jog: ini.boolean("TRAJ", "NO_PROBE_JOG_ERROR")?.unwrap_or(false),
            home: ini.boolean("TRAJ", "NO_PROBE_HOME_ERROR")?.unwrap_or(false),
        };
        let keys = ["NO_PROBE_JOG_ERROR", "NO_PROBE_HOME_ERROR"];
        self.setting(ini, "TRAJ", &keys, cmd)?;
        // Sent with or without [TRAJ]HOME (the origin then), as LinuxCNC's
        // task sends it.
        let home = Pose(traj.home.unwrap_or([0.0; 9]));
        self.setting(ini, "TRAJ", &["HOME"], Command::SetWorldHome { pose: home })?;
        for (keys, why) in TRAJ_READ_ONLY {
            let given: Vec<&str> = keys
                .iter()
                .copied()
                .filter(|k| ini.entry("TRAJ", k).is_some())
                .collect();
            if let Some((first, rest)) = given.split_first() {
                let more = if rest.is_empty() {
                    String::new()
                } else {
                    format!(" (and {})", rest.join(", "))
                };
                notes.push(format!(
                    "{}{more}: read, not sent: {why}",
                    at(ini, "TRAJ", &[first])
                ));
            }
        }
        Ok(())
    }

    /// Applies a changed `ini.*` pin.
    pub fn apply(&mut self, change: &IniChange) -> Result<(), LaunchError> {
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
            IniChange::JointJerk { joint, value } => Command::SetJointJerkLimit {
                joint: joint as i32,
                jerk: value,
            },
            IniChange::AxisJerk { axis, value } => Command::SetAxisJerkLimit {
                axis: axis as i32,
                jerk: value,
            },
            IniChange::TrajVel { value } => Command::SetVelLimit { vel: value },
            IniChange::TrajAcc { value } => Command::SetAccLimit { acc: value },
            IniChange::TrajJerk { value } => Command::SetJerkLimit { jerk: value },
            IniChange::PlannerType { value } => Command::SetPlannerType { planner: value },
            IniChange::NotApplied { pin } => {
                return Err(LaunchError::NotApplied {
                    pin: pin.to_string(),
                })
            }
        };
        self.send(cmd).map_err(|source| LaunchError::IniPin {
            pin: change.pin().to_string(),
            source,
        })
    }

    /// Machine on: amplifiers enabled. ENABLE, then ENABLE_AMPLIFIER for
    /// each joint, as LinuxCNC's task sends them (motion takes those and
    /// does nothing more: the amplifiers follow ENABLE).
    pub fn enable(&mut self) -> Result<(), Reject> {
        self.send(Command::Enable)?;
        for joint in 0..self.joints {
            self.send(Command::EnableAmplifier {
                joint: joint as i32,
            })?;
        }
        Ok(())
    }

    /// Machine off or e-stop: planners stopped, amplifiers off.
    /// DISABLE_AMPLIFIER for each joint, then DISABLE, as LinuxCNC's task
    /// sends them; DISABLE is sent even if one of the others is refused.
    pub fn disable(&mut self) -> Result<(), Reject> {
        let mut first = Ok(());
        for joint in 0..self.joints {
            first = first.and(self.send(Command::DisableAmplifier {
                joint: joint as i32,
            }));
        }
        self.send(Command::Disable).and(first)
    }

    /// Stops every move as LinuxCNC's task does: each joint's jog or
    /// homing (JOG_ABORT for every joint number motion can have, as
    /// LinuxCNC's task sends it; motion refuses those beyond the machine's
    /// joints, which is no fault), then the planners (ABORT). Every
    /// command is sent even if one is refused; the first refusal is
    /// returned.
    pub fn abort_moves(&mut self) -> Result<(), Reject> {
        let mut first = Ok(());
        for j in 0..motion::sizes::MAX_JOINTS {
            let r = match self.send(Command::JogAbort { joint: j as i32 }) {
                Err(Reject::NoSuchJoint { .. }) if j >= self.joints => Ok(()),
                r => r,
            };
            first = first.and(r);
        }
        first.and(self.send(Command::Abort))
    }

    /// Abort: every move stops, and every spindle (as LinuxCNC's task
    /// abort does).
    pub fn abort(&mut self) -> Result<(), Reject> {
        let moves = self.abort_moves();
        // The spindle stops even if the abort was not taken.
        let spindles = self.send(Command::SpindleOff { spindle: -1 });
        moves.and(spindles)
    }

    /// Into e-stop, in LinuxCNC's task's order: abort (moves and
    /// spindles), motion disabled, then the joints with VOLATILE_HOME
    /// unhomed (JOINT_UNHOME -2). A refused disable is returned; the rest
    /// is sent whatever the answers.
    pub fn estop(&mut self) -> Result<(), Reject> {
        let _ = self.abort();
        let disabled = self.disable();
        let _ = self.send(Command::Unhome { joint: -2 });
        disabled
    }

    /// The controller's status snapshot, if it can be read.
    pub fn status(&self) -> Option<motion::MotionStatus> {
        self.client.status().ok()
    }

    /// Sends a command of a running program or MDI line (queued moves,
    /// planner settings, pause, resume, step, mode changes).
    pub fn command(&mut self, cmd: Command) -> Result<(), Reject> {
        self.send(cmd)
    }

    /// The summary for `task-cmd status`: one line, and motion's external
    /// offsets line while one is applied or requested.
    pub fn summary(&self) -> String {
        match self.client.status() {
            Ok(s) => {
                let mut text = format!(
                    "motion: {} ({}), {} joints, {}",
                    if s.enabled { "enabled" } else { "disabled" },
                    s.mode,
                    s.joints.iter().filter(|j| j.active).count(),
                    if s.all_homed {
                        "all homed"
                    } else {
                        "not all homed"
                    }
                );
                if let Some(line) = s.external_offsets_line() {
                    text.push('\n');
                    text.push_str(&line);
                }
                text
            }
            Err(e) => format!("motion: status not readable: {e}"),
        }
    }
}
