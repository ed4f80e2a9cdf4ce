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
mod reject;
mod wire_error;

pub use codes::{reject_code, result_name, RejectWire};
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
    /// [`Command::Teleop`]. There is no queued planner yet: the pose is
    /// held.
    Coord,
    /// LinuxCNC's legacy ENABLE_AMPLIFIER: refused, because a joint's
    /// amplifier follows ENABLE/DISABLE and has no side channel
    /// (reference "→ Design").
    EnableAmplifier { joint: i32 },
    /// LinuxCNC's legacy DISABLE_AMPLIFIER: refused like
    /// [`Command::EnableAmplifier`].
    DisableAmplifier { joint: i32 },
    /// Jog `joint` continuously at `vel` (sign = direction) until aborted
    /// or until the jog limit.
    JogCont { joint: i32, vel: f64 },
    /// Move `joint` by `offset` (≥ 0) in the direction of `vel`, from the
    /// planner's current target, so increments accumulate.
    JogIncr { joint: i32, vel: f64, offset: f64 },
    /// Move `joint` to `pos` (clamped into its jog limits) at speed `|vel|`.
    JogAbs { joint: i32, vel: f64, pos: f64 },
    /// Stop the jog of `joint` at its acceleration limit.
    JogAbort { joint: i32 },
    /// Make `joint` active: its inputs are read, it is planned and checked.
    JointActivate { joint: i32 },
    /// Make `joint` inactive; its amplifier is switched off too.
    JointDeactivate { joint: i32 },
    /// `joint < 0`: end any limit override. Otherwise override the hard
    /// limits that are tripped now, until the end of the next jog.
    OverrideLimits { joint: i32 },
    /// The free-mode SCALE: every joint planner's velocity limit is
    /// multiplied by it (clamped to 0..=1). LinuxCNC's FEED_SCALE has no
    /// effect in free mode; here it is the jog override.
    Scale { scale: f64 },
    /// Soft limits of `joint`.
    SetJointPositionLimits { joint: i32, min: f64, max: f64 },
    /// Maximum velocity of `joint` (> 0).
    SetJointVelLimit { joint: i32, vel: f64 },
    /// Maximum acceleration of `joint` (> 0).
    SetJointAccLimit { joint: i32, acc: f64 },
    /// Following-error limit at standstill (≥ 0).
    SetJointMinFerror { joint: i32, ferror: f64 },
    /// Following-error limit at the joint's maximum velocity (≥ 0).
    SetJointMaxFerror { joint: i32, ferror: f64 },
    /// Backlash of `joint` (≥ 0), taken up at each reversal.
    SetJointBacklash { joint: i32, backlash: f64 },
    /// Restores the homing offset of `joint` (motor = joint + offset).
    SetJointMotorOffset { joint: i32, offset: f64 },
    /// The world pose used as the first guess of iterative forward
    /// kinematics.
    SetWorldHome { pose: Pose },
    /// JOINT_HOME: home `joint` (its whole group if its HOME_SEQUENCE is
    /// negative), or with −1 every joint in HOME_SEQUENCE order. Needs
    /// free mode, motion enabled, `motion.homing-inhibit` false and no
    /// homing in progress.
    Home { joint: i32 },
    /// JOINT_UNHOME: forget the reference of `joint`; −1 every active
    /// joint, −2 the VOLATILE_HOME joints. Needs free mode or disabled,
    /// and the joints standing still and not homing.
    Unhome { joint: i32 },
    /// SET_JOINT_HOMING_PARAMS: the whole homing configuration of `joint`.
    SetJointHomingParams { joint: i32, config: HomingConfig },
    /// UPDATE_JOINT_HOMING_PARAMS: HOME_OFFSET, HOME and HOME_SEQUENCE
    /// only, allowed at run time (not while homing).
    UpdateJointHomingParams {
        joint: i32,
        offset: f64,
        home: f64,
        sequence: i32,
    },
    /// Teleop mode: jog world axis `axis` (0..=8, X Y Z A B C U V W)
    /// continuously at `vel` (sign = direction) towards its position limit.
    AxisJogCont { axis: i32, vel: f64 },
    /// Teleop mode: move `axis` by `offset` (≥ 0) in the direction of
    /// `vel`, from the planner's current target, so increments accumulate.
    AxisJogIncr { axis: i32, vel: f64, offset: f64 },
    /// Teleop mode: move `axis` to `pos`, clamped into its position
    /// limits, at speed `|vel|`.
    AxisJogAbs { axis: i32, vel: f64, pos: f64 },
    /// Stop the jog of `axis` at its acceleration limit.
    AxisJogAbort { axis: i32 },
    /// Position limits of world axis `axis`.
    SetAxisPositionLimits { axis: i32, min: f64, max: f64 },
    /// Maximum velocity of world axis `axis` (> 0).
    SetAxisVelLimit { axis: i32, vel: f64 },
    /// Maximum acceleration of world axis `axis` (> 0).
    SetAxisAccLimit { axis: i32, acc: f64 },
}
