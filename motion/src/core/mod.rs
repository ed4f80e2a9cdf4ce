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
//! Files: this one holds the controller's state and its status
//! accessors; `commands` applies commands, `jog` the joint jogs (keyboard
//! and wheel), `cycle` the servo cycle, `modes` the FREE/TELEOP/COORD
//! requests and the world modes' kinematics, `teleop` the axis jogs and
//! the teleop cycle, `coord` coordinated mode, `eoffset` the external
//! axis offsets. Modes: disabled, free
//! (joint) mode, teleop mode (world axis jogs through the inverse
//! kinematics) and coordinated mode; `modes` and `teleop` document their
//! differences from LinuxCNC; `spindle` the spindles and the spindle
//! synchronisation commands. Deliberate differences from LinuxCNC, each
//! following a "→ Design" note of the reference:
//! * every refused command returns a [`Reject`](crate::command::Reject) and changes nothing, and a
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

use crate::axis::AxisInputs;
use crate::command::ProbeType;
use crate::events::EventRing;
use crate::homing::{HomeState, Homing, HomingConfig};
use crate::joint::{Joint, JointInputs, JointStatus};
use crate::kins::{Kinematics, KinematicsType, KinsFlags, Pose, NUM_AXES};
use crate::tp::{Planner, PlannerStatus};

mod commands;
mod coord;
mod cycle;
mod eoffset;
mod indexer;
mod jog;
mod modes;
mod queue;
mod spindle;
mod teleop;

pub use crate::sizes::{
    FH_ENABLED, FS_ENABLED, MAX_JOINTS, MAX_MISC_ERROR, MAX_SPINDLES, SS_ENABLED,
};
pub use modes::MODE_ENTRY_TOLERANCE;
use modes::{Mode, World};
pub use spindle::{OrientState, Spindle, SpindleOutput};

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
    /// Digital inputs and outputs (`motion.digital-in-NN`, 0..=64).
    pub num_dio: usize,
    /// Analog inputs and outputs (`motion.analog-in-NN`, 0..=64).
    pub num_aio: usize,
    /// Joints with `unlock`/`is-unlocked` pins (bit n: joint n), the only
    /// ones that may be locking indexers.
    pub unlock_joints_mask: u32,
    /// The servo period the coordinated planner plans for, in ns.
    pub servo_period_nsec: u64,
}

impl Default for MotionConfig {
    fn default() -> Self {
        MotionConfig {
            num_joints: 3,
            num_extrajoints: 0,
            num_spindles: 1,
            num_misc_error: 0,
            num_dio: 4,
            num_aio: 4,
            unlock_joints_mask: 0,
            servo_period_nsec: 1_000_000,
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
    /// `spindle.N.at-speed` (default true).
    pub spindle_at_speed: [bool; MAX_SPINDLES],
    /// `spindle.N.inhibit`.
    pub spindle_inhibit: [bool; MAX_SPINDLES],
    /// `spindle.N.speed-in`: the measured speed, revolutions per second.
    pub spindle_speed_in: [f64; MAX_SPINDLES],
    /// `spindle.N.revs`: the measured position, revolutions.
    pub spindle_revs: [f64; MAX_SPINDLES],
    /// `spindle.N.index-enable` as read back (the encoder clears it at
    /// the index).
    pub spindle_index_enable: [bool; MAX_SPINDLES],
    /// `spindle.N.is-oriented`: the drive reached the M19 angle.
    pub spindle_is_oriented: [bool; MAX_SPINDLES],
    /// `spindle.N.orient-fault`: non-zero fails an M19.
    pub spindle_orient_fault: [i32; MAX_SPINDLES],
    /// `motion.digital-in-NN` (M66 P).
    pub din: [bool; crate::sizes::MAX_IO],
    /// `motion.analog-in-NN` (M66 E).
    pub ain: [f64; crate::sizes::MAX_IO],
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
            spindle_at_speed: [true; MAX_SPINDLES],
            spindle_inhibit: [false; MAX_SPINDLES],
            spindle_speed_in: [0.0; MAX_SPINDLES],
            spindle_revs: [0.0; MAX_SPINDLES],
            spindle_index_enable: [false; MAX_SPINDLES],
            spindle_is_oriented: [false; MAX_SPINDLES],
            spindle_orient_fault: [0; MAX_SPINDLES],
            din: [false; crate::sizes::MAX_IO],
            ain: [0.0; crate::sizes::MAX_IO],
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
    /// Coordinated mode: the queued trajectory planner makes the pose,
    /// the inverse kinematics move the joints.
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
    /// The coordinated planner.
    tp: Planner,
    /// Feed override (FEED_SCALE), rapid override (RAPID_SCALE) and the
    /// largest feed override allowed.
    feed_scale: f64,
    rapid_scale: f64,
    max_feed_override: f64,
    /// Probing (G38.x) state.
    probe: ProbeState,
    /// The spindles as commanded.
    spindles: [Spindle; MAX_SPINDLES],
    /// The next feed move waits for the spindles at speed.
    atspeed_next_feed: bool,
    /// Each world axis's locking indexer joint (`LOCKING_INDEXER_JOINT`).
    indexer_joint: [Option<u8>; NUM_AXES],
    /// The joints commands may name (SET_NUM_JOINTS; all at first).
    joints_in_use: usize,
    /// The spindles commands may name (SET_NUM_SPINDLES; all at first).
    spindles_in_use: usize,
    /// The tool offset (SET_OFFSET), shown on `motion.tooloffset.L`.
    tool_offset: Pose,
    /// SET_PROBE_ERR_INHIBIT: a probe contact stops no jog, aborts no
    /// homing.
    probe_err_inhibit: (bool, bool),
}

/// Where probing stands.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct ProbeState {
    /// A probing move is executing.
    pub probing: bool,
    /// What it looks for.
    pub kind: ProbeType,
    /// Its motion id.
    pub id: i32,
    /// The last probing move found what it looked for.
    pub tripped: bool,
    /// Where (the feedback pose when the input changed, or where the move
    /// ended without it).
    pub pos: Pose,
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

/// A servo period in seconds (1 ms if zero).
fn period_secs(nsec: u64) -> f64 {
    if nsec == 0 {
        0.001
    } else {
        nsec as f64 * 1e-9
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
        cfg.num_dio = cfg.num_dio.min(crate::sizes::MAX_IO);
        cfg.num_aio = cfg.num_aio.min(crate::sizes::MAX_IO);
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
            tp: Planner::new(period_secs(cfg.servo_period_nsec)),
            feed_scale: 1.0,
            rapid_scale: 1.0,
            max_feed_override: 1.0,
            probe: ProbeState::default(),
            spindles: [Spindle::default(); MAX_SPINDLES],
            atspeed_next_feed: false,
            indexer_joint: [None; NUM_AXES],
            joints_in_use: cfg.num_joints,
            spindles_in_use: cfg.num_spindles,
            tool_offset: Pose::ZERO,
            probe_err_inhibit: (false, false),
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

    /// Joint `j`'s `unlock` output (locking indexers: homing, or the
    /// planner around an indexer's rapid); false while disabled.
    pub fn unlock_output(&self, j: usize) -> bool {
        self.enabled && (self.homing.joints[j].unlock || self.tp.indexer_unlock() == Some(j))
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

    /// The override enable bits the next queued move takes (M48 to M53:
    /// `SS_ENABLED`, `FS_ENABLED`, `AF_ENABLED`, `FH_ENABLED`).
    pub fn enables(&self) -> u8 {
        self.enables_new
    }

    pub(crate) fn joint_ref(&self, j: usize) -> &Joint {
        &self.joints[j]
    }

    /// The coordinated planner's status.
    pub fn planner(&self) -> PlannerStatus {
        self.tp.status()
    }

    /// The planner's commanded pose.
    pub fn planner_pos(&self) -> Pose {
        self.tp.pos()
    }

    /// Where the last queued move ends: the next one starts there.
    pub fn planner_goal(&self) -> Pose {
        self.tp.goal()
    }

    /// Feed override, rapid override and the largest feed override.
    pub fn overrides(&self) -> (f64, f64, f64) {
        (self.feed_scale, self.rapid_scale, self.max_feed_override)
    }

    /// The digital and analog outputs (M62 to M68).
    pub fn io_outputs(&self) -> &crate::tp::IoOutputs {
        self.tp.io_outputs()
    }

    /// Whether a probing move is executing.
    pub fn probing(&self) -> bool {
        self.probe.probing
    }

    /// Whether the last probing move found what it looked for, and where.
    pub fn probe_result(&self) -> (bool, Pose) {
        (self.probe.tripped, self.probe.pos)
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

    /// Marks joint `j` homed or not, as the homing state machine will
    /// (tests; the motion-logger stand-in, which homes at once).
    pub(crate) fn set_homed(&mut self, j: usize, homed: bool) {
        self.joints[j].homed = homed;
    }
}

#[cfg(test)]
mod coord_tests;
#[cfg(test)]
mod eoffset_tests;
#[cfg(test)]
mod indexer_tests;
#[cfg(test)]
mod io_tests;
#[cfg(test)]
mod setup_tests;
#[cfg(test)]
mod spindle_tests;
#[cfg(test)]
mod teleop_tests;
#[cfg(test)]
mod tests;
