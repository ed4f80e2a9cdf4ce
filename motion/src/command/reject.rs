//! Why a command was refused ([`Reject`]), with the values it names
//! ([`Quantity`], [`Feature`], [`Direction`]).

use super::WireError;
use crate::homing::ConfigProblem;

/// What a [`Reject::BadValue`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// The scale.
    Scale,
    /// The minimum limit.
    MinimumLimit,
    /// The maximum limit.
    MaximumLimit,
    /// The velocity limit.
    VelocityLimit,
    /// The acceleration limit.
    AccelerationLimit,
    /// The minimum following error.
    MinimumFerror,
    /// The maximum following error.
    MaximumFerror,
    /// The backlash.
    Backlash,
    /// The motor offset.
    MotorOffset,
    /// The world home coordinate.
    WorldHomeCoordinate,
    /// The jog increment.
    JogIncrement,
    /// The jog position.
    JogPosition,
    /// The jog target.
    JogTarget,
    /// A coordinate of a queued move's end point or arc.
    Coordinate,
    /// The dwell time.
    DwellTime,
    /// The blend tolerance.
    BlendTolerance,
    /// The jerk limit.
    JerkLimit,
    /// A screw-compensation value.
    CompValue,
    /// The planner type.
    PlannerType,
}

impl Quantity {
    /// Every value, in wire-code order.
    pub const ALL: [Quantity; 19] = [
        Quantity::Scale,
        Quantity::MinimumLimit,
        Quantity::MaximumLimit,
        Quantity::VelocityLimit,
        Quantity::AccelerationLimit,
        Quantity::MinimumFerror,
        Quantity::MaximumFerror,
        Quantity::Backlash,
        Quantity::MotorOffset,
        Quantity::WorldHomeCoordinate,
        Quantity::JogIncrement,
        Quantity::JogPosition,
        Quantity::JogTarget,
        Quantity::Coordinate,
        Quantity::DwellTime,
        Quantity::BlendTolerance,
        Quantity::JerkLimit,
        Quantity::CompValue,
        Quantity::PlannerType,
    ];

    /// The text used in messages.
    pub fn text(self) -> &'static str {
        match self {
            Quantity::Scale => "scale",
            Quantity::MinimumLimit => "minimum limit",
            Quantity::MaximumLimit => "maximum limit",
            Quantity::VelocityLimit => "velocity limit",
            Quantity::AccelerationLimit => "acceleration limit",
            Quantity::MinimumFerror => "minimum following error",
            Quantity::MaximumFerror => "maximum following error",
            Quantity::Backlash => "backlash",
            Quantity::MotorOffset => "motor offset",
            Quantity::WorldHomeCoordinate => "world home coordinate",
            Quantity::JogIncrement => "jog increment",
            Quantity::JogPosition => "jog position",
            Quantity::JogTarget => "jog target",
            Quantity::Coordinate => "coordinate",
            Quantity::DwellTime => "dwell time",
            Quantity::BlendTolerance => "blend tolerance",
            Quantity::JerkLimit => "jerk limit",
            Quantity::CompValue => "compensation value",
            Quantity::PlannerType => "planner type",
        }
    }

    /// The code on the wire.
    pub fn code(self) -> u64 {
        self as u64
    }

    /// The value with wire code `code`.
    pub fn from_code(code: u64) -> Option<Quantity> {
        usize::try_from(code)
            .ok()
            .and_then(|i| Self::ALL.get(i))
            .copied()
    }
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.text())
    }
}

/// What a [`Reject::Unsupported`] refuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// A joint's amplifier follows ENABLE/DISABLE and JOINT_ACTIVATE/DEACTIVATE; there is no separate amplifier command.
    AmplifierCommand,
    /// Teleop and coordinated modes need inverse kinematics.
    WorldModeWithoutInverse,
}

impl Feature {
    /// Every value, in wire-code order.
    pub const ALL: [Feature; 2] = [Feature::AmplifierCommand, Feature::WorldModeWithoutInverse];

    /// The text used in messages.
    pub fn text(self) -> &'static str {
        match self {
            Feature::AmplifierCommand => "a joint's amplifier follows ENABLE/DISABLE and JOINT_ACTIVATE/DEACTIVATE; there is no separate amplifier command",
            Feature::WorldModeWithoutInverse => "teleop and coordinated modes need inverse kinematics",
        }
    }

    /// The code on the wire.
    pub fn code(self) -> u64 {
        self as u64
    }

    /// The value with wire code `code`.
    pub fn from_code(code: u64) -> Option<Feature> {
        usize::try_from(code)
            .ok()
            .and_then(|i| Self::ALL.get(i))
            .copied()
    }
}

impl std::fmt::Display for Feature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.text())
    }
}

/// Which way a jog would move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Towards larger positions.
    Positive,
    /// Towards smaller positions.
    Negative,
}

impl std::fmt::Display for Direction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Direction::Positive => "positive",
            Direction::Negative => "negative",
        })
    }
}

/// Why a command was refused. Nothing was changed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reject {
    /// The joint number is outside `0..num_joints`.
    NoSuchJoint {
        /// The joint number.
        joint: i32,
        /// How many joints there are.
        num_joints: usize,
    },
    /// The joint is not active.
    JointInactive {
        /// The joint number.
        joint: usize,
    },
    /// `motion.enable` is false.
    EnableInputFalse,
    /// Motion is not enabled.
    NotEnabled,
    /// Motion is not in free mode.
    NotFreeMode,
    /// `motion.jog-inhibit` is true.
    JogInhibited,
    /// Homing is in progress.
    HomingActive,
    /// A jog wheel is moving this joint.
    WheelJogActive {
        /// The joint number.
        joint: usize,
    },
    /// The joint is moving.
    JointMoving {
        /// The joint number.
        joint: usize,
    },
    /// The joint's hard limit switch in that direction is tripped.
    OnHardLimit {
        /// The joint number.
        joint: usize,
        /// The direction.
        dir: Direction,
    },
    /// The joint is already at or beyond its jog limit in that direction.
    PastSoftLimit {
        /// The joint number.
        joint: usize,
        /// The direction.
        dir: Direction,
    },
    /// The incremental jog would end outside the jog limits.
    TargetOutsideLimits {
        /// The joint number.
        joint: usize,
        /// The target position.
        target: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// A velocity that is zero or not finite.
    BadVelocity {
        /// Velocity (its sign gives a jog's direction).
        vel: f64,
    },
    /// A value that is negative, not finite or otherwise out of range.
    BadValue {
        /// What the value is.
        what: Quantity,
        /// The value.
        value: f64,
    },
    /// A minimum limit above the maximum.
    LimitsReversed {
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// A joint may only be activated while motion is disabled.
    ActivateWhileEnabled {
        /// The joint number.
        joint: usize,
    },
    /// The motion controller did not answer (its thread is not running).
    Timeout,
    /// The command exists but this controller does not carry it out.
    Unsupported {
        /// What the value is.
        what: Feature,
    },
    /// A command read from the shared-memory channel was corrupt or of an
    /// unknown kind; it was not executed.
    Malformed {
        /// What was wrong.
        error: WireError,
    },
    /// `motion.homing-inhibit` is true.
    HomingInhibited,
    /// Home-all found no active joint with a HOME_SEQUENCE of 100 or less.
    NothingToHome,
    /// Home-all sequence numbers must start at 0 or 1 and have no gaps.
    HomeSequenceGap {
        /// The first sequence number missing.
        missing: i32,
    },
    /// The joint is homed and may not be homed again (absolute encoder).
    AlreadyHomed {
        /// The joint number.
        joint: usize,
    },
    /// The joint's shared home switch is closed.
    SharedHomeSwitchClosed {
        /// The joint number.
        joint: usize,
    },
    /// The homing configuration cannot be used.
    BadHomingConfig {
        /// The joint number.
        joint: usize,
        /// What is wrong with it.
        problem: ConfigProblem,
    },
    /// The joint homes in a synchronised group: jogging it alone would
    /// rack the gantry.
    SynchronizedJoint {
        /// The joint number.
        joint: usize,
    },
    /// The joint is a locking indexer; it only moves by homing.
    LockingIndexer {
        /// The joint number.
        joint: usize,
    },
    /// Unhoming needs free mode or motion disabled.
    NotFreeOrDisabled,
    /// An extra joint may only be unhomed while motion is disabled.
    ExtraJointEnabled {
        /// The joint number.
        joint: usize,
    },
    /// A mode change while some planner moves (or homing runs).
    NotInPosition,
    /// Teleop or coordinated mode with non-identity kinematics before
    /// every active joint is homed.
    NotHomed,
    /// An axis jog outside teleop mode.
    NotTeleopMode,
    /// A joint jog in teleop mode.
    JointJogInTeleop,
    /// The axis number is outside `0..9`.
    NoSuchAxis {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: i32,
    },
    /// The kinematics do not compute this axis (not in their coordinates).
    AxisNotInKinematics {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: usize,
    },
    /// The motion error flag is set (e.g. a soft limit was exceeded).
    MotionError,
    /// A jog wheel is moving this axis.
    AxisWheelJogActive {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: usize,
    },
    /// The axis is already beyond its position limit in that direction.
    AxisPastLimit {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: usize,
        /// The direction.
        dir: Direction,
    },
    /// The incremental axis jog would end outside the axis limits.
    AxisTargetOutsideLimits {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: usize,
        /// The target position.
        target: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// The kinematics found no solution for the current joint positions
    /// when entering a world mode.
    KinematicsFailed,
    /// Entering a world mode would step `joint` by `jump` at once: the
    /// joints are not where the kinematics would put them (for example
    /// the two joints of an unsquared gantry).
    ModeChangeJump {
        /// The joint number.
        joint: usize,
        /// How far the joint would step.
        jump: f64,
    },
    /// Moves are only queued in coordinated mode.
    NotCoordMode,
    /// The queue holds as many moves as it can; try again once some ran.
    QueueFull {
        /// How many moves the queue holds.
        capacity: usize,
    },
    /// An abort is bringing the queued motion to a stop; nothing is queued
    /// until it has.
    Aborting,
    /// The move would take `axis` to `value`, outside its limits.
    OutsideAxisLimits {
        /// The world axis: 0..=8 for X Y Z A B C U V W.
        axis: usize,
        /// The value.
        value: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// The move would take `joint` to `value`, outside its soft limits.
    OutsideJointLimits {
        /// The joint number.
        joint: usize,
        /// The value.
        value: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// The kinematics have no solution for the move's end point.
    EndUnreachable,
    /// A hard limit switch of `joint` is tripped: no move is queued.
    HardLimitTripped {
        /// The joint number.
        joint: usize,
    },
    /// The arc's start or end lies on its centre's axis, or its normal is
    /// zero.
    BadArc,
    /// STEP needs the queued motion paused.
    NotPaused,
    /// STEP needs the paused motion at rest.
    StillMoving,
    /// The probe input already shows what the probing move looks for
    /// (tripped for G38.2, clear for G38.4).
    ProbeAlreadyThere {
        /// Whether the move looks for the input clearing (G38.4, G38.5).
        trip_on_clear: bool,
    },
    /// The S-curve planner needs a jerk limit of at least 1.
    NeedsJerkLimit {
        /// Jerk.
        jerk: f64,
    },
    /// Screw-compensation nominals must increase.
    CompNotIncreasing {
        /// The joint number.
        joint: usize,
        /// The nominal (commanded) position.
        nominal: f64,
        /// The nominal before it.
        previous: f64,
    },
    /// A joint's screw-compensation table holds at most 256 entries.
    CompTableFull {
        /// The joint number.
        joint: usize,
    },
    /// This can only be changed while motion is disabled.
    MustBeDisabled,
}

/// The upper-case letter of world axis `axis` (`?` if there is none).
pub fn axis_letter(axis: usize) -> char {
    crate::kins::AXIS_LETTERS
        .get(axis)
        .map_or('?', |l| l.to_ascii_uppercase())
}

impl std::fmt::Display for Reject {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Reject::NoSuchJoint { joint, num_joints } => {
                write!(f, "joint {joint} does not exist (there are {num_joints})")
            }
            Reject::JointInactive { joint } => write!(f, "joint {joint} is not active"),
            Reject::ActivateWhileEnabled { joint } => {
                write!(
                    f,
                    "can't activate joint {joint} while motion is enabled; disable first"
                )
            }
            Reject::EnableInputFalse => f.write_str("can't enable motion, enable input is false"),
            Reject::NotEnabled => f.write_str("motion is not enabled"),
            Reject::NotFreeMode => f.write_str("motion is not in joint (free) mode"),
            Reject::JogInhibited => f.write_str("jogging is inhibited by motion.jog-inhibit"),
            Reject::HomingActive => f.write_str("can't jog while homing is in progress"),
            Reject::WheelJogActive { joint } => {
                write!(f, "joint {joint} is being moved by its jog wheel")
            }
            Reject::JointMoving { joint } => write!(f, "joint {joint} is moving"),
            Reject::OnHardLimit { joint, dir } => {
                write!(
                    f,
                    "can't jog joint {joint} further past its {dir} hard limit"
                )
            }
            Reject::PastSoftLimit { joint, dir } => {
                write!(
                    f,
                    "can't jog joint {joint} further past its {dir} soft limit"
                )
            }
            Reject::TargetOutsideLimits {
                joint,
                target,
                min,
                max,
            } => write!(
                f,
                "jog of joint {joint} to {target} would leave its jog limits [{min}, {max}]"
            ),
            Reject::BadVelocity { vel } => write!(f, "bad jog velocity {vel}"),
            Reject::BadValue { what, value } => write!(f, "bad {what} {value}"),
            Reject::LimitsReversed { min, max } => {
                write!(f, "minimum limit {min} is above maximum limit {max}")
            }
            Reject::Timeout => {
                f.write_str("the motion controller did not answer (is its thread running?)")
            }
            Reject::Unsupported { what } => write!(f, "not supported: {what}"),
            Reject::Malformed { error } => write!(f, "malformed command: {error}"),
            Reject::HomingInhibited => f.write_str("homing is inhibited by motion.homing-inhibit"),
            Reject::NothingToHome => f.write_str(
                "no active joint has a HOME_SEQUENCE for home-all (0 to 100, or -1 to -100)",
            ),
            Reject::HomeSequenceGap { missing } => write!(
                f,
                "home-all sequence numbers must start at 0 or 1 and have no gaps: no joint has sequence {missing}"
            ),
            Reject::AlreadyHomed { joint } => write!(
                f,
                "joint {joint} is homed and must not be homed again (absolute encoder); unhome it first"
            ),
            Reject::SharedHomeSwitchClosed { joint } => {
                write!(f, "can't home joint {joint} while its shared home switch is closed")
            }
            Reject::BadHomingConfig { joint, problem } => {
                write!(f, "homing configuration of joint {joint}: {problem}")
            }
            Reject::SynchronizedJoint { joint } => write!(
                f,
                "can't jog joint {joint} alone: its HOME_SEQUENCE is synchronised (negative)"
            ),
            Reject::LockingIndexer { joint } => {
                write!(f, "can't jog joint {joint}: it is a locking indexer")
            }
            Reject::NotFreeOrDisabled => {
                f.write_str("must be in joint (free) mode or disabled to unhome")
            }
            Reject::ExtraJointEnabled { joint } => {
                write!(f, "extra joint {joint} can only be unhomed while motion is disabled")
            }
            Reject::NotInPosition => f.write_str(
                "motion is not in position (something is moving); stop it before changing mode",
            ),
            Reject::NotHomed => {
                f.write_str("all joints must be homed before going into teleop/coordinated mode")
            }
            Reject::NotTeleopMode => {
                f.write_str("motion is not in teleop mode; axes can only be jogged in teleop mode")
            }
            Reject::JointJogInTeleop => f.write_str(
                "motion is in teleop mode; jog an axis, or switch to free mode to jog a joint",
            ),
            Reject::NoSuchAxis { axis } => write!(
                f,
                "axis {axis} does not exist (axes are 0..8: X Y Z A B C U V W)"
            ),
            Reject::AxisNotInKinematics { axis } => write!(
                f,
                "axis {} is not one of the kinematics' coordinates",
                axis_letter(axis)
            ),
            Reject::MotionError => {
                f.write_str("the motion error flag is set (see the messages); ABORT clears it")
            }
            Reject::AxisWheelJogActive { axis } => write!(
                f,
                "axis {} is being moved by its jog wheel",
                axis_letter(axis)
            ),
            Reject::AxisPastLimit { axis, dir } => write!(
                f,
                "can't jog axis {} further past its {dir} limit",
                axis_letter(axis)
            ),
            Reject::AxisTargetOutsideLimits {
                axis,
                target,
                min,
                max,
            } => write!(
                f,
                "jog of axis {} to {target} would leave its limits [{min}, {max}]",
                axis_letter(axis)
            ),
            Reject::KinematicsFailed => {
                f.write_str("the kinematics have no solution for the current joint positions")
            }
            Reject::ModeChangeJump { joint, jump } => write!(
                f,
                "entering the mode would move joint {joint} by {jump} at once: the joints are \
                 not where the kinematics put them (an unsquared gantry?); align them in free \
                 mode first"
            ),
            Reject::NotCoordMode => {
                f.write_str("motion is not in coordinated mode; moves are only queued there")
            }
            Reject::QueueFull { capacity } => write!(
                f,
                "the motion queue is full ({capacity} moves); try again once some have run"
            ),
            Reject::Aborting => {
                f.write_str("an abort is stopping the queued motion; queue again once it has")
            }
            Reject::OutsideAxisLimits {
                axis,
                value,
                min,
                max,
            } => write!(
                f,
                "the move would take axis {} to {value}, outside its limits [{min}, {max}]",
                axis_letter(axis)
            ),
            Reject::OutsideJointLimits {
                joint,
                value,
                min,
                max,
            } => write!(
                f,
                "the move would take joint {joint} to {value}, outside its limits [{min}, {max}]"
            ),
            Reject::EndUnreachable => {
                f.write_str("the kinematics have no solution for the move's end point")
            }
            Reject::HardLimitTripped { joint } => write!(
                f,
                "joint {joint} is on a hard limit switch; no move is queued until it is off"
            ),
            Reject::BadArc => f.write_str(
                "the arc's start or end lies on its centre's axis, or its normal is zero",
            ),
            Reject::NotPaused => f.write_str("can't STEP while already executing; PAUSE first"),
            Reject::StillMoving => {
                f.write_str("can't STEP while the paused motion is still slowing down")
            }
            Reject::ProbeAlreadyThere {
                trip_on_clear: false,
            } => f.write_str("Probe is already tripped when starting G38.2 or G38.3 move"),
            Reject::ProbeAlreadyThere {
                trip_on_clear: true,
            } => f.write_str("Probe is already clear when starting G38.4 or G38.5 move"),
            Reject::NeedsJerkLimit { jerk } => write!(
                f,
                "the S-curve planner needs MAX_LINEAR_JERK of at least 1 (it is {jerk})"
            ),
            Reject::CompNotIncreasing {
                joint,
                nominal,
                previous,
            } => write!(
                f,
                "joint {joint}: compensation nominal {nominal} does not increase (the last was \
                 {previous})"
            ),
            Reject::CompTableFull { joint } => write!(
                f,
                "joint {joint}: too many compensation entries (at most 256)"
            ),
            Reject::MustBeDisabled => {
                f.write_str("this can only be changed while motion is disabled")
            }
        }
    }
}

impl std::error::Error for Reject {}

/// The result of a command.
pub type CommandResult = Result<(), Reject>;
