//! The motion controller core: per-joint controllers, the enable/disable
//! state machine, free-mode jogging, limits, following error and fault
//! handling, independent of HAL.
//!
//! [`MotionCore::cycle`] is one run of LinuxCNC's `motion-controller`
//! function in the documented order (reference §4.2): latch the homing
//! inputs, switch kinematics if asked, read the joint inputs and compute
//! feedback and following error, forward kinematics of the feedback, probe,
//! fault checks, mode transitions, jog wheels, position commands per mode
//! with the backup soft-limit check, backlash compensation and the motor
//! commands. [`MotionCore::command`] is one command taken by
//! `motion-command-handler`. The HAL glue (`motmod`) copies pins into
//! [`MotionCore::inputs`] and [`MotionCore::joint_inputs`] before each call
//! and writes the results back to pins after it; tests drive the core
//! directly.
//!
//! Per joint the seven position quantities are, in cycle order:
//! (5) `motor_pos_fb` read from HAL, (6) `pos_fb = motor_pos_fb −
//! (backlash_filt + motor_offset)`, (7) `carte_pos_fb` = forward kinematics
//! of (6), then (2) `coarse_pos` and (3) `pos_cmd` from the free planner
//! (or `pos_fb` while disabled), (1) `carte_pos_cmd` = forward kinematics of
//! the previous cycle's (2) (or (7) while disabled), and (4)
//! `motor_pos_cmd = pos_cmd + backlash_filt + motor_offset`.
//!
//! Everything is preallocated when the core is built; a cycle or a command
//! never allocates, locks or makes a system call.
//!
//! Modes: disabled, free (joint) mode, teleop mode (world axis jogs through
//! the inverse kinematics) and coordinated mode, which holds its pose until
//! the queued trajectory planner exists; the world modes and the mode
//! requests are in `teleop.rs`, whose documentation lists their
//! differences from LinuxCNC. Homing and the spindles come later (their HAL
//! pins already exist). Deliberate differences from LinuxCNC, each
//! following a "→ Design" note of the reference:
//! * every refused command returns a [`Reject`] and changes nothing, and a
//!   refused jog does not set the joint's error flag;
//! * the free-mode SCALE is applied to the free planners as a jog override
//!   (LinuxCNC ignores its feed override in free mode);
//! * jog velocities are capped at the joint's velocity limit (LinuxCNC's
//!   task does this before sending);
//! * an absolute jog checks the hard limit in its direction of travel;
//! * deactivating a joint also switches its amplifier off, and is refused
//!   while the joint moves;
//! * `motion.jog-stop` is tested directly (not through the SS enable bit).

use std::sync::Arc;

use crate::axis::{wheel_acc, AxisInputs};
use crate::command::{Command, CommandResult, Direction, Feature, Quantity, Reject};
use crate::events::{Event, EventRing};
use crate::homing::{ConfigProblem, HomeFault, HomeFlags, HomeState, Homing, HomingConfig};
use crate::joint::{Joint, JointInputs, JointStatus};
use crate::kins::{Kinematics, KinematicsType, KinsFlags, Pose, NUM_AXES};

mod teleop;
pub use teleop::MODE_ENTRY_TOLERANCE;
use teleop::{Mode, World};

/// Most joints (`EMCMOT_MAX_JOINTS`).
pub const MAX_JOINTS: usize = 16;
/// Most spindles (`EMCMOT_MAX_SPINDLES`).
pub const MAX_SPINDLES: usize = 8;
/// Most digital or analog I/O pairs (`EMCMOT_MAX_DIO`, `EMCMOT_MAX_AIO`).
pub const MAX_IO: usize = 64;
/// Most misc-error inputs (`EMCMOT_MAX_MISC_ERROR`).
pub const MAX_MISC_ERROR: usize = 64;

/// Spindle-scale enable bit (M51): also gates the inhibit inputs.
pub const SS_ENABLED: u8 = 0x01;
/// Feed-scale enable bit (M50).
pub const FS_ENABLED: u8 = 0x02;
/// Adaptive-feed enable bit (M52).
pub const AF_ENABLED: u8 = 0x04;
/// Feed-hold enable bit (M53).
pub const FH_ENABLED: u8 = 0x08;

/// How large the motion controller is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotionConfig {
    /// Joints, including extra joints (1..=16).
    pub num_joints: usize,
    /// Trailing joints that take no part in kinematics.
    pub num_extrajoints: usize,
    /// Spindles (0..=8).
    pub num_spindles: usize,
    /// Misc-error inputs (0..=64).
    pub num_misc_error: usize,
    /// Joints with `unlock`/`is-unlocked` pins (bit n: joint n), the only
    /// ones that may be locking indexers.
    pub unlock_joints_mask: u32,
}

impl Default for MotionConfig {
    fn default() -> Self {
        MotionConfig {
            num_joints: 3,
            num_extrajoints: 0,
            num_spindles: 1,
            num_misc_error: 0,
            unlock_joints_mask: 0,
        }
    }
}

/// The machine-wide HAL inputs (`motion.*`, `spindle.N.*`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionInputs {
    /// `motion.enable` (default true).
    pub enable: bool,
    /// `motion.probe-input`.
    pub probe_input: bool,
    /// `motion.adaptive-feed` (default 1.0).
    pub adaptive_feed: f64,
    /// `motion.feed-hold`.
    pub feed_hold: bool,
    /// `motion.feed-inhibit`.
    pub feed_inhibit: bool,
    /// `motion.homing-inhibit`.
    pub homing_inhibit: bool,
    /// `motion.jog-inhibit`.
    pub jog_inhibit: bool,
    /// `motion.jog-stop`.
    pub jog_stop: bool,
    /// `motion.jog-stop-immediate`.
    pub jog_stop_immediate: bool,
    /// `motion.switchkins-type`.
    pub switchkins_type: f64,
    /// `motion.misc-error-NN` / `motion.err-<name>`.
    pub misc_error: [bool; MAX_MISC_ERROR],
    /// `spindle.N.amp-fault-in`.
    pub spindle_amp_fault: [bool; MAX_SPINDLES],
}

impl Default for MotionInputs {
    fn default() -> Self {
        MotionInputs {
            enable: true,
            probe_input: false,
            adaptive_feed: 1.0,
            feed_hold: false,
            feed_inhibit: false,
            homing_inhibit: false,
            jog_inhibit: false,
            jog_stop: false,
            jog_stop_immediate: false,
            switchkins_type: 0.0,
            misc_error: [false; MAX_MISC_ERROR],
            spindle_amp_fault: [false; MAX_SPINDLES],
        }
    }
}

/// The operating state, derived every cycle from the motion flags.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionState {
    /// Amplifiers off; commands track feedback.
    Disabled,
    /// Joint mode: every joint has its own planner.
    Free,
    /// World jog mode: every axis has its own planner, the inverse
    /// kinematics move the joints.
    Teleop,
    /// Coordinated mode: the commanded pose is held (no queued planner
    /// yet), the inverse kinematics move the joints.
    Coord,
}

/// The motion controller.
pub struct MotionCore {
    kins: Arc<dyn Kinematics>,
    kins_type: KinematicsType,
    kins_flags: KinsFlags,
    cfg: MotionConfig,
    /// Joints taking part in kinematics (the leading ones).
    kins_joints: usize,
    joints: Vec<Joint>,
    /// Machine-wide inputs; the HAL glue refreshes them before every call.
    pub inputs: MotionInputs,
    /// Per-joint inputs, one per joint.
    pub joint_inputs: Vec<JointInputs>,
    /// Per-axis jog-wheel inputs (X Y Z A B C U V W).
    pub axis_inputs: [AxisInputs; NUM_AXES],
    /// The mode (kept over a disable) and the nine axes.
    world: World,
    events: Arc<EventRing>,

    /// Requested enabled state (set by commands, honoured by the cycle).
    enabling: bool,
    /// The ENABLE flag.
    enabled: bool,
    /// The INPOS flag.
    inpos: bool,
    /// The motion ERROR flag (`motion.coord-error`).
    error: bool,
    state: MotionState,
    /// Hard limits overridden: bit 2n negative, bit 2n+1 positive of joint n.
    override_limit_mask: u32,
    /// An overriding jog has started; the override ends when all stop.
    overriding: bool,
    carte_pos_cmd: Pose,
    carte_pos_cmd_ok: bool,
    carte_pos_fb: Pose,
    carte_pos_fb_ok: bool,
    world_home: Pose,
    on_soft_limit: bool,
    /// Free-mode SCALE (0..=1).
    scale: f64,
    net_feed_scale: f64,
    enables_new: u8,
    /// The homing state machines and sequence manager.
    homing: Homing,
    /// Whether jog moves since the last queued move unhome all joints
    /// (inverse-only kinematics).
    rehome_all: bool,
    wheel_first_pass: bool,
    old_probe: bool,
    jog_is_active: bool,
    current_vel: f64,
    switchkins_type: i32,
    heartbeat: u64,
    /// Scratch for kinematics calls.
    positions: [f64; MAX_JOINTS],
}

impl std::fmt::Debug for MotionCore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MotionCore")
            .field("kins", &self.kins.name())
            .field("cfg", &self.cfg)
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

/// A C `(int)` conversion of a float, x86-64 style: out of range and NaN
/// give `i32::MIN`.
fn c_int(v: f64) -> i32 {
    if v.is_nan() || v <= -2147483649.0 || v >= 2147483648.0 {
        i32::MIN
    } else {
        v as i32
    }
}

impl MotionCore {
    /// A controller for `cfg.num_joints` joints (clamped to 1..=16) using
    /// `kins`. Joints start inactive with LinuxCNC's default limits; motion
    /// starts disabled.
    pub fn new(cfg: MotionConfig, kins: Arc<dyn Kinematics>) -> MotionCore {
        let mut cfg = cfg;
        cfg.num_joints = cfg.num_joints.clamp(1, MAX_JOINTS);
        cfg.num_extrajoints = cfg.num_extrajoints.min(cfg.num_joints);
        cfg.num_spindles = cfg.num_spindles.min(MAX_SPINDLES);
        cfg.num_misc_error = cfg.num_misc_error.min(MAX_MISC_ERROR);
        let kins_type = kins.kins_type();
        MotionCore {
            kins,
            kins_type,
            kins_flags: KinsFlags::default(),
            cfg,
            kins_joints: cfg.num_joints - cfg.num_extrajoints,
            joints: vec![Joint::default(); cfg.num_joints],
            inputs: MotionInputs::default(),
            joint_inputs: vec![JointInputs::default(); cfg.num_joints],
            axis_inputs: [AxisInputs::default(); NUM_AXES],
            world: World::default(),
            events: Arc::new(EventRing::default()),
            enabling: false,
            enabled: false,
            inpos: true,
            error: false,
            state: MotionState::Disabled,
            override_limit_mask: 0,
            overriding: false,
            carte_pos_cmd: Pose::ZERO,
            carte_pos_cmd_ok: false,
            carte_pos_fb: Pose::ZERO,
            carte_pos_fb_ok: false,
            world_home: Pose::ZERO,
            on_soft_limit: false,
            scale: 1.0,
            net_feed_scale: 1.0,
            enables_new: FS_ENABLED | SS_ENABLED | FH_ENABLED,
            homing: Homing::new(cfg.num_joints),
            rehome_all: false,
            wheel_first_pass: true,
            old_probe: false,
            jog_is_active: false,
            current_vel: 0.0,
            switchkins_type: 0,
            heartbeat: 0,
            positions: [0.0; MAX_JOINTS],
        }
    }

    // ----------------------------------------------------------------
    // Status

    /// The configuration in use.
    pub fn config(&self) -> MotionConfig {
        self.cfg
    }

    /// The kinematics in use.
    pub fn kinematics(&self) -> &Arc<dyn Kinematics> {
        &self.kins
    }

    /// Where reported messages go.
    pub fn events(&self) -> &Arc<EventRing> {
        &self.events
    }

    /// Number of joints.
    pub fn num_joints(&self) -> usize {
        self.joints.len()
    }

    /// A copy of joint `j`'s state.
    ///
    /// # Panics
    /// If `j` is not a joint number.
    pub fn joint(&self, j: usize) -> JointStatus {
        self.joints[j].status()
    }

    /// The operating state.
    pub fn state(&self) -> MotionState {
        self.state
    }

    /// Whether motion is enabled (amplifiers of active joints on).
    pub fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// Whether every planner is at rest.
    pub fn in_position(&self) -> bool {
        self.inpos
    }

    /// The motion ERROR flag (`motion.coord-error`).
    pub fn error(&self) -> bool {
        self.error
    }

    /// Whether a homed joint's command is outside its soft limits.
    pub fn on_soft_limit(&self) -> bool {
        self.on_soft_limit
    }

    /// The commanded world pose (1) and whether it is valid.
    pub fn carte_pos_cmd(&self) -> (Pose, bool) {
        (self.carte_pos_cmd, self.carte_pos_cmd_ok)
    }

    /// The world feedback pose (7) and whether it is valid.
    pub fn carte_pos_fb(&self) -> (Pose, bool) {
        (self.carte_pos_fb, self.carte_pos_fb_ok)
    }

    /// The hard-limit override mask (bit 2n: joint n negative, 2n+1
    /// positive).
    pub fn override_limit_mask(&self) -> u32 {
        self.override_limit_mask
    }

    /// The free-mode SCALE in use.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The combined feed scale of this cycle (feed hold, inhibit).
    pub fn net_feed_scale(&self) -> f64 {
        self.net_feed_scale
    }

    /// Speed of the machine: √Σ v² over the joints whose planner moves.
    pub fn current_vel(&self) -> f64 {
        self.current_vel
    }

    /// Whether a keyboard or wheel jog is in progress on any joint.
    pub fn jog_is_active(&self) -> bool {
        self.jog_is_active
    }

    /// Whether homing is in progress.
    pub fn homing_active(&self) -> bool {
        self.homing.is_active()
    }

    /// Joint `j`'s homing state (`joint.N.home-state`).
    ///
    /// # Panics
    /// If `j` is not a joint number.
    pub fn home_state(&self, j: usize) -> HomeState {
        self.homing.joints[j].state
    }

    /// Joint `j`'s published `homing` flag: true while it homes, and
    /// while the sequence it belongs to still runs (so a client does not
    /// send a new HOME that would be refused).
    pub fn joint_homing(&self, j: usize) -> bool {
        self.joints[j].homing || self.homing.in_sequence(j)
    }

    /// Joint `j`'s homing configuration.
    pub fn homing_config(&self, j: usize) -> HomingConfig {
        self.homing.joints[j].cfg
    }

    /// What to write to joint `j`'s `index-enable` this cycle: only the
    /// edges of homing's request, because the encoder drives the same
    /// signal.
    pub fn index_enable_drive(&self, j: usize) -> Option<bool> {
        self.homing.joints[j].index_drive
    }

    /// Joint `j`'s `unlock` output (locking indexers); false while
    /// disabled.
    pub fn unlock_output(&self, j: usize) -> bool {
        self.enabled && self.homing.joints[j].unlock
    }

    /// Whether every active joint is homed.
    pub fn is_all_homed(&self) -> bool {
        self.joints.iter().all(|j| !j.active || j.homed)
    }

    /// Completed cycles.
    pub fn heartbeat(&self) -> u64 {
        self.heartbeat
    }

    /// The kinematics type.
    pub fn kins_type(&self) -> KinematicsType {
        self.kins_type
    }

    pub(crate) fn joint_ref(&self, j: usize) -> &Joint {
        &self.joints[j]
    }

    /// Requests the disabled state without a command (the safe-state hook).
    pub fn force_disable(&mut self) {
        self.enabling = false;
    }

    /// Every homing state joint `j` has entered.
    #[cfg(test)]
    pub(crate) fn homing_trace(&self, j: usize) -> &[HomeState] {
        &self.homing.joints[j].trace
    }

    /// Marks joint `j` homed or not, as the homing state machine will.
    #[cfg(test)]
    pub(crate) fn set_homed(&mut self, j: usize, homed: bool) {
        self.joints[j].homed = homed;
    }

    // ----------------------------------------------------------------
    // Commands

    fn joint_index(&self, joint: i32) -> Result<usize, Reject> {
        if joint >= 0 && (joint as usize) < self.joints.len() {
            Ok(joint as usize)
        } else {
            Err(Reject::NoSuchJoint {
                joint,
                num_joints: self.joints.len(),
            })
        }
    }

    fn finite(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    fn non_negative(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    fn positive(what: Quantity, value: f64) -> Result<f64, Reject> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Reject::BadValue { what, value })
        }
    }

    /// Applies one command. On `Err` nothing changed. Reads the
    /// machine-wide inputs (`motion.enable`, `motion.jog-inhibit`) from
    /// [`Self::inputs`].
    pub fn command(&mut self, cmd: &Command) -> CommandResult {
        match *cmd {
            Command::Abort => {
                self.homing.abort(&mut self.joints);
                for j in &mut self.joints {
                    j.free_tp.enable = false;
                    j.error = false;
                    j.fault = false;
                }
                self.abort_axis_jogs(false);
                self.error = false;
                Ok(())
            }
            Command::Enable => {
                if !self.inputs.enable {
                    return Err(Reject::EnableInputFalse);
                }
                self.enabling = true;
                Ok(())
            }
            Command::Disable => {
                self.enabling = false;
                Ok(())
            }
            Command::JogCont { joint, vel } => {
                let j = self.jog_checks(joint, vel)?;
                self.jog_direction_ok(j, dir_of(vel))?;
                let jt = &mut self.joints[j];
                jt.refresh_jog_limits();
                jt.free_tp.pos_cmd = if vel > 0.0 {
                    jt.max_jog_limit
                } else {
                    jt.min_jog_limit
                };
                self.start_kb_jog(j, vel);
                Ok(())
            }
            Command::JogIncr { joint, vel, offset } => {
                let j = self.jog_checks(joint, vel)?;
                let offset = Self::non_negative(Quantity::JogIncrement, offset)?;
                self.jog_direction_ok(j, dir_of(vel))?;
                let jt = &mut self.joints[j];
                jt.refresh_jog_limits();
                let target = if vel > 0.0 {
                    jt.free_tp.pos_cmd + offset
                } else {
                    jt.free_tp.pos_cmd - offset
                };
                if !target.is_finite() {
                    return Err(Reject::BadValue {
                        what: Quantity::JogTarget,
                        value: target,
                    });
                }
                if target > jt.max_jog_limit || target < jt.min_jog_limit {
                    return Err(Reject::TargetOutsideLimits {
                        joint: j,
                        target,
                        min: jt.min_jog_limit,
                        max: jt.max_jog_limit,
                    });
                }
                jt.free_tp.pos_cmd = target;
                self.start_kb_jog(j, vel);
                Ok(())
            }
            Command::JogAbs { joint, vel, pos } => {
                let j = self.jog_checks(joint, vel)?;
                let pos = Self::finite(Quantity::JogPosition, pos)?;
                let jt = &mut self.joints[j];
                jt.refresh_jog_limits();
                let target = pos.clamp(jt.min_jog_limit, jt.max_jog_limit);
                let here = jt.free_tp.curr_pos;
                if target != here {
                    let dir = if target > here {
                        Direction::Positive
                    } else {
                        Direction::Negative
                    };
                    self.jog_direction_ok(j, dir)?;
                }
                self.joints[j].free_tp.pos_cmd = target;
                self.start_kb_jog(j, vel);
                Ok(())
            }
            Command::JogAbort { joint } => {
                let j = self.joint_index(joint)?;
                self.homing.cancel_joint(j, &mut self.joints);
                let jt = &mut self.joints[j];
                jt.end_jogs(false);
                jt.error = false;
                Ok(())
            }
            Command::JointActivate { joint } => {
                let j = self.joint_index(joint)?;
                // Activated while enabled, the joint would move without
                // being enabled, and so without its fault checks.
                if self.enabled && !self.joints[j].active {
                    return Err(Reject::ActivateWhileEnabled { joint: j });
                }
                self.joints[j].active = true;
                Ok(())
            }
            Command::JointDeactivate { joint } => {
                let j = self.joint_index(joint)?;
                if self.homing.in_sequence(j) {
                    return Err(Reject::HomingActive);
                }
                if self.axes_moving() {
                    return Err(Reject::JointMoving { joint: j });
                }
                let jt = &mut self.joints[j];
                if jt.free_tp.active {
                    return Err(Reject::JointMoving { joint: j });
                }
                jt.active = false;
                jt.enabled = false;
                jt.free_tp.enable = false;
                Ok(())
            }
            Command::OverrideLimits { joint } => {
                if joint < 0 {
                    self.override_limit_mask = 0;
                } else {
                    let mut mask = 0u32;
                    for (n, jt) in self.joints.iter().enumerate() {
                        if jt.nhl {
                            mask |= 1 << (2 * n);
                        }
                        if jt.phl {
                            mask |= 2 << (2 * n);
                        }
                    }
                    self.override_limit_mask = mask;
                }
                self.overriding = false;
                for jt in &mut self.joints {
                    jt.error = false;
                }
                Ok(())
            }
            Command::Free => self.request_mode(Mode::Free),
            Command::Teleop => self.request_mode(Mode::Teleop),
            Command::Coord => self.request_mode(Mode::Coord),
            Command::EnableAmplifier { joint } | Command::DisableAmplifier { joint } => {
                self.joint_index(joint)?;
                Err(Reject::Unsupported {
                    what: Feature::AmplifierCommand,
                })
            }
            Command::Scale { scale } => {
                if scale.is_nan() {
                    return Err(Reject::BadValue {
                        what: Quantity::Scale,
                        value: scale,
                    });
                }
                self.scale = scale.clamp(0.0, 1.0);
                Ok(())
            }
            Command::SetJointPositionLimits { joint, min, max } => {
                let j = self.joint_index(joint)?;
                let min = Self::finite(Quantity::MinimumLimit, min)?;
                let max = Self::finite(Quantity::MaximumLimit, max)?;
                if min > max {
                    return Err(Reject::LimitsReversed { min, max });
                }
                self.joints[j].cfg.min_pos_limit = min;
                self.joints[j].cfg.max_pos_limit = max;
                Ok(())
            }
            Command::SetJointVelLimit { joint, vel } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.vel_limit = Self::positive(Quantity::VelocityLimit, vel)?;
                Ok(())
            }
            Command::SetJointAccLimit { joint, acc } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.acc_limit = Self::positive(Quantity::AccelerationLimit, acc)?;
                Ok(())
            }
            Command::SetJointMinFerror { joint, ferror } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.min_ferror =
                    Self::non_negative(Quantity::MinimumFerror, ferror)?;
                Ok(())
            }
            Command::SetJointMaxFerror { joint, ferror } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.max_ferror =
                    Self::non_negative(Quantity::MaximumFerror, ferror)?;
                Ok(())
            }
            Command::SetJointBacklash { joint, backlash } => {
                let j = self.joint_index(joint)?;
                self.joints[j].cfg.backlash = Self::non_negative(Quantity::Backlash, backlash)?;
                Ok(())
            }
            Command::SetJointMotorOffset { joint, offset } => {
                let j = self.joint_index(joint)?;
                if self.homing.is_active() {
                    return Err(Reject::HomingActive);
                }
                self.joints[j].motor_offset = Self::finite(Quantity::MotorOffset, offset)?;
                Ok(())
            }
            Command::SetWorldHome { pose } => {
                for v in pose.0 {
                    Self::finite(Quantity::WorldHomeCoordinate, v)?;
                }
                self.world_home = pose;
                Ok(())
            }
            Command::Home { joint } => self.home(joint),
            Command::Unhome { joint } => self.unhome(joint),
            Command::SetJointHomingParams { joint, config } => {
                let j = self.joint_index(joint)?;
                config
                    .check()
                    .map_err(|problem| Reject::BadHomingConfig { joint: j, problem })?;
                let lockable = j < 32 && self.cfg.unlock_joints_mask & (1 << j) != 0;
                if config.flags.contains(HomeFlags::UNLOCK_FIRST) && !lockable {
                    return Err(Reject::BadHomingConfig {
                        joint: j,
                        problem: ConfigProblem::NoUnlockPins,
                    });
                }
                if self.homing.is_active() {
                    return Err(Reject::HomingActive);
                }
                self.homing.joints[j].cfg = config;
                Ok(())
            }
            Command::UpdateJointHomingParams {
                joint,
                offset,
                home,
                sequence,
            } => {
                let j = self.joint_index(joint)?;
                let config = HomingConfig {
                    offset,
                    home,
                    sequence,
                    ..self.homing.joints[j].cfg
                };
                config
                    .check()
                    .map_err(|problem| Reject::BadHomingConfig { joint: j, problem })?;
                if self.homing.is_active() {
                    return Err(Reject::HomingActive);
                }
                self.homing.joints[j].cfg = config;
                Ok(())
            }
            Command::AxisJogCont { axis, vel } => self.axis_jog_cont(axis, vel),
            Command::AxisJogIncr { axis, vel, offset } => self.axis_jog_incr(axis, vel, offset),
            Command::AxisJogAbs { axis, vel, pos } => self.axis_jog_abs(axis, vel, pos),
            Command::AxisJogAbort { axis } => self.axis_jog_abort(axis),
            Command::SetAxisPositionLimits { axis, min, max } => {
                self.set_axis_position_limits(axis, min, max)
            }
            Command::SetAxisVelLimit { axis, vel } => self.set_axis_vel_limit(axis, vel),
            Command::SetAxisAccLimit { axis, acc } => self.set_axis_acc_limit(axis, acc),
        }
    }

    /// JOINT_HOME with its requirements, in LinuxCNC's order.
    fn home(&mut self, joint: i32) -> CommandResult {
        if joint != -1 {
            self.joint_index(joint)?;
        }
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        if self.state != MotionState::Free {
            return Err(Reject::NotFreeMode);
        }
        if self.inputs.homing_inhibit {
            return Err(Reject::HomingInhibited);
        }
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        // Homed extra joints follow posthome-cmd, not their planner.
        let mut following_posthome = [false; MAX_JOINTS];
        for (j, f) in following_posthome
            .iter_mut()
            .enumerate()
            .take(self.joints.len())
        {
            *f = j >= self.kins_joints && self.joints[j].homed;
        }
        self.homing.request(joint, &mut self.joints)?;
        // Homing one of them takes it back from posthome-cmd: its
        // command restarts where it is.
        for (j, jt) in self.joints.iter_mut().enumerate() {
            if following_posthome[j] && self.homing.in_sequence(j) && !jt.homed {
                jt.pos_cmd = jt.pos_fb;
                jt.coarse_pos = jt.pos_fb;
                jt.rest_planner_at(jt.pos_fb);
            }
        }
        Ok(())
    }

    /// JOINT_UNHOME: one joint, every active joint (−1) or the volatile
    /// ones (−2); for −1 and −2 all or nothing.
    fn unhome(&mut self, joint: i32) -> CommandResult {
        if !matches!(self.state, MotionState::Free | MotionState::Disabled) {
            return Err(Reject::NotFreeOrDisabled);
        }
        let volatile_only = match joint {
            -1 => false,
            -2 => true,
            _ => {
                let j = self.joint_index(joint)?;
                let jt = &self.joints[j];
                if !jt.active {
                    return Err(Reject::JointInactive { joint: j });
                }
                if jt.homing || self.homing.in_sequence(j) {
                    return Err(Reject::HomingActive);
                }
                if jt.free_tp.active {
                    return Err(Reject::JointMoving { joint: j });
                }
                if j >= self.kins_joints && self.enabled {
                    return Err(Reject::ExtraJointEnabled { joint: j });
                }
                self.joints[j].homed = false;
                return Ok(());
            }
        };
        let chosen = |j: usize, jt: &Joint, homing: &Homing| {
            jt.active && (!volatile_only || homing.joints[j].cfg.volatile_home)
        };
        for (j, jt) in self.joints.iter().enumerate() {
            if !chosen(j, jt, &self.homing) {
                continue;
            }
            if jt.homing || self.homing.in_sequence(j) {
                return Err(Reject::HomingActive);
            }
            if jt.free_tp.active {
                return Err(Reject::JointMoving { joint: j });
            }
            if j >= self.kins_joints && self.enabled && jt.homed {
                return Err(Reject::ExtraJointEnabled { joint: j });
            }
        }
        for j in 0..self.joints.len() {
            if chosen(j, &self.joints[j], &self.homing) {
                self.joints[j].homed = false;
            }
        }
        Ok(())
    }

    /// The requirements every free-mode jog shares; returns the joint.
    fn jog_checks(&self, joint: i32, vel: f64) -> Result<usize, Reject> {
        let j = self.joint_index(joint)?;
        if !vel.is_finite() || vel == 0.0 {
            return Err(Reject::BadVelocity { vel });
        }
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        if self.state == MotionState::Teleop {
            return Err(Reject::JointJogInTeleop);
        }
        if self.state != MotionState::Free {
            return Err(Reject::NotFreeMode);
        }
        if !self.joints[j].active {
            return Err(Reject::JointInactive { joint: j });
        }
        if self.inputs.jog_inhibit {
            return Err(Reject::JogInhibited);
        }
        if self.homing.is_active() {
            return Err(Reject::HomingActive);
        }
        if self.joints[j].wheel_jog_active {
            return Err(Reject::WheelJogActive { joint: j });
        }
        let flags = self.homing.joints[j].cfg.flags;
        if flags.contains(HomeFlags::UNLOCK_FIRST) {
            return Err(Reject::LockingIndexer { joint: j });
        }
        if self.homing.is_synchronized(j) {
            return Err(Reject::SynchronizedJoint { joint: j });
        }
        Ok(j)
    }

    /// LinuxCNC's `joint_jog_ok`: no jogging further into a tripped hard
    /// limit (unless both limits of the joint are overridden: a shared
    /// switch) and none from beyond the jog limit further out.
    fn jog_direction_ok(&mut self, j: usize, dir: Direction) -> Result<(), Reject> {
        let neg_ovr = self.override_limit_mask & (1 << (2 * j)) != 0;
        let pos_ovr = self.override_limit_mask & (2 << (2 * j)) != 0;
        if neg_ovr && pos_ovr {
            return Ok(());
        }
        let jt = &mut self.joints[j];
        match dir {
            Direction::Positive if jt.phl => {
                return Err(Reject::OnHardLimit { joint: j, dir });
            }
            Direction::Negative if jt.nhl => {
                return Err(Reject::OnHardLimit { joint: j, dir });
            }
            _ => {}
        }
        jt.refresh_jog_limits();
        match dir {
            Direction::Positive if jt.pos_cmd > jt.max_jog_limit => {
                Err(Reject::PastSoftLimit { joint: j, dir })
            }
            Direction::Negative if jt.pos_cmd < jt.min_jog_limit => {
                Err(Reject::PastSoftLimit { joint: j, dir })
            }
            _ => Ok(()),
        }
    }

    /// What every accepted keyboard jog does once its target is set.
    fn start_kb_jog(&mut self, j: usize, vel: f64) {
        let jt = &mut self.joints[j];
        jt.free_tp.max_vel = vel.abs().min(jt.cfg.vel_limit);
        jt.free_tp.max_acc = jt.cfg.acc_limit;
        jt.kb_jog_active = true;
        jt.free_tp.enable = true;
        jt.error = false;
        self.clear_homes(j);
    }

    /// Inverse-only kinematics cannot tell where a jogged machine is:
    /// jogging unhomes the joint (every joint once a move was queued).
    fn clear_homes(&mut self, j: usize) {
        if self.kins_type == KinematicsType::InverseOnly {
            if self.rehome_all {
                for jt in &mut self.joints {
                    jt.homed = false;
                }
            } else {
                self.joints[j].homed = false;
            }
        }
    }

    // ----------------------------------------------------------------
    // The servo cycle

    /// One servo cycle of `period` seconds (LinuxCNC's `period * 1e-9`).
    pub fn cycle(&mut self, period: f64) {
        self.latch_homing_inputs();
        self.switch_kinematics();
        self.process_inputs();
        self.forward_kins_feedback();
        self.process_probe();
        self.check_for_faults();
        self.set_operating_mode();
        self.handle_jog_wheels();
        self.handle_axis_jog_wheels();
        let mut homed_all_now = false;
        if self.state == MotionState::Free {
            let was_homing = self.homing.is_active();
            self.homing.run(&mut self.joints, period, &self.events);
            homed_all_now = was_homing && !self.homing.is_active() && self.is_all_homed();
        }
        self.get_pos_cmds(period);
        if homed_all_now {
            // As LinuxCNC: once homing has homed every joint, motion goes
            // to teleop mode by itself (world jogs from then on). Entered
            // after this cycle's commands, so at the exact HOME positions.
            // A refusal (kinematics that cannot reproduce the joints)
            // leaves motion in free mode.
            let _ = self.request_mode(teleop::Mode::Teleop);
        }
        self.compute_backlash(period);
        self.motor_commands();
        self.homing.update_outputs();
        self.heartbeat = self.heartbeat.wrapping_add(1);
    }

    fn latch_homing_inputs(&mut self) {
        for ((jt, jh), inp) in self
            .joints
            .iter_mut()
            .zip(&mut self.homing.joints)
            .zip(&self.joint_inputs)
        {
            jt.home_sw = inp.home_sw;
            jt.index_enable = inp.index_enable;
            jh.is_unlocked = inp.is_unlocked;
        }
    }

    /// Switchable kinematics follow `motion.switchkins-type`.
    fn switch_kinematics(&mut self) {
        if !self.kins.is_switchable() {
            return;
        }
        let t = c_int(self.inputs.switchkins_type);
        if t == self.switchkins_type {
            return;
        }
        self.switchkins_type = t;
        match self.kins.switch_to(t) {
            Err(_) => {
                self.events.push(Event::KinsSwitchFailed { kins_type: t });
                self.error = true;
            }
            Ok(()) => {
                let n = self.load_positions(|jt| jt.pos_cmd);
                let _ = self.kins.forward(
                    &self.positions[..n],
                    &mut self.carte_pos_cmd,
                    &mut self.kins_flags,
                );
                self.world_kins_switched();
            }
        }
    }

    fn process_inputs(&mut self) {
        let enables = self.enables_new;
        let mut scale = 1.0;
        if enables & FH_ENABLED != 0 && self.inputs.feed_hold {
            scale = 0.0;
        }
        if enables & SS_ENABLED != 0 && self.inputs.feed_inhibit {
            scale = 0.0;
        }
        self.net_feed_scale = scale;

        for ((jt, jh), inp) in self
            .joints
            .iter_mut()
            .zip(&self.homing.joints)
            .zip(&self.joint_inputs)
        {
            if !jt.active {
                continue;
            }
            // In the cycle the encoder reports the index its count may
            // have jumped: homing re-derives the feedback right after.
            let index_hit = jh.index_seen(jt);
            jt.process_inputs(inp, index_hit);
        }
        self.extra_joints_ferror();

        if self.jog_is_active && (self.inputs.jog_stop || self.inputs.jog_stop_immediate) {
            let immediate = self.inputs.jog_stop_immediate;
            for jt in &mut self.joints {
                if jt.kb_jog_active || jt.wheel_jog_active {
                    jt.end_jogs(immediate);
                }
            }
            self.stop_axis_jogs(immediate);
            self.jog_is_active = false;
            self.events.push(Event::JogStopped { immediate });
        }
    }

    /// Homed extra joints are commanded from `posthome-cmd`; motion does not
    /// plan or check them.
    fn extra_joints_ferror(&mut self) {
        let first_extra = self.kins_joints;
        for jt in &mut self.joints[first_extra..] {
            if jt.active && jt.homed {
                jt.ferror = 0.0;
                jt.ferror_flag = false;
            }
        }
    }

    /// Copies a position of each kinematic joint into the kinematics
    /// scratch; returns how many there are.
    fn load_positions(&mut self, of: impl Fn(&Joint) -> f64) -> usize {
        let n = self.kins_joints;
        for (p, jt) in self.positions.iter_mut().zip(&self.joints[..n]) {
            *p = of(jt);
        }
        n
    }

    /// Forward kinematics of the loaded positions into `pose`, with
    /// LinuxCNC's validity rules: identity kinematics always compute and
    /// are valid once every joint is homed; kinematics of both kinds
    /// compute only once homed, starting from the world home when the
    /// previous result was not valid. `None` for kinematics without a
    /// usable forward direction (the caller decides).
    fn forward_pose(&mut self, n: usize, pose: &mut Pose, was_ok: bool) -> Option<bool> {
        let all_homed = self.is_all_homed();
        let q = &self.positions[..n];
        match self.kins_type {
            KinematicsType::Identity => {
                let _ = self.kins.forward(q, pose, &mut self.kins_flags);
                Some(all_homed)
            }
            KinematicsType::Both if all_homed => {
                if !was_ok {
                    *pose = self.world_home;
                }
                Some(self.kins.forward(q, pose, &mut self.kins_flags).is_ok())
            }
            KinematicsType::Both => Some(false),
            KinematicsType::InverseOnly | KinematicsType::ForwardOnly => None,
        }
    }

    fn forward_kins_feedback(&mut self) {
        let n = self.load_positions(|jt| jt.pos_fb);
        let mut pose = self.carte_pos_fb;
        let ok = self.forward_pose(n, &mut pose, self.carte_pos_fb_ok);
        self.carte_pos_fb = pose;
        match ok {
            Some(ok) => self.carte_pos_fb_ok = ok,
            None => {
                // Without forward kinematics the world command stands in
                // for the feedback in the world modes (as LinuxCNC does);
                // in free mode there is none.
                let world = matches!(self.state, MotionState::Teleop | MotionState::Coord);
                if world {
                    self.carte_pos_fb = self.carte_pos_cmd;
                }
                self.carte_pos_fb_ok = world;
            }
        }
    }

    /// A probe contact while jogging stops the jogs (no probing moves in
    /// free mode).
    fn process_probe(&mut self) {
        let probe = self.inputs.probe_input;
        if probe && !self.old_probe && self.homing.is_active() {
            if let Some(joint) = (0..self.joints.len()).find(|&j| self.joints[j].homing) {
                self.events.push(Event::HomingAborted {
                    joint,
                    fault: HomeFault::ProbeTripped,
                    state: self.homing.joints[joint].state,
                });
            }
            self.homing.abort(&mut self.joints);
        }
        if probe && !self.old_probe {
            let mut stopped = false;
            for jt in &mut self.joints {
                if jt.active && jt.free_tp.enable && !jt.homing {
                    jt.free_tp.enable = false;
                    stopped = true;
                }
            }
            if stopped {
                self.events.push(Event::ProbeTrippedDuringJog);
            }
            if self.stop_axis_jogs_on_probe() {
                self.events.push(Event::ProbeTrippedDuringAxisJog);
            }
        }
        self.old_probe = probe;
    }

    fn check_for_faults(&mut self) {
        if self.enabled && !self.inputs.enable {
            self.events.push(Event::EnableInputStopped);
            self.enabling = false;
        }
        for n in 0..self.cfg.num_spindles {
            if self.enabled && self.inputs.spindle_amp_fault[n] {
                self.events.push(Event::SpindleAmpFault { spindle: n });
                self.enabling = false;
            }
        }
        for n in 0..self.cfg.num_misc_error {
            if self.enabled && self.inputs.misc_error[n] {
                self.events.push(Event::MiscError { input: n });
                self.enabling = false;
            }
        }
        let mask = self.override_limit_mask;
        for (n, jt) in self.joints.iter_mut().enumerate() {
            if !(jt.active && jt.enabled) {
                continue;
            }
            let neg_ovr = mask & (1 << (2 * n)) != 0;
            let pos_ovr = mask & (2 << (2 * n)) != 0;
            if ((jt.phl && !pos_ovr) || (jt.nhl && !neg_ovr)) && !jt.homing {
                if !jt.error {
                    self.events.push(Event::JointOnLimit { joint: n });
                }
                jt.error = true;
                self.enabling = false;
            }
            if jt.fault {
                if !jt.error {
                    self.events.push(Event::JointAmpFault { joint: n });
                }
                jt.error = true;
                self.enabling = false;
            }
            if jt.ferror_flag {
                if !jt.error {
                    self.events.push(Event::JointFollowingError { joint: n });
                }
                jt.error = true;
                self.enabling = false;
            }
        }
    }

    fn set_operating_mode(&mut self) {
        if !self.enabling && self.enabled {
            if let Some(joint) = (0..self.joints.len()).find(|&j| self.joints[j].homing) {
                self.events.push(Event::HomingAborted {
                    joint,
                    fault: HomeFault::Disabled,
                    state: self.homing.joints[joint].state,
                });
            }
            self.homing.abort(&mut self.joints);
            for jt in &mut self.joints {
                jt.free_tp.enable = false;
                jt.free_tp.curr_vel = 0.0;
                if jt.active {
                    jt.inpos = true;
                    jt.enabled = false;
                }
            }
            self.world_disable_edge();
            self.enabled = false;
        }
        if self.enabling && !self.enabled {
            self.homing.abort(&mut self.joints);
            for jt in &mut self.joints {
                jt.free_tp.curr_pos = jt.pos_cmd;
                if jt.active {
                    jt.enabled = true;
                }
                jt.error = false;
            }
            self.enabled = true;
            self.error = false;
            self.world_enable_edge();
        }
        self.state = self.operating_state();
    }

    /// MPG jogs: each joint's `jog-counts` moves its free planner target.
    fn handle_jog_wheels(&mut self) {
        if self.inputs.jog_inhibit {
            return;
        }
        let first = self.wheel_first_pass;
        self.wheel_first_pass = false;
        for j in 0..self.joints.len() {
            let inp = self.joint_inputs[j];
            let jt = &mut self.joints[j];
            let delta = inp.jog_counts.wrapping_sub(jt.old_jog_counts);
            jt.old_jog_counts = inp.jog_counts;
            if first || delta == 0 || !jt.active {
                continue;
            }
            if self.state != MotionState::Free || !inp.jog_enable || self.homing.is_active() {
                continue;
            }
            if jt.kb_jog_active {
                continue;
            }
            let locking = self.homing.joints[j]
                .cfg
                .flags
                .contains(HomeFlags::UNLOCK_FIRST);
            if locking || self.homing.is_synchronized(j) {
                continue;
            }
            if self.net_feed_scale < 0.0001 {
                break;
            }
            let distance = f64::from(delta) * inp.jog_scale;
            if !distance.is_finite() {
                continue;
            }
            if distance > 0.0 && jt.phl {
                continue;
            }
            if distance < 0.0 && jt.nhl {
                continue;
            }
            let mut pos = jt.free_tp.pos_cmd + distance;
            jt.refresh_jog_limits();
            if pos > jt.max_jog_limit || pos < jt.min_jog_limit {
                continue;
            }
            let acc = wheel_acc(jt.cfg.acc_limit, inp.jog_accel_fraction);
            if inp.jog_vel_mode {
                let v = jt.cfg.vel_limit * self.net_feed_scale;
                let stop_dist = v * v / (2.0 * acc);
                if pos > jt.pos_cmd + stop_dist {
                    pos = jt.pos_cmd + stop_dist;
                } else if pos < jt.pos_cmd - stop_dist {
                    pos = jt.pos_cmd - stop_dist;
                }
            }
            jt.free_tp.pos_cmd = pos;
            jt.free_tp.max_vel = jt.cfg.vel_limit;
            jt.free_tp.max_acc = acc;
            jt.wheel_jog_active = true;
            jt.free_tp.enable = true;
            jt.error = false;
            self.clear_homes(j);
        }
    }

    fn get_pos_cmds(&mut self, period: f64) {
        match self.state {
            MotionState::Free => {
                // (1) is the forward kinematics of the previous cycle's (2).
                let n = self.load_positions(|jt| jt.coarse_pos);
                self.inpos = true;
                for (j, jt) in self.joints.iter_mut().enumerate() {
                    if !jt.active || (j >= n && jt.homed) {
                        continue;
                    }
                    jt.free_tp.max_acc = if jt.wheel_jog_active {
                        wheel_acc(jt.cfg.acc_limit, self.joint_inputs[j].jog_accel_fraction)
                    } else {
                        jt.cfg.acc_limit
                    };
                    // Homing moves ignore the jog override: the latch speed
                    // must not change with it, and a zero override would
                    // stall homing for ever.
                    let scale = if jt.homing { 1.0 } else { self.scale };
                    jt.free_tp.update(period, scale);
                    jt.pos_cmd = jt.free_tp.curr_pos;
                    jt.coarse_pos = jt.free_tp.curr_pos;
                    jt.vel_cmd = jt.free_tp.curr_vel;
                    jt.acc_cmd = 0.0;
                    jt.jerk_cmd = 0.0;
                    if jt.free_tp.active {
                        jt.inpos = false;
                        self.inpos = false;
                        if self.override_limit_mask != 0 {
                            self.overriding = true;
                        }
                    } else {
                        jt.inpos = true;
                        jt.kb_jog_active = false;
                        jt.wheel_jog_active = false;
                    }
                }
                if self.overriding && self.inpos {
                    self.override_limit_mask = 0;
                    self.overriding = false;
                }
                let mut pose = self.carte_pos_cmd;
                let ok = self.forward_pose(n, &mut pose, self.carte_pos_cmd_ok);
                self.carte_pos_cmd = pose;
                self.carte_pos_cmd_ok = ok.unwrap_or(false);
            }
            MotionState::Teleop => self.teleop_pos_cmds(period),
            MotionState::Coord => self.coord_pos_cmds(period),
            MotionState::Disabled => {
                self.carte_pos_cmd = self.carte_pos_fb;
                for jt in &mut self.joints {
                    jt.pos_cmd = jt.pos_fb;
                    jt.vel_cmd = 0.0;
                    jt.acc_cmd = 0.0;
                }
            }
        }
        self.check_soft_limits();
        self.teleop_soft_limit_stop();
    }

    /// The backup check: a homed joint commanded outside its soft limits
    /// raises the motion error once, when it happens.
    fn check_soft_limits(&mut self) {
        let mut onlimit = false;
        for jt in &mut self.joints {
            jt.soft_limit = None;
            if jt.active && jt.homed {
                if jt.pos_cmd > jt.cfg.max_pos_limit + 1e-12 {
                    jt.soft_limit = Some(Direction::Positive);
                    onlimit = true;
                } else if jt.pos_cmd < jt.cfg.min_pos_limit - 1e-12 {
                    jt.soft_limit = Some(Direction::Negative);
                    onlimit = true;
                }
            }
        }
        if onlimit {
            if !self.on_soft_limit {
                for (n, jt) in self.joints.iter().enumerate() {
                    if let Some(dir) = jt.soft_limit {
                        self.events.push(Event::SoftLimitExceeded { joint: n, dir });
                    }
                }
                self.error = true;
            }
            self.on_soft_limit = true;
        } else {
            self.on_soft_limit = false;
        }
    }

    fn compute_backlash(&mut self, period: f64) {
        let n = self.kins_joints;
        for (j, jt) in self.joints.iter_mut().enumerate() {
            if !jt.active || (j >= n && jt.homed) {
                continue;
            }
            jt.backlash_comp(period, self.net_feed_scale);
        }
    }

    /// (4) the motor commands, and the machine-wide outputs derived from
    /// the joints.
    fn motor_commands(&mut self) {
        let n = self.kins_joints;
        let mut v2 = 0.0;
        let mut jogging = false;
        for (j, jt) in self.joints.iter_mut().enumerate() {
            if j >= n && jt.homed {
                // A homed extra joint follows its `posthome-cmd` input.
                jt.motor_pos_cmd = self.joint_inputs[j].posthome_cmd + jt.motor_offset;
            } else {
                jt.motor_pos_cmd = jt.pos_cmd + jt.backlash_filt + jt.motor_offset;
            }
            if jt.active && jt.free_tp.active {
                v2 += jt.vel_cmd * jt.vel_cmd;
            }
            jogging |= jt.kb_jog_active || jt.wheel_jog_active;
        }
        let v2 = v2 + self.teleop_vel_squared();
        self.current_vel = if v2 > 0.0 { v2.sqrt() } else { 0.0 };
        self.jog_is_active = jogging || self.axis_jogging();
    }
}

fn dir_of(vel: f64) -> Direction {
    if vel > 0.0 {
        Direction::Positive
    } else {
        Direction::Negative
    }
}

#[cfg(test)]
mod teleop_tests;
#[cfg(test)]
mod tests;
