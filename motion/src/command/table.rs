//! Every motion command, described once: its fields, the opcode and
//! words it travels in, and its `motion-cmd` command lines. [`commands!`]
//! generates the rest (see `define`).

use super::cli::args::{
    arc_center, arc_normal, arc_turns, arc_words, blend_tolerance, coordinates, end_words, fixed,
    flag, homing_keys, int, num, probe_type, term_cond, world_axis,
};
use super::define::commands;
use super::{LineKind, ProbeType, TermCond};
use crate::kins::Pose;
use crate::vocab::HomingConfig;

commands! {
    /// A command, as LinuxCNC's `EMCMOT_*` commands of the same names.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub enum Command {
        // ---- The machine: enable, modes ----

        /// Stop every free-mode move at its acceleration limit, cancel jogs,
        /// clear the motion and joint error flags and the amp fault flags.
        Abort = 1, cli basic "abort" {};
        /// Request the enabled state (amplifiers on). Needs `motion.enable`.
        Enable = 2, cli basic "enable" {};
        /// Request the disabled state: planners stopped, amplifiers off.
        Disable = 3, cli basic "disable" {};
        /// Request free (joint) mode. Refused while something moves; while
        /// motion is disabled it is remembered and takes effect on enable.
        Free = 4, cli basic "free" {};
        /// Request teleop (world jog) mode: axis jogs through the inverse
        /// kinematics. Refused while something moves and, unless the
        /// kinematics are identity, before every active joint is homed; while
        /// motion is disabled it is remembered and takes effect on enable.
        Teleop = 5, cli basic "teleop" {};
        /// Request coordinated mode, with the same requirements as
        /// [`Command::Teleop`]: the queued moves run in it.
        Coord = 6, cli basic "coord" {};

        // ---- Joints (free mode) ----

        /// Jog `joint` continuously at `vel` (sign = direction) until aborted
        /// or until the jog limit.
        JogCont {
            /// The joint number.
            [slot] joint: i32,
            /// Velocity; its sign gives the direction.
            vel: f64,
        } = 7, cli basic "jog-cont" { joint: int(0, "JOINT"), vel: num(1, "VEL") };
        /// Move `joint` by `offset` (≥ 0) in the direction of `vel`, from the
        /// planner's current target, so increments accumulate.
        JogIncr {
            /// The joint number.
            [slot] joint: i32,
            /// Velocity; its sign gives the direction.
            vel: f64,
            /// How far to move (at least 0).
            offset: f64,
        } = 8, cli basic "jog-incr" {
            joint: int(0, "JOINT"),
            vel: num(1, "VEL"),
            offset: num(2, "DISTANCE"),
        };
        /// Move `joint` to `pos` (clamped into its jog limits) at speed `|vel|`.
        JogAbs {
            /// The joint number.
            [slot] joint: i32,
            /// Velocity; its sign gives the direction.
            vel: f64,
            /// Where to move.
            pos: f64,
        } = 9, cli basic "jog-abs" {
            joint: int(0, "JOINT"),
            vel: num(1, "VEL"),
            pos: num(2, "POSITION"),
        };
        /// Stop the jog of `joint` at its acceleration limit.
        JogAbort {
            /// The joint number.
            [slot] joint: i32,
        } = 10, cli basic "jog-abort" { joint: int(0, "JOINT") };
        /// Make `joint` active: its inputs are read, it is planned and checked.
        JointActivate {
            /// The joint number.
            [slot] joint: i32,
        } = 11, cli basic "activate" { joint: int(0, "JOINT") };
        /// Make `joint` inactive; its amplifier is switched off too.
        JointDeactivate {
            /// The joint number.
            [slot] joint: i32,
        } = 12, cli basic "deactivate" { joint: int(0, "JOINT") };
        /// `joint < 0`: end any limit override. Otherwise override the hard
        /// limits that are tripped now, until the end of the next jog.
        OverrideLimits {
            /// The joint number.
            [slot] joint: i32,
        } = 13, cli basic "override-limits" { joint: int(0, "JOINT") };
        /// The free-mode SCALE: every joint planner's velocity limit is
        /// multiplied by it (clamped to 0..=1). LinuxCNC's FEED_SCALE has no
        /// effect in free mode; here it is the jog override.
        Scale {
            /// The scale, clamped to 0..=1.
            scale: f64,
        } = 14, cli basic "scale" { scale: num(0, "VALUE") };
        /// LinuxCNC's ENABLE_AMPLIFIER, sent by task after ENABLE for each
        /// joint: taken and does nothing, as in LinuxCNC 2.9, because a
        /// joint's amplifier follows ENABLE/DISABLE.
        EnableAmplifier {
            /// The joint number.
            [slot] joint: i32,
        } = 15, cli basic "amp-enable" { joint: int(0, "JOINT") };
        /// LinuxCNC's DISABLE_AMPLIFIER, sent by task before DISABLE for
        /// each joint: taken and does nothing, like
        /// [`Command::EnableAmplifier`].
        DisableAmplifier {
            /// The joint number.
            [slot] joint: i32,
        } = 16, cli basic "amp-disable" { joint: int(0, "JOINT") };

        // ---- Joint configuration ----

        /// Soft limits of `joint`.
        SetJointPositionLimits {
            /// The joint number.
            [slot] joint: i32,
            /// Lower limit.
            min: f64,
            /// Upper limit.
            max: f64,
        } = 17, cli basic "set-limits" {
            joint: int(0, "JOINT"),
            min: num(1, "MIN"),
            max: num(2, "MAX"),
        };
        /// Maximum velocity of `joint` (> 0).
        SetJointVelLimit {
            /// The joint number.
            [slot] joint: i32,
            /// The velocity limit (> 0).
            vel: f64,
        } = 18, cli basic "set-vel-limit" { joint: int(0, "JOINT"), vel: num(1, "VEL") };
        /// Maximum acceleration of `joint` (> 0).
        SetJointAccLimit {
            /// The joint number.
            [slot] joint: i32,
            /// Acceleration.
            acc: f64,
        } = 19, cli basic "set-acc-limit" { joint: int(0, "JOINT"), acc: num(1, "ACC") };
        /// Following-error limit at standstill (≥ 0).
        SetJointMinFerror {
            /// The joint number.
            [slot] joint: i32,
            /// Following error.
            ferror: f64,
        } = 20, cli basic "set-min-ferror" { joint: int(0, "JOINT"), ferror: num(1, "VALUE") };
        /// Following-error limit at the joint's maximum velocity (≥ 0).
        SetJointMaxFerror {
            /// The joint number.
            [slot] joint: i32,
            /// Following error.
            ferror: f64,
        } = 21, cli basic "set-max-ferror" { joint: int(0, "JOINT"), ferror: num(1, "VALUE") };
        /// Backlash of `joint` (≥ 0), taken up at each reversal.
        SetJointBacklash {
            /// The joint number.
            [slot] joint: i32,
            /// Backlash.
            backlash: f64,
        } = 22, cli basic "set-backlash" { joint: int(0, "JOINT"), backlash: num(1, "VALUE") };
        /// Restores the homing offset of `joint` (motor = joint + offset).
        SetJointMotorOffset {
            /// The joint number.
            [slot] joint: i32,
            /// The motor offset (motor position minus joint position).
            offset: f64,
        } = 23, cli basic "set-motor-offset" { joint: int(0, "JOINT"), offset: num(1, "VALUE") };
        /// SET_NUM_JOINTS: the joints the machine uses (`[KINS]JOINTS`),
        /// 1 up to the joints motion was loaded with; the joints above
        /// them are made inactive and refuse activation until a larger
        /// number is set. Only while disabled.
        SetNumJoints {
            /// How many joints.
            joints: i32,
        } = 71, cli basic "set-num-joints" { joints: int(0, "JOINTS") };
        /// SET_NUM_SPINDLES: the spindles the machine uses
        /// (`[TRAJ]SPINDLES`), 1 up to the spindles motion was loaded
        /// with; commands to the spindles above them are refused. Only
        /// while disabled.
        SetNumSpindles {
            /// How many spindles.
            spindles: i32,
        } = 72, cli basic "set-num-spindles" { spindles: int(0, "SPINDLES") };
        /// The world pose used as the first guess of iterative forward
        /// kinematics.
        SetWorldHome {
            /// The world pose.
            pose: Pose,
        } = 24, cli basic "set-world-home" { pose: coordinates(0, "coordinate") };

        // ---- Homing ----

        /// JOINT_HOME: home `joint` (its whole group if its HOME_SEQUENCE is
        /// negative), or with −1 every joint in HOME_SEQUENCE order. Needs
        /// free mode, motion enabled, `motion.homing-inhibit` false and no
        /// homing in progress.
        Home {
            /// The joint number.
            [slot] joint: i32,
        } = 25, cli basic "home" { joint: int(0, "JOINT") };
        /// JOINT_UNHOME: forget the reference of `joint`; −1 every active
        /// joint, −2 the VOLATILE_HOME joints. Needs free mode or disabled,
        /// and the joints standing still and not homing.
        Unhome {
            /// The joint number.
            [slot] joint: i32,
        } = 26, cli basic "unhome" { joint: int(0, "JOINT") };
        /// SET_JOINT_HOMING_PARAMS: the whole homing configuration of `joint`.
        SetJointHomingParams {
            /// The joint number.
            [slot] joint: i32,
            /// The homing configuration.
            config: HomingConfig,
        } = 27, cli basic "set-homing-params" {
            joint: int(0, "JOINT"),
            config: homing_keys(1),
        };
        /// UPDATE_JOINT_HOMING_PARAMS: HOME_OFFSET, HOME and HOME_SEQUENCE
        /// only, allowed at run time (not while homing).
        UpdateJointHomingParams {
            /// The joint number.
            [slot] joint: i32,
            /// HOME_OFFSET.
            offset: f64,
            /// HOME: where the joint goes after homing.
            home: f64,
            /// HOME_SEQUENCE.
            sequence: i32,
        } = 28, cli basic "update-homing-params" {
            joint: int(0, "JOINT"),
            offset: num(1, "OFFSET"),
            home: num(2, "HOME"),
            sequence: int(3, "SEQUENCE"),
        };

        // ---- World axes (teleop mode) ----

        /// Teleop mode: jog world axis `axis` (0..=8, X Y Z A B C U V W)
        /// continuously at `vel` (sign = direction) towards its position limit.
        AxisJogCont {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// Velocity; its sign gives the direction.
            vel: f64,
        } = 29, cli basic "axis-jog-cont" { axis: world_axis(0), vel: num(1, "VEL") };
        /// Teleop mode: move `axis` by `offset` (≥ 0) in the direction of
        /// `vel`, from the planner's current target, so increments accumulate.
        AxisJogIncr {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// Velocity; its sign gives the direction.
            vel: f64,
            /// How far to move (at least 0).
            offset: f64,
        } = 30, cli basic "axis-jog-incr" {
            axis: world_axis(0),
            vel: num(1, "VEL"),
            offset: num(2, "DIST"),
        };
        /// Teleop mode: move `axis` to `pos`, clamped into its position
        /// limits, at speed `|vel|`.
        AxisJogAbs {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// Velocity; its sign gives the direction.
            vel: f64,
            /// Where to move.
            pos: f64,
        } = 31, cli basic "axis-jog-abs" { axis: world_axis(0), vel: num(1, "VEL"), pos: num(2, "POS") };
        /// Stop the jog of `axis` at its acceleration limit.
        AxisJogAbort {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
        } = 32, cli basic "axis-jog-abort" { axis: world_axis(0) };
        /// Position limits of world axis `axis`.
        SetAxisPositionLimits {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// Lower limit.
            min: f64,
            /// Upper limit.
            max: f64,
        } = 33, cli basic "set-axis-limits" {
            axis: world_axis(0),
            min: num(1, "MIN"),
            max: num(2, "MAX"),
        };
        /// Maximum velocity of world axis `axis` (> 0).
        SetAxisVelLimit {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// The velocity limit (> 0).
            vel: f64,
        } = 34, cli basic "set-axis-vel-limit" { axis: world_axis(0), vel: num(1, "VEL") };
        /// Maximum acceleration of world axis `axis` (> 0).
        SetAxisAccLimit {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// Acceleration.
            acc: f64,
        } = 35, cli basic "set-axis-acc-limit" { axis: world_axis(0), acc: num(1, "ACC") };
        /// `[AXIS_L]OFFSET_AV_RATIO` of world axis `axis` (0..=0.9): the
        /// share of its velocity and acceleration limits kept for its
        /// external offset (`axis.L.eoffset-*`); planned moves get the rest.
        /// 0 (the default) leaves the offset pins without effect. Only
        /// while disabled.
        SetAxisEoffsetRatio {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// The ratio.
            ratio: f64,
        } = 69, cli basic "set-axis-eoffset-ratio" { axis: world_axis(0), ratio: num(1, "RATIO") };
        /// `[AXIS_L]LOCKING_INDEXER_JOINT`: world axis `axis` is a locking
        /// indexer driven by `joint` (-1: none, the default). A rapid that
        /// moves the axis, alone, raises `joint.N.unlock`, waits for
        /// `joint.N.is-unlocked`, moves, drops the unlock and waits for
        /// is-unlocked to fall; any other move of the axis is refused. The
        /// joint needs unlock pins (motmod's `unlock_joints_mask`). Only
        /// while disabled.
        SetAxisLockingIndexer {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// The joint, or -1.
            joint: i32,
        } = 70, cli basic "set-axis-locking-indexer" { axis: world_axis(0), joint: int(1, "JOINT") };

        // ---- Queueing and the coordinated planner (coordinated mode) ----

        /// SET_LINE: queue a straight move to `end`. `vel` is the speed
        /// asked for along the path: the feed of a feed move; for a rapid,
        /// the traverse speed task worked out (0: as fast as the limits
        /// allow). `ini_maxvel` and `acc` are the path speed and
        /// acceleration the axes' INI limits allow along this move, as task
        /// works them out (LinuxCNC's SET_LINE fields of those names): the
        /// move never goes faster, not even with the feed override, nor
        /// accelerates harder; 0 leaves motion's own limits alone. `id` is
        /// the motion id reported while it runs (the program line).
        Line {
            /// The end point.
            end: Pose,
            /// Speed asked for along the path, units per second.
            vel: f64,
            /// The largest path speed along this move (0: no cap of its own).
            ini_maxvel: f64,
            /// The largest path acceleration along this move (0: no cap of
            /// its own).
            acc: f64,
            /// What kind of move.
            kind: LineKind,
            /// The motion id reported while it runs (the program line).
            [slot] id: i32,
        } = 36, cli planner "line" {
            end: end_words(2),
            vel: num(1, "VEL"),
            ini_maxvel: fixed(0.0),
            acc: fixed(0.0),
            kind: fixed(LineKind::Feed),
            id: int(0, "ID"),
        }, cli planner "rapid" {
            end: end_words(1),
            vel: fixed(0.0),
            ini_maxvel: fixed(0.0),
            acc: fixed(0.0),
            kind: fixed(LineKind::Traverse),
            id: int(0, "ID"),
        };
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
            /// The largest path speed along this move (0: no cap of its
            /// own), as for [`Command::Line`].
            ini_maxvel: f64,
            /// The largest path acceleration along this move (0: no cap of
            /// its own).
            acc: f64,
            /// The motion id reported while it runs (the program line).
            [slot] id: i32,
        } = 37, cli planner "arc" {
            end: arc_words(2),
            center: arc_center(),
            normal: arc_normal(),
            turns: arc_turns(),
            vel: num(1, "VEL"),
            ini_maxvel: fixed(0.0),
            acc: fixed(0.0),
            id: int(0, "ID"),
        };
        /// Queue a pause of `seconds` (G4) after the moves before it stop.
        Dwell {
            /// How long, in seconds.
            seconds: f64,
            /// The motion id reported while it runs (the program line).
            [slot] id: i32,
        } = 38, cli planner "dwell" { seconds: num(1, "SECONDS"), id: int(0, "ID") };
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
            [slot] id: i32,
        } = 39, cli planner "probe" {
            probe: probe_type(2),
            end: end_words(3),
            vel: num(1, "VEL"),
            id: int(0, "ID"),
        };
        /// CLEAR_PROBE_FLAGS: forget the last probe result.
        ClearProbeFlags = 40, cli planner "clear-probe" {};
        /// SET_PROBE_ERR_INHIBIT (`[TRAJ]NO_PROBE_JOG_ERROR`,
        /// `NO_PROBE_HOME_ERROR`): with `jog`, a probe contact no longer
        /// stops jogs; with `home`, it no longer aborts homing.
        SetProbeErrInhibit {
            /// Jogs go on through a probe contact.
            jog: bool,
            /// Homing goes on through a probe contact.
            home: bool,
        } = 77, cli planner "probe-err-inhibit" {
            jog: flag(0, "the jog inhibit"),
            home: flag(1, "the home inhibit"),
        };
        /// SET_TERM_COND: how the moves queued from now on end; `tolerance`
        /// is the blend tolerance (G64 P) for [`TermCond::Blend`].
        SetTermCond {
            /// The termination condition.
            cond: TermCond,
            /// The blend tolerance (G64 P).
            tolerance: f64,
        } = 41, cli planner "term-cond" { cond: term_cond(0), tolerance: blend_tolerance(1) };
        /// PAUSE: the queued motion slows down along its path at its
        /// acceleration limits and stops; the queue is kept.
        Pause = 42, cli planner "pause" {};
        /// RESUME: continue after a pause (or a single step).
        Resume = 43, cli planner "resume" {};
        /// STEP: while paused and at rest, run to the end of the current motion
        /// id and pause again.
        Step = 44, cli planner "step" {};
        /// FEED_SCALE: the feed override (≥ 0, at most the maximum feed
        /// override in effect).
        FeedScale {
            /// The scale factor.
            scale: f64,
        } = 45, cli planner "feed-scale" { scale: num(0, "SCALE") };
        /// RAPID_SCALE: the rapid override (0..=1).
        RapidScale {
            /// The scale factor.
            scale: f64,
        } = 46, cli planner "rapid-scale" { scale: num(0, "SCALE") };
        /// SET_MAX_FEED_OVERRIDE: the largest feed override and adaptive feed
        /// factor (`[DISPLAY]MAX_FEED_OVERRIDE`, ≥ 0).
        SetMaxFeedOverride {
            /// The scale factor.
            scale: f64,
        } = 47, cli planner "max-feed-override" { scale: num(0, "SCALE") };
        /// FS_ENABLE (M50): whether the overrides apply to moves queued next.
        FeedScaleEnable {
            /// On or off.
            on: bool,
        } = 48, cli planner "feed-scale-enable" { on: flag(0, "the enable") };
        /// FH_ENABLE (M53): whether `motion.feed-hold` applies to moves
        /// queued next.
        FeedHoldEnable {
            /// On or off.
            on: bool,
        } = 49, cli planner "feed-hold-enable" { on: flag(0, "the enable") };
        /// AF_ENABLE (M52): whether `motion.adaptive-feed` applies to moves
        /// queued next.
        AdaptiveFeedEnable {
            /// On or off.
            on: bool,
        } = 50, cli planner "adaptive-feed-enable" { on: flag(0, "the enable") };
        /// SS_ENABLE (M51): the spindle override enable, which also gates
        /// `motion.feed-inhibit` (as LinuxCNC).
        SpindleScaleEnable {
            /// On or off.
            on: bool,
        } = 51, cli planner "spindle-scale-enable" { on: flag(0, "the enable") };
        /// SET_VEL_LIMIT: the tool-tip speed limit of every move that is not
        /// purely rotary (`[TRAJ]MAX_LINEAR_VELOCITY`, > 0).
        SetVelLimit {
            /// The velocity limit (> 0).
            vel: f64,
        } = 52, cli planner "set-traj-vel" { vel: num(0, "VEL") };
        /// SET_ACC: the tangential acceleration limit of every move
        /// (`[TRAJ]MAX_LINEAR_ACCELERATION`, > 0).
        SetAccLimit {
            /// Acceleration.
            acc: f64,
        } = 53, cli planner "set-traj-acc" { acc: num(0, "ACC") };
        /// SET_JERK: the path jerk limit (`[TRAJ]MAX_LINEAR_JERK`, > 0).
        SetJerkLimit {
            /// Jerk.
            jerk: f64,
        } = 54, cli planner "set-traj-jerk" { jerk: num(0, "JERK") };
        /// SET_PLANNER_TYPE: 0 trapezoidal, 1 S-curve (needs a jerk limit of
        /// at least 1). Applied at once when the queue is idle, otherwise as
        /// soon as it is.
        SetPlannerType {
            /// The planner type.
            planner: i32,
        } = 55, cli planner "planner-type" { planner: int(0, "TYPE") };
        /// SET_VEL: the trajectory velocity and the INI velocity task
        /// gives the coordinated planner (LinuxCNC's task sends 0 and
        /// `[TRAJ]DEFAULT_LINEAR_VELOCITY`). The planner keeps both, as
        /// LinuxCNC's does, without limiting any move by them: each queued
        /// move carries its own speed and caps. Both ≥ 0.
        SetVel {
            /// The trajectory velocity.
            vel: f64,
            /// The INI (default) velocity.
            ini_maxvel: f64,
        } = 73, cli planner "set-vel" { vel: num(0, "VEL"), ini_maxvel: num(1, "INI-MAXVEL") };
        /// SETUP_ARC_BLENDS: `[TRAJ]ARC_BLEND_*`. With `enable` off,
        /// blending (G64) runs as exact path (G61) for the moves queued
        /// from now on: no corner is rounded; one the axes can take at
        /// speed is crossed at speed, any other at rest. `fallback`, `depth` (≥ 0), `gap_cycles` (≥ 0) and `ramp_freq`
        /// (≥ 0) are kept for LinuxCNC's planner options; this planner
        /// looks ahead over the whole queue and has no ramp mode.
        SetupArcBlends {
            /// Blend arcs at corners.
            enable: bool,
            /// ARC_BLEND_FALLBACK_ENABLE.
            fallback: bool,
            /// ARC_BLEND_OPTIMIZATION_DEPTH.
            depth: i32,
            /// ARC_BLEND_GAP_CYCLES.
            gap_cycles: i32,
            /// ARC_BLEND_RAMP_FREQ, Hz.
            ramp_freq: f64,
        } = 74, cli planner "arc-blends" {
            enable: flag(0, "the arc blends"),
            fallback: flag(1, "the fallback"),
            depth: int(2, "DEPTH"),
            gap_cycles: int(3, "GAP-CYCLES"),
            ramp_freq: num(4, "RAMP-FREQ"),
        };
        /// SET_OFFSET: the tool length offset in effect (machine units,
        /// nine axes), which motion shows on `motion.tooloffset.L` for
        /// kinematics and HAL logic that follow the tool tip.
        SetToolOffset {
            /// The offset.
            offset: Pose,
        } = 76, cli planner "tool-offset" { offset: coordinates(0, "offset") };
        /// SET_JOINT_JERK_LIMIT: maximum jerk of `joint` (≥ 0; 0 no limit).
        SetJointJerkLimit {
            /// The joint number.
            [slot] joint: i32,
            /// Jerk.
            jerk: f64,
        } = 56, cli planner "set-jerk-limit" { joint: int(0, "JOINT"), jerk: num(1, "JERK") };
        /// SET_AXIS_JERK_LIMIT: maximum jerk of world axis `axis` (≥ 0; 0 no
        /// limit).
        SetAxisJerkLimit {
            /// The world axis: 0..=8 for X Y Z A B C U V W.
            [slot] axis: i32,
            /// Jerk.
            jerk: f64,
        } = 57, cli planner "set-axis-jerk-limit" { axis: world_axis(0), jerk: num(1, "JERK") };
        /// SET_JOINT_COMP: append one entry to `joint`'s screw-error table:
        /// at `nominal`, add `forward` to the command while moving in the
        /// positive direction and `reverse` while moving in the negative one.
        /// Nominals must increase; at most 256 entries. Only while disabled.
        SetJointComp {
            /// The joint number.
            [slot] joint: i32,
            /// The nominal (commanded) position.
            nominal: f64,
            /// Trim while moving in the positive direction.
            forward: f64,
            /// Trim while moving in the negative direction.
            reverse: f64,
        } = 58, cli planner "comp-entry" {
            joint: int(0, "JOINT"),
            nominal: num(1, "NOMINAL"),
            forward: num(2, "FORWARD"),
            reverse: num(3, "REVERSE"),
        };
        /// Empty `joint`'s screw-error table (BACKLASH applies again). Only
        /// while disabled.
        ClearJointComp {
            /// The joint number.
            [slot] joint: i32,
        } = 59, cli planner "clear-comp" { joint: int(0, "JOINT") };

        // ---- Spindles ----

        /// SPINDLE_ON: `spindle` (−1: every spindle) turns at `speed` rpm,
        /// positive forward (M3), negative in reverse (M4), its brake
        /// released. With `wait`, the next feed move waits at rest for
        /// `spindle.N.at-speed`. Needs motion enabled.
        SpindleOn {
            /// The spindle number, or −1 for all.
            [slot] spindle: i32,
            /// Speed in rpm; its sign gives the direction.
            speed: f64,
            /// Whether the next feed move waits for the spindle at speed.
            wait: bool,
        } = 60, cli planner "spindle-on" {
            spindle: int(0, "SPINDLE"),
            speed: num(1, "RPM"),
            wait: flag(2, "the at-speed wait"),
        };
        /// SPINDLE_OFF: `spindle` (−1: every spindle) stops, its brake
        /// applied.
        SpindleOff {
            /// The spindle number, or −1 for all.
            [slot] spindle: i32,
        } = 61, cli planner "spindle-off" { spindle: int(0, "SPINDLE") };
        /// SET_SPINDLE_PARAMS: the speed range of `spindle` (−1: every
        /// spindle), rpm: forward speeds are held within
        /// `min_pos..=max_pos`, reverse speeds within `max_neg..=min_neg`
        /// (`[SPINDLE_n]MAX_FORWARD_VELOCITY`, `MIN_FORWARD_VELOCITY`,
        /// `MAX_REVERSE_VELOCITY` negated, `MIN_REVERSE_VELOCITY`
        /// negated). Needs `0 ≤ min_pos ≤ max_pos` and
        /// `max_neg ≤ min_neg ≤ 0`.
        SetSpindleParams {
            /// The spindle number, or −1 for all.
            [slot] spindle: i32,
            /// The fastest forward speed.
            max_pos: f64,
            /// The slowest forward speed.
            min_pos: f64,
            /// The fastest reverse speed (≤ 0).
            max_neg: f64,
            /// The slowest reverse speed (≤ 0).
            min_neg: f64,
        } = 75, cli planner "spindle-params" {
            spindle: int(0, "SPINDLE"),
            max_pos: num(1, "MAX-FORWARD"),
            min_pos: num(2, "MIN-FORWARD"),
            max_neg: num(3, "MAX-REVERSE"),
            min_neg: num(4, "MIN-REVERSE"),
        };
        /// SPINDLE_SCALE: the spindle override of `spindle` (−1: every
        /// spindle), at least 0; it applies while M51 enables it.
        SpindleScale {
            /// The spindle number, or −1 for all.
            [slot] spindle: i32,
            /// The scale factor.
            scale: f64,
        } = 62, cli planner "spindle-scale" { spindle: int(0, "SPINDLE"), scale: num(1, "SCALE") };
        /// SPINDLE_BRAKE_ENGAGE (`on`; the spindle also stops) and
        /// SPINDLE_BRAKE_RELEASE.
        SpindleBrake {
            /// The spindle number, or −1 for all.
            [slot] spindle: i32,
            /// Engage (true) or release.
            on: bool,
        } = 63, cli planner "spindle-brake" { spindle: int(0, "SPINDLE"), on: flag(1, "the brake") };
        /// SPINDLE_ORIENT (M19): `spindle` stops, its brake released, and
        /// `spindle.N.orient` asks the drive to turn it to `angle` degrees
        /// (`orient-angle`) in `mode` (`orient-mode`: 0 the shorter way,
        /// 1 clockwise, 2 counterclockwise); `is-oriented` completes it
        /// (`locked`, brake on), a non-zero `orient-fault` fails it.
        SpindleOrient {
            /// The spindle number.
            [slot] spindle: i32,
            /// The angle, degrees.
            angle: f64,
            /// The direction mode.
            mode: i32,
        } = 66, cli planner "spindle-orient" {
            spindle: int(0, "SPINDLE"),
            angle: num(1, "DEGREES"),
            mode: int(2, "MODE"),
        };
        /// Feed per revolution (G95; LinuxCNC's SET_SPINDLESYNC in
        /// velocity mode): the feed moves queued after it move `per_rev`
        /// machine units per revolution of `spindle`, their speed following
        /// `spindle.N.speed-in` (revolutions per second) each period; 0
        /// ends it (units per minute again).
        SetFeedPerRev {
            /// The spindle followed.
            [slot] spindle: i32,
            /// Machine units per revolution (0: off).
            per_rev: f64,
        } = 67, cli planner "feed-per-rev" {
            spindle: int(0, "SPINDLE"),
            per_rev: num(1, "UNITS-PER-REV"),
        };
        /// SET_SPINDLESYNC: the feed moves queued after it follow `spindle`,
        /// `per_rev` machine units along their path per revolution; 0 ends
        /// it. In position mode (G33, G76; `velocity_mode` false) each
        /// synchronised run starts at rest: it waits for the spindles at
        /// speed, sets `spindle.N.index-enable`, waits for the encoder to
        /// clear it and then keeps the progress at `spindle.N.revs` (from
        /// the index) times `per_rev`, within the axes' limits; the feed
        /// override, feed hold and pause do not apply to it. In velocity
        /// mode it is [`Command::SetFeedPerRev`].
        SpindleSync {
            /// The spindle followed.
            [slot] spindle: i32,
            /// Machine units per revolution (0: off).
            per_rev: f64,
            /// Follow the spindle's speed (G95) rather than its position.
            velocity_mode: bool,
        } = 78, cli planner "spindle-sync" {
            spindle: int(0, "SPINDLE"),
            per_rev: num(1, "UNITS-PER-REV"),
            velocity_mode: flag(2, "velocity mode"),
        };
        /// RIGID_TAP (G33.1): queue a rigid tap from where the queue ends to
        /// `end`'s X, Y and Z and back, at the position synchronisation in
        /// effect ([`Command::SpindleSync`], refused without it): locked to
        /// the spindle to the depth, where motion multiplies the spindle's
        /// speed by −`scale`; back to the start locked to the reversed
        /// spindle, where it divides the speed by −`scale`; then onto the
        /// start. `vel` is the programmed speed; `id` the motion id.
        RigidTap {
            /// The bottom of the hole (X, Y, Z; the other axes stay).
            end: Pose,
            /// Programmed speed along the path, units per second.
            vel: f64,
            /// The reversal's speed factor (G33.1 I, > 0).
            scale: f64,
            /// The motion id reported while it runs (the program line).
            [slot] id: i32,
        } = 79, cli planner "rigid-tap" {
            end: end_words(3),
            vel: num(1, "VEL"),
            scale: num(2, "SCALE"),
            id: int(0, "ID"),
        };
        /// Constant surface speed (G96): while `spindle` turns, its speed
        /// is `factor / |X - x_offset|` rpm (X the commanded machine
        /// position, `x_offset` where the spindle axis is), at most the
        /// speed of its SPINDLE_ON (the G96 D limit), in that direction;
        /// `factor` 0 ends it (the SPINDLE_ON speed again).
        SpindleCss {
            /// The spindle number, or −1 for all.
            [slot] spindle: i32,
            /// Surface speed over 2π: machine units per minute.
            factor: f64,
            /// The machine X of the spindle axis.
            x_offset: f64,
        } = 68, cli planner "spindle-css" {
            spindle: int(0, "SPINDLE"),
            factor: num(1, "FACTOR"),
            x_offset: num(2, "X-OFFSET"),
        };

        // ---- Digital and analog outputs ----

        /// SET_DOUT: `motion.digital-out-NN` number `index` to `on`, at
        /// once (`now`: M64, M65) or when the next move queued starts
        /// (M62, M63).
        SetDout {
            /// The output number.
            [slot] index: i32,
            /// On or off.
            on: bool,
            /// At once, not with the next move.
            now: bool,
        } = 64, cli planner "dout" {
            index: int(0, "OUTPUT"),
            on: flag(1, "the output"),
            now: flag(2, "now"),
        };
        /// SET_AOUT: `motion.analog-out-NN` number `index` to `value`, at
        /// once (`now`: M68) or when the next move queued starts (M67).
        SetAout {
            /// The output number.
            [slot] index: i32,
            /// The value.
            value: f64,
            /// At once, not with the next move.
            now: bool,
        } = 65, cli planner "aout" {
            index: int(0, "OUTPUT"),
            value: num(1, "VALUE"),
            now: flag(2, "now"),
        };
    }
}
