//! Commands to the motion controller and their typed results.
//!
//! LinuxCNC answers most refused commands with "OK" and a text message
//! only; here every command is either applied completely or refused with a
//! [`Reject`] that says why, and a refusal changes nothing. Commands and
//! rejections are plain `Copy` data, so the realtime command handler can
//! take and answer them without allocating.

use crate::homing::HomingConfig;
use crate::kins::Pose;

pub mod codes;
mod queueing;
mod reject;
mod wire_error;

pub use codes::{reject_code, result_name, RejectWire};
pub use queueing::{LineKind, ProbeType, TermCond};
pub use reject::{axis_letter, CommandResult, Direction, Feature, Quantity, Reject};
pub use wire_error::WireError;

/// A command, as LinuxCNC's `EMCMOT_*` commands of the same names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Stop every free-mode move at its acceleration limit, cancel jogs,
    /// clear the motion and joint error flags and the amp fault flags.
    Abort,
    /// Request the enabled state (amplifiers on). Needs `motion.enable`.
    Enable,
    /// Request the disabled state: planners stopped, amplifiers off.
    Disable,
    /// Request free (joint) mode. Refused while something moves; while
    /// motion is disabled it is remembered and takes effect on enable.
    Free,
    /// Request teleop (world jog) mode: axis jogs through the inverse
    /// kinematics. Refused while something moves and, unless the
    /// kinematics are identity, before every active joint is homed; while
    /// motion is disabled it is remembered and takes effect on enable.
    Teleop,
    /// Request coordinated mode, with the same requirements as
    /// [`Command::Teleop`]: the queued moves run in it.
    Coord,
    /// LinuxCNC's legacy ENABLE_AMPLIFIER: refused, because a joint's
    /// amplifier follows ENABLE/DISABLE and has no side channel
    /// (reference "→ Design").
    EnableAmplifier {
        /// The joint number.
        joint: i32,
    },
    /// LinuxCNC's legacy DISABLE_AMPLIFIER: refused like
    /// [`Command::EnableAmplifier`].
    DisableAmplifier {
        /// The joint number.
        joint: i32,
    },
    /// Jog `joint` continuously at `vel` (sign = direction) until aborted
    /// or until the jog limit.
    JogCont {
        /// The joint number.
        joint: i32,
        /// Velocity; its sign gives the direction.
        vel: f64,
    },
    /// Move `joint` by `offset` (≥ 0) in the direction of `vel`, from the
    /// planner's current target, so increments accumulate.
    JogIncr {
        /// The joint number.
        joint: i32,
        /// Velocity; its sign gives the direction.
        vel: f64,
        /// How far to move (at least 0).
        offset: f64,
    },
    /// Move `joint` to `pos` (clamped into its jog limits) at speed `|vel|`.
    JogAbs {
        /// The joint number.
        joint: i32,
        /// Velocity; its sign gives the direction.
        vel: f64,
        /// Where to move.
        pos: f64,
    },
    /// Stop the jog of `joint` at its acceleration limit.
    JogAbort {
        /// The joint number.
        joint: i32,
    },
    /// Make `joint` active: its inputs are read, it is planned and checked.
    JointActivate {
        /// The joint number.
        joint: i32,
    },
    /// Make `joint` inactive; its amplifier is switched off too.
    JointDeactivate {
        /// The joint number.
        joint: i32,
    },
    /// `joint < 0`: end any limit override. Otherwise override the hard
    /// limits that are tripped now, until the end of the next jog.
    OverrideLimits {
        /// The joint number.
        joint: i32,
    },
    /// The free-mode SCALE: every joint planner's velocity limit is
    /// multiplied by it (clamped to 0..=1). LinuxCNC's FEED_SCALE has no
    /// effect in free mode; here it is the jog override.
    Scale {
        /// The scale, clamped to 0..=1.
        scale: f64,
    },
    /// Soft limits of `joint`.
    SetJointPositionLimits {
        /// The joint number.
        joint: i32,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// Maximum velocity of `joint` (> 0).
    SetJointVelLimit {
        /// The joint number.
        joint: i32,
        /// The velocity limit (> 0).
        vel: f64,
    },
    /// Maximum acceleration of `joint` (> 0).
    SetJointAccLimit {
        /// The joint number.
        joint: i32,
        /// Acceleration.
        acc: f64,
    },
    /// Following-error limit at standstill (≥ 0).
    SetJointMinFerror {
        /// The joint number.
        joint: i32,
        /// Following error.
        ferror: f64,
    },
    /// Following-error limit at the joint's maximum velocity (≥ 0).
    SetJointMaxFerror {
        /// The joint number.
        joint: i32,
        /// Following error.
        ferror: f64,
    },
    /// Backlash of `joint` (≥ 0), taken up at each reversal.
    SetJointBacklash {
        /// The joint number.
        joint: i32,
        /// Backlash.
        backlash: f64,
    },
    /// Restores the homing offset of `joint` (motor = joint + offset).
    SetJointMotorOffset {
        /// The joint number.
        joint: i32,
        /// The motor offset (motor position minus joint position).
        offset: f64,
    },
    /// The world pose used as the first guess of iterative forward
    /// kinematics.
    SetWorldHome {
        /// The world pose.
        pose: Pose,
    },
    /// JOINT_HOME: home `joint` (its whole group if its HOME_SEQUENCE is
    /// negative), or with −1 every joint in HOME_SEQUENCE order. Needs
    /// free mode, motion enabled, `motion.homing-inhibit` false and no
    /// homing in progress.
    Home {
        /// The joint number.
        joint: i32,
    },
    /// JOINT_UNHOME: forget the reference of `joint`; −1 every active
    /// joint, −2 the VOLATILE_HOME joints. Needs free mode or disabled,
    /// and the joints standing still and not homing.
    Unhome {
        /// The joint number.
        joint: i32,
    },
    /// SET_JOINT_HOMING_PARAMS: the whole homing configuration of `joint`.
    SetJointHomingParams {
        /// The joint number.
        joint: i32,
        /// The homing configuration.
        config: HomingConfig,
    },
    /// UPDATE_JOINT_HOMING_PARAMS: HOME_OFFSET, HOME and HOME_SEQUENCE
    /// only, allowed at run time (not while homing).
    UpdateJointHomingParams {
        /// The joint number.
        joint: i32,
        /// HOME_OFFSET.
        offset: f64,
        /// HOME: where the joint goes after homing.
        home: f64,
        /// HOME_SEQUENCE.
        sequence: i32,
    },
    /// Teleop mode: jog world axis `axis` (0..=8, X Y Z A B C U V W)
    /// continuously at `vel` (sign = direction) towards its position limit.
    AxisJogCont {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// Velocity; its sign gives the direction.
        vel: f64,
    },
    /// Teleop mode: move `axis` by `offset` (≥ 0) in the direction of
    /// `vel`, from the planner's current target, so increments accumulate.
    AxisJogIncr {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// Velocity; its sign gives the direction.
        vel: f64,
        /// How far to move (at least 0).
        offset: f64,
    },
    /// Teleop mode: move `axis` to `pos`, clamped into its position
    /// limits, at speed `|vel|`.
    AxisJogAbs {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// Velocity; its sign gives the direction.
        vel: f64,
        /// Where to move.
        pos: f64,
    },
    /// Stop the jog of `axis` at its acceleration limit.
    AxisJogAbort {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
    },
    /// Position limits of world axis `axis`.
    SetAxisPositionLimits {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// Maximum velocity of world axis `axis` (> 0).
    SetAxisVelLimit {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// The velocity limit (> 0).
        vel: f64,
    },
    /// Maximum acceleration of world axis `axis` (> 0).
    SetAxisAccLimit {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// Acceleration.
        acc: f64,
    },

    // ---- Queueing and the coordinated planner (coordinated mode) ----
    /// SET_LINE: queue a straight move to `end`. `vel` is the programmed
    /// speed along the path (feed moves; ignored for rapids); `id` the
    /// motion id reported while it runs (the program line).
    Line {
        /// The end point.
        end: Pose,
        /// Programmed speed along the path, units per second.
        vel: f64,
        /// What kind of move.
        kind: LineKind,
        /// The motion id reported while it runs (the program line).
        id: i32,
    },
    /// SET_CIRCLE: queue an arc or helix to `end` about the axis through
    /// `center` along `normal`, counter-clockwise about `normal` (right-hand
    /// rule) with `turns` extra full turns; a negative `turns` turns
    /// clockwise with `-1 - turns` extra turns (LinuxCNC's encoding: G2 P n
    /// is `-n`, G3 P n is `n - 1`). The other six axes move in proportion.
    Circle {
        /// The end point.
        end: Pose,
        /// A point on the arc's axis (XYZ).
        center: [f64; 3],
        /// The arc's axis direction (XYZ); it turns counter-clockwise about it.
        normal: [f64; 3],
        /// Extra full turns (negative: clockwise, see above).
        turns: i32,
        /// Programmed speed along the path, units per second.
        vel: f64,
        /// The motion id reported while it runs (the program line).
        id: i32,
    },
    /// Queue a pause of `seconds` (G4) after the moves before it stop.
    Dwell {
        /// How long, in seconds.
        seconds: f64,
        /// The motion id reported while it runs (the program line).
        id: i32,
    },
    /// PROBE: queue a straight probing move (G38.x). Clears the tripped
    /// flag; refused if the input already shows what is sought (unless
    /// `probe.no_error`).
    Probe {
        /// The end point.
        end: Pose,
        /// Programmed speed along the path, units per second.
        vel: f64,
        /// What the probing move looks for.
        probe: ProbeType,
        /// The motion id reported while it runs (the program line).
        id: i32,
    },
    /// CLEAR_PROBE_FLAGS: forget the last probe result.
    ClearProbeFlags,
    /// SET_TERM_COND: how the moves queued from now on end; `tolerance`
    /// is the blend tolerance (G64 P) for [`TermCond::Blend`].
    SetTermCond {
        /// The termination condition.
        cond: TermCond,
        /// The blend tolerance (G64 P).
        tolerance: f64,
    },
    /// PAUSE: the queued motion slows down along its path at its
    /// acceleration limits and stops; the queue is kept.
    Pause,
    /// RESUME: continue after a pause (or a single step).
    Resume,
    /// STEP: while paused and at rest, run to the end of the current motion
    /// id and pause again.
    Step,
    /// FEED_SCALE: the feed override (≥ 0, at most the maximum feed
    /// override in effect).
    FeedScale {
        /// The scale factor.
        scale: f64,
    },
    /// RAPID_SCALE: the rapid override (0..=1).
    RapidScale {
        /// The scale factor.
        scale: f64,
    },
    /// SET_MAX_FEED_OVERRIDE: the largest feed override and adaptive feed
    /// factor (`[DISPLAY]MAX_FEED_OVERRIDE`, ≥ 0).
    SetMaxFeedOverride {
        /// The scale factor.
        scale: f64,
    },
    /// FS_ENABLE (M50): whether the overrides apply to moves queued next.
    FeedScaleEnable {
        /// On or off.
        on: bool,
    },
    /// FH_ENABLE (M53): whether `motion.feed-hold` applies to moves
    /// queued next.
    FeedHoldEnable {
        /// On or off.
        on: bool,
    },
    /// AF_ENABLE (M52): whether `motion.adaptive-feed` applies to moves
    /// queued next.
    AdaptiveFeedEnable {
        /// On or off.
        on: bool,
    },
    /// SS_ENABLE (M51): the spindle override enable, which also gates
    /// `motion.feed-inhibit` (as LinuxCNC).
    SpindleScaleEnable {
        /// On or off.
        on: bool,
    },
    /// SET_VEL_LIMIT: the tool-tip speed limit of every move that is not
    /// purely rotary (`[TRAJ]MAX_LINEAR_VELOCITY`, > 0).
    SetVelLimit {
        /// The velocity limit (> 0).
        vel: f64,
    },
    /// SET_ACC: the tangential acceleration limit of every move
    /// (`[TRAJ]MAX_LINEAR_ACCELERATION`, > 0).
    SetAccLimit {
        /// Acceleration.
        acc: f64,
    },
    /// SET_JERK: the path jerk limit (`[TRAJ]MAX_LINEAR_JERK`, > 0).
    SetJerkLimit {
        /// Jerk.
        jerk: f64,
    },
    /// SET_PLANNER_TYPE: 0 trapezoidal, 1 S-curve (needs a jerk limit of
    /// at least 1). Applied at once when the queue is idle, otherwise as
    /// soon as it is.
    SetPlannerType {
        /// The planner type.
        planner: i32,
    },
    /// SET_JOINT_JERK_LIMIT: maximum jerk of `joint` (≥ 0; 0 no limit).
    SetJointJerkLimit {
        /// The joint number.
        joint: i32,
        /// Jerk.
        jerk: f64,
    },
    /// SET_AXIS_JERK_LIMIT: maximum jerk of world axis `axis` (≥ 0; 0 no
    /// limit).
    SetAxisJerkLimit {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
        /// Jerk.
        jerk: f64,
    },
    /// SET_JOINT_COMP: append one entry to `joint`'s screw-error table:
    /// at `nominal`, add `forward` to the command while moving in the
    /// positive direction and `reverse` while moving in the negative one.
    /// Nominals must increase; at most 256 entries. Only while disabled.
    SetJointComp {
        /// The joint number.
        joint: i32,
        /// The nominal (commanded) position.
        nominal: f64,
        /// Trim while moving in the positive direction.
        forward: f64,
        /// Trim while moving in the negative direction.
        reverse: f64,
    },
    /// Empty `joint`'s screw-error table (BACKLASH applies again). Only
    /// while disabled.
    ClearJointComp {
        /// The joint number.
        joint: i32,
    },
}
