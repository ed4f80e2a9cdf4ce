//! Why a command was refused: every [`Reject`] described once, with its
//! reason code, the detail words its fields travel in, its short name and
//! its text; [`rejects!`] generates the rest (see `reject_macro`).

use super::reject_macro::rejects;
use super::{ConfigProblem, Direction, Feature, Quantity, WireError};

/// The upper-case letter of world axis `axis` (`?` if there is none).
pub fn axis_letter(axis: usize) -> char {
    crate::kins::AXIS_LETTERS
        .get(axis)
        .map_or('?', |l| l.to_ascii_uppercase())
}

/// The result of a command.
pub type CommandResult = Result<(), Reject>;

/// The reason code of a rejection on the wire (never 0, which means
/// accepted).
pub fn reject_code(r: &Reject) -> u64 {
    r.code()
}

rejects! {
    /// Why a command was refused. Nothing was changed.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub enum Reject {
        /// The joint number is outside `0..num_joints`.
        NoSuchJoint {
            /// The joint number.
            joint: i32 = n0,
            /// How many joints there are.
            num_joints: usize = n1,
        } = 1, "no such joint" => "joint {joint} does not exist (there are {num_joints})";
        /// The joint is not active.
        JointInactive {
            /// The joint number.
            joint: usize = n0,
        } = 2, "joint inactive" => "joint {joint} is not active";
        /// `motion.enable` is false.
        EnableInputFalse = 3, "enable input false" => "can't enable motion, enable input is false";
        /// Motion is not enabled.
        NotEnabled = 4, "not enabled" => "motion is not enabled";
        /// Motion is not in free mode.
        NotFreeMode = 5, "not in free mode" => "motion is not in joint (free) mode";
        /// `motion.jog-inhibit` is true.
        JogInhibited = 6, "jog inhibited" => "jogging is inhibited by motion.jog-inhibit";
        /// Homing is in progress.
        HomingActive = 7, "homing active" => "can't jog while homing is in progress";
        /// A jog wheel is moving this joint.
        WheelJogActive {
            /// The joint number.
            joint: usize = n0,
        } = 8, "wheel jog active" => "joint {joint} is being moved by its jog wheel";
        /// The joint is moving.
        JointMoving {
            /// The joint number.
            joint: usize = n0,
        } = 9, "joint moving" => "joint {joint} is moving";
        /// The joint's hard limit switch in that direction is tripped.
        OnHardLimit {
            /// The joint number.
            joint: usize = n0,
            /// The direction.
            dir: Direction = n1,
        } = 10, "on hard limit" => "can't jog joint {joint} further past its {dir} hard limit";
        /// The joint is already at or beyond its jog limit in that direction.
        PastSoftLimit {
            /// The joint number.
            joint: usize = n0,
            /// The direction.
            dir: Direction = n1,
        } = 11, "past soft limit" => "can't jog joint {joint} further past its {dir} soft limit";
        /// The incremental jog would end outside the jog limits.
        TargetOutsideLimits {
            /// The joint number.
            joint: usize = n0,
            /// The target position.
            target: f64 = f0,
            /// Lower limit.
            min: f64 = f1,
            /// Upper limit.
            max: f64 = f2,
        } = 12, "target outside limits"
            => "jog of joint {joint} to {target} would leave its jog limits [{min}, {max}]";
        /// A velocity that is zero or not finite.
        BadVelocity {
            /// Velocity (its sign gives a jog's direction).
            vel: f64 = f0,
        } = 13, "bad velocity" => "bad jog velocity {vel}";
        /// A value that is negative, not finite or otherwise out of range.
        BadValue {
            /// What the value is.
            what: Quantity = n1,
            /// The value.
            value: f64 = f0,
        } = 14, "bad value" => "bad {what} {value}";
        /// A minimum limit above the maximum.
        LimitsReversed {
            /// Lower limit.
            min: f64 = f0,
            /// Upper limit.
            max: f64 = f1,
        } = 15, "limits reversed" => "minimum limit {min} is above maximum limit {max}";
        /// The motion controller did not answer (its thread is not running).
        Timeout = 16, "timeout"
            => "the motion controller did not answer (is its thread running?)";
        /// The command exists but this controller does not carry it out.
        Unsupported {
            /// What the value is.
            what: Feature = n1,
        } = 17, "unsupported" => "not supported: {what}";
        /// A command read from the shared-memory channel was corrupt or of an
        /// unknown kind; it was not executed.
        Malformed {
            /// What was wrong.
            error: WireError = n,
        } = 18, "malformed" => "malformed command: {error}";
        /// A joint may only be activated while motion is disabled.
        ActivateWhileEnabled {
            /// The joint number.
            joint: usize = n0,
        } = 19, "activate while enabled"
            => "can't activate joint {joint} while motion is enabled; disable first";
        /// `motion.homing-inhibit` is true.
        HomingInhibited = 20, "homing inhibited" => "homing is inhibited by motion.homing-inhibit";
        /// Home-all found no active joint with a HOME_SEQUENCE of 100 or less.
        NothingToHome = 21, "nothing to home"
            => "no active joint has a HOME_SEQUENCE for home-all (0 to 100, or -1 to -100)";
        /// Home-all sequence numbers must start at 0 or 1 and have no gaps.
        HomeSequenceGap {
            /// The first sequence number missing.
            missing: i32 = n0,
        } = 22, "home sequence gap"
            => "home-all sequence numbers must start at 0 or 1 and have no gaps: no joint has sequence {missing}";
        /// The joint is homed and may not be homed again (absolute encoder).
        AlreadyHomed {
            /// The joint number.
            joint: usize = n0,
        } = 23, "already homed"
            => "joint {joint} is homed and must not be homed again (absolute encoder); unhome it first";
        /// The joint's shared home switch is closed.
        SharedHomeSwitchClosed {
            /// The joint number.
            joint: usize = n0,
        } = 24, "shared home switch closed"
            => "can't home joint {joint} while its shared home switch is closed";
        /// The homing configuration cannot be used.
        BadHomingConfig {
            /// The joint number.
            joint: usize = n0,
            /// What is wrong with it.
            problem: ConfigProblem = n1,
        } = 25, "bad homing configuration" => "homing configuration of joint {joint}: {problem}";
        /// The joint homes in a synchronised group: jogging it alone would
        /// rack the gantry.
        SynchronizedJoint {
            /// The joint number.
            joint: usize = n0,
        } = 26, "synchronised joint"
            => "can't jog joint {joint} alone: its HOME_SEQUENCE is synchronised (negative)";
        /// The joint is a locking indexer; it only moves by homing.
        LockingIndexer {
            /// The joint number.
            joint: usize = n0,
        } = 27, "locking indexer" => "can't jog joint {joint}: it is a locking indexer";
        /// Unhoming needs free mode or motion disabled.
        NotFreeOrDisabled = 28, "not free or disabled"
            => "must be in joint (free) mode or disabled to unhome";
        /// An extra joint may only be unhomed while motion is disabled.
        ExtraJointEnabled {
            /// The joint number.
            joint: usize = n0,
        } = 29, "extra joint enabled"
            => "extra joint {joint} can only be unhomed while motion is disabled";
        /// A mode change while some planner moves (or homing runs).
        NotInPosition = 30, "not in position"
            => "motion is not in position (something is moving); stop it before changing mode";
        /// Teleop or coordinated mode with non-identity kinematics before
        /// every active joint is homed.
        NotHomed = 31, "not homed"
            => "all joints must be homed before going into teleop/coordinated mode";
        /// An axis jog outside teleop mode.
        NotTeleopMode = 32, "not in teleop mode"
            => "motion is not in teleop mode; axes can only be jogged in teleop mode";
        /// A joint jog in teleop mode.
        JointJogInTeleop = 33, "joint jog in teleop mode"
            => "motion is in teleop mode; jog an axis, or switch to free mode to jog a joint";
        /// The axis number is outside `0..9`.
        NoSuchAxis {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: i32 = n0,
        } = 34, "no such axis" => "axis {axis} does not exist (axes are 0..8: X Y Z A B C U V W)";
        /// The kinematics do not compute this axis (not in their coordinates).
        AxisNotInKinematics {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
        } = 35, "axis not in kinematics"
            => "axis {} is not one of the kinematics' coordinates", axis_letter(axis);
        /// The motion error flag is set (e.g. a soft limit was exceeded).
        MotionError = 36, "motion error"
            => "the motion error flag is set (see the messages); ABORT clears it";
        /// A jog wheel is moving this axis.
        AxisWheelJogActive {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
        } = 37, "axis wheel jog active"
            => "axis {} is being moved by its jog wheel", axis_letter(axis);
        /// The axis is already beyond its position limit in that direction.
        AxisPastLimit {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
            /// The direction.
            dir: Direction = n1,
        } = 38, "axis past limit"
            => "can't jog axis {} further past its {dir} limit", axis_letter(axis);
        /// The incremental axis jog would end outside the axis limits.
        AxisTargetOutsideLimits {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
            /// The target position.
            target: f64 = f0,
            /// Lower limit.
            min: f64 = f1,
            /// Upper limit.
            max: f64 = f2,
        } = 39, "axis target outside limits"
            => "jog of axis {} to {target} would leave its limits [{min}, {max}]", axis_letter(axis);
        /// The kinematics found no solution for the current joint positions
        /// when entering a world mode.
        KinematicsFailed = 40, "kinematics failed"
            => "the kinematics have no solution for the current joint positions";
        /// Entering a world mode would step `joint` by `jump` at once: the
        /// joints are not where the kinematics would put them (for example
        /// the two joints of an unsquared gantry).
        ModeChangeJump {
            /// The joint number.
            joint: usize = n0,
            /// How far the joint would step.
            jump: f64 = f0,
        } = 41, "mode change would jump"
            => "entering the mode would move joint {joint} by {jump} at once: the joints are \
                not where the kinematics put them (an unsquared gantry?); align them in free \
                mode first";
        /// Moves are only queued in coordinated mode.
        NotCoordMode = 42, "not in coordinated mode"
            => "motion is not in coordinated mode; moves are only queued there";
        /// The queue holds as many moves as it can; try again once some ran.
        QueueFull {
            /// How many moves the queue holds.
            capacity: usize = n0,
        } = 43, "queue full"
            => "the motion queue is full ({capacity} moves); try again once some have run";
        /// An abort is bringing the queued motion to a stop; nothing is queued
        /// until it has.
        Aborting = 44, "aborting"
            => "an abort is stopping the queued motion; queue again once it has";
        /// The move would take `axis` to `value`, outside its limits.
        OutsideAxisLimits {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
            /// The value.
            value: f64 = f0,
            /// Lower limit.
            min: f64 = f1,
            /// Upper limit.
            max: f64 = f2,
        } = 45, "outside axis limits"
            => "the move would take axis {} to {value}, outside its limits [{min}, {max}]",
                axis_letter(axis);
        /// The move would take `joint` to `value`, outside its soft limits.
        OutsideJointLimits {
            /// The joint number.
            joint: usize = n0,
            /// The value.
            value: f64 = f0,
            /// Lower limit.
            min: f64 = f1,
            /// Upper limit.
            max: f64 = f2,
        } = 46, "outside joint limits"
            => "the move would take joint {joint} to {value}, outside its limits [{min}, {max}]";
        /// The kinematics have no solution for the move's end point.
        EndUnreachable = 47, "end unreachable"
            => "the kinematics have no solution for the move's end point";
        /// A hard limit switch of `joint` is tripped: no move is queued.
        HardLimitTripped {
            /// The joint number.
            joint: usize = n0,
        } = 48, "hard limit tripped"
            => "joint {joint} is on a hard limit switch; no move is queued until it is off";
        /// The arc's start or end lies on its centre's axis, or its normal is
        /// zero.
        BadArc = 49, "bad arc"
            => "the arc's start or end lies on its centre's axis, or its normal is zero";
        /// STEP needs the queued motion paused.
        NotPaused = 50, "not paused" => "can't STEP while already executing; PAUSE first";
        /// STEP needs the paused motion at rest.
        StillMoving = 51, "still moving"
            => "can't STEP while the paused motion is still slowing down";
        /// The probe input already shows what the probing move looks for
        /// (tripped for G38.2, clear for G38.4).
        ProbeAlreadyThere {
            /// Whether the move looks for the input clearing (G38.4, G38.5).
            trip_on_clear: bool = n0,
        } = 52, "probe already there" => "{}", if trip_on_clear {
            "Probe is already clear when starting G38.4 or G38.5 move"
        } else {
            "Probe is already tripped when starting G38.2 or G38.3 move"
        };
        /// The S-curve planner needs a jerk limit of at least 1.
        NeedsJerkLimit {
            /// Jerk.
            jerk: f64 = f0,
        } = 53, "needs a jerk limit"
            => "the S-curve planner needs MAX_LINEAR_JERK of at least 1 (it is {jerk})";
        /// Screw-compensation nominals must increase.
        CompNotIncreasing {
            /// The joint number.
            joint: usize = n0,
            /// The nominal (commanded) position.
            nominal: f64 = f0,
            /// The nominal before it.
            previous: f64 = f1,
        } = 54, "compensation not increasing"
            => "joint {joint}: compensation nominal {nominal} does not increase (the last was \
                {previous})";
        /// A joint's screw-compensation table holds at most 256 entries.
        CompTableFull {
            /// The joint number.
            joint: usize = n0,
        } = 55, "compensation table full"
            => "joint {joint}: too many compensation entries (at most 256)";
        /// This can only be changed while motion is disabled.
        MustBeDisabled = 56, "must be disabled"
            => "this can only be changed while motion is disabled";
        /// The spindle number is neither −1 nor in `0..num_spindles`.
        NoSuchSpindle {
            /// The spindle number.
            spindle: i32 = n0,
            /// How many spindles there are.
            num_spindles: usize = n1,
        } = 57, "no such spindle" => "spindle {spindle} does not exist (there are {num_spindles})";
        /// The digital or analog output number is outside `0..num_dio`
        /// (`0..num_aio`).
        NoSuchOutput {
            /// The output number.
            index: i32 = n0,
            /// How many there are (motmod's num_dio or num_aio).
            count: usize = n1,
        } = 58, "no such output" => "output {index} does not exist (there are {count})";
        /// A locking indexer needs a joint with `unlock`/`is-unlocked` pins
        /// (motmod's `unlock_joints_mask`).
        NoUnlockPins {
            /// The joint number.
            joint: i32 = n0,
        } = 59, "no unlock pins"
            => "joint {joint} has no unlock pins (add it to motmod's unlock_joints_mask) and \
                cannot be a locking indexer";
        /// A feed move, arc or probing move would move a locking indexer
        /// axis: only a rapid (G0) unlocks it.
        IndexerNeedsRapid {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
        } = 60, "locking indexer needs a rapid"
            => "axis {} is a locking indexer: only a rapid move (G0) may move it, and alone",
                axis_letter(axis);
        /// A rapid would move a locking indexer axis together with other
        /// axes.
        IndexerNotAlone {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
        } = 61, "locking indexer not alone"
            => "axis {} is a locking indexer: a move of it may move no other axis",
                axis_letter(axis);
        /// A locking indexer axis is not jogged in teleop mode (jog its
        /// joint in joint mode, or move it with G0).
        IndexerJog {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            axis: usize = n0,
            /// Its locking indexer joint.
            joint: usize = n1,
        } = 62, "locking indexer jog"
            => "cannot jog axis {}: it is a locking indexer (joint {joint}); move it with G0",
                axis_letter(axis);
        /// A rigid tap needs the position synchronisation on
        /// ([`crate::Command::SpindleSync`] in position mode).
        RigidTapNotSynchronised = 63, "rigid tap not synchronised"
            => "Cannot add unsynchronized rigid tap move";
        /// SET_NUM_JOINTS asked for no joints or for more than motion
        /// was loaded with.
        BadJointCount {
            /// The number asked for.
            count: i32 = n0,
            /// The joints motion was loaded with (motmod's num_joints).
            loaded: usize = n1,
        } = 64, "bad joint count"
            => "{count} joints asked for: motion has 1 to {loaded} (motmod's num_joints)";
        /// SET_NUM_SPINDLES asked for no spindles or for more than motion
        /// was loaded with.
        BadSpindleCount {
            /// The number asked for.
            count: i32 = n0,
            /// The spindles motion was loaded with (motmod's num_spindles).
            loaded: usize = n1,
        } = 65, "bad spindle count"
            => "{count} spindles asked for: motion has 1 to {loaded} (motmod's num_spindles)";
        /// SET_SPINDLE_PARAMS: a speed range whose slow end is beyond its
        /// fast end, or on the wrong side of 0.
        SpindleRangeReversed {
            /// The slow forward (or fast reverse) end.
            low: f64 = f0,
            /// The fast forward (or slow reverse) end.
            high: f64 = f1,
        } = 66, "spindle range reversed"
            => "spindle speed range {low} to {high} is reversed or crosses 0";
    }
}

impl std::error::Error for Reject {}
