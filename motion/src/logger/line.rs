//! One log line per command, in LinuxCNC's motion-logger words where
//! LinuxCNC has the command: its name (`SET_LINE`, `JOINT_HOME`, ...), the
//! same fields in the same order, numbers as C's `%.6g`, and a bare name
//! where LinuxCNC prints one. SET_LINE's `turn` is LinuxCNC's locking
//! indexer joint, which our SET_LINE does not carry (motion knows the
//! indexer from SET_AXIS_LOCKING_JOINT): it shows -1, as LinuxCNC's task
//! sends for every other move. Commands LinuxCNC does not have are named
//! in the same style with all their fields (`name=value, ...`).

use std::fmt::Write as _;

use crate::command::{Command, LineKind};
use crate::kins::Pose;

/// `v` as C's `printf("%.6g")` writes it.
pub fn g6(v: f64) -> String {
    hal_core::cfmt::fmt_g(v, 6)
}

/// `v` as C's `printf("%.2e")` writes it.
pub fn e2(v: f64) -> String {
    if !v.is_finite() {
        return hal_core::cfmt::fmt_f(v);
    }
    let s = format!("{v:.2e}");
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let sign = if exp < 0 { '-' } else { '+' };
    format!("{mantissa}e{sign}{:02}", exp.unsigned_abs())
}

/// `x=.., y=.., ..., w=..` of a pose, in `%.6g`.
fn pose(p: &Pose) -> String {
    let mut s = String::new();
    for (i, (name, v)) in ["x", "y", "z", "a", "b", "c", "u", "v", "w"]
        .iter()
        .zip(p.0.iter())
        .enumerate()
    {
        if i > 0 {
            s.push_str(", ");
        }
        let _ = write!(s, "{name}={}", g6(*v));
    }
    s
}

fn on(b: bool) -> u8 {
    u8::from(b)
}

/// LinuxCNC's motion types: 1 traverse, 2 feed, 3 arc, 5 probing.
fn motion_type(kind: LineKind) -> i32 {
    match kind {
        LineKind::Traverse => 1,
        LineKind::Feed => 2,
    }
}

/// SPINDLE_ON as LinuxCNC's logger writes it: the speed, the constant
/// surface speed factor and the X offset, as C's `%f`.
pub fn spindle_on(speed: f64, css_factor: f64, x_offset: f64) -> String {
    format!("SPINDLE_ON speed={speed:.6}, css_factor={css_factor:.6}, xoffset={x_offset:.6}")
}

/// The log line of `cmd` (without the newline). SPINDLE_ON's shows no
/// surface speed here ([`spindle_on`] takes it from motion's state).
pub fn line(cmd: &Command) -> String {
    use Command as C;
    let g = g6;
    match *cmd {
        C::Abort => "ABORT".into(),
        C::Enable => "ENABLE".into(),
        C::Disable => "DISABLE".into(),
        C::Free => "FREE".into(),
        C::Teleop => "TELEOP".into(),
        C::Coord => "COORD".into(),
        C::JogCont { .. } => "JOG_CONT".into(),
        C::JogIncr { .. } => "JOG_INCR".into(),
        C::JogAbs { .. } => "JOG_ABS".into(),
        C::JogAbort { joint } => format!("JOG_ABORT joint={joint}"),
        C::JointActivate { joint } => format!("JOINT_ACTIVATE joint={joint}"),
        C::JointDeactivate { joint } => format!("JOINT_DEACTIVATE joint={joint}"),
        C::OverrideLimits { .. } => "OVERRIDE_LIMITS".into(),
        C::Scale { scale } => format!("SCALE scale={}", g(scale)),
        // LinuxCNC's logger names the joint of neither.
        C::EnableAmplifier { .. } => "ENABLE_AMPLIFIER".into(),
        C::DisableAmplifier { .. } => "DISABLE_AMPLIFIER".into(),
        C::SetJointPositionLimits { joint, min, max } => format!(
            "SET_JOINT_POSITION_LIMITS joint={joint}, min={}, max={}",
            g(min),
            g(max)
        ),
        C::SetJointVelLimit { joint, vel } => {
            format!("SET_JOINT_VEL_LIMIT joint={joint}, vel={}", g(vel))
        }
        C::SetJointAccLimit { joint, acc } => {
            format!("SET_JOINT_ACC_LIMIT joint={joint}, acc={}", g(acc))
        }
        C::SetJointMinFerror { joint, ferror } => {
            format!("SET_JOINT_MIN_FERROR joint={joint}, minFerror={}", g(ferror))
        }
        C::SetJointMaxFerror { joint, ferror } => {
            format!("SET_JOINT_MAX_FERROR joint={joint}, maxFerror={}", g(ferror))
        }
        C::SetJointBacklash { joint, backlash } => {
            format!("SET_JOINT_BACKLASH joint={joint}, backlash={}", g(backlash))
        }
        C::SetJointMotorOffset { .. } => "SET_JOINT_MOTOR_OFFSET".into(),
        C::SetWorldHome { pose: p } => format!("SET_WORLD_HOME {}", pose(&p)),
        C::SetNumJoints { joints } => format!("SET_NUM_JOINTS {joints}"),
        C::SetNumSpindles { spindles } => format!("SET_NUM_SPINDLES {spindles}"),
        // LinuxCNC's logger writes the offset without the comma after c.
        C::SetToolOffset { offset: p } => {
            let [x, y, z, a, b, c, u, v, w] = p.0.map(g);
            format!("SET_OFFSET x={x}, y={y}, z={z}, a={a}, b={b}, c={c} u={u}, v={v}, w={w}")
        }
        C::Home { joint } => format!("JOINT_HOME joint={joint}"),
        C::Unhome { joint } => format!("JOINT_UNHOME joint={joint}"),
        C::SetJointHomingParams { joint, config: h } => format!(
            "SET_JOINT_HOMING_PARAMS joint={joint}, offset={} home={}, final_vel={}, \
             search_vel={}, latch_vel={}, flags=0x{:08x}, sequence={}, volatile={}",
            g(h.offset),
            g(h.home),
            g(h.final_vel),
            g(h.search_vel),
            g(h.latch_vel),
            h.flags.bits(),
            h.sequence,
            on(h.volatile_home)
        ),
        C::UpdateJointHomingParams {
            joint,
            offset,
            home,
            sequence,
        } => format!(
            "UPDATE_JOINT_HOMING_PARAMS joint={joint}, offset={} home={} home_sequence={sequence}",
            g(offset),
            g(home)
        ),
        C::AxisJogCont { axis, vel } => format!("AXIS_JOG_CONT axis={axis}, vel={}", g(vel)),
        C::AxisJogIncr { axis, vel, offset } => format!(
            "AXIS_JOG_INCR axis={axis}, vel={}, offset={}",
            g(vel),
            g(offset)
        ),
        C::AxisJogAbs { axis, vel, pos } => {
            format!("AXIS_JOG_ABS axis={axis}, vel={}, pos={}", g(vel), g(pos))
        }
        C::AxisJogAbort { axis } => format!("AXIS_JOG_ABORT axis={axis}"),
        C::SetAxisPositionLimits { axis, min, max } => format!(
            "SET_AXIS_POSITION_LIMITS axis={axis}, min={}, max={}",
            g(min),
            g(max)
        ),
        C::SetAxisVelLimit { axis, vel } => format!("SET_AXIS_VEL_LIMIT axis={axis} vel={}", g(vel)),
        C::SetAxisAccLimit { axis, acc } => {
            format!("SET_AXIS_ACC_LIMIT axis={axis}, acc={}", g(acc))
        }
        C::SetAxisEoffsetRatio { axis, ratio } => {
            format!("SET_AXIS_EOFFSET_RATIO axis={axis}, ratio={}", g(ratio))
        }
        C::SetAxisLockingIndexer { axis, joint } => {
            format!("SET_AXIS_LOCKING_JOINT axis={axis}, locking_joint={joint}")
        }
        C::Line {
            end,
            vel,
            ini_maxvel,
            acc,
            kind,
            id,
        } => format!(
            "SET_LINE {}, id={id}, motion_type={}, vel={}, ini_maxvel={}, acc={}, turn=-1",
            pose(&end),
            motion_type(kind),
            g(vel),
            g(ini_maxvel),
            g(acc)
        ),
        C::Circle {
            end,
            center,
            normal,
            turns,
            vel,
            ini_maxvel,
            acc,
            id,
        } => format!(
            "SET_CIRCLE:\n    pos: {}\n    center: x={}, y={}, z={}\n    normal: x={}, y={}, z={}\n    \
             id={id}, motion_type=3, vel={}, ini_maxvel={}, acc={}, turn={turns}",
            pose(&end),
            g(center[0]),
            g(center[1]),
            g(center[2]),
            g(normal[0]),
            g(normal[1]),
            g(normal[2]),
            g(vel),
            g(ini_maxvel),
            g(acc)
        ),
        C::Dwell { seconds, id } => format!("DWELL seconds={}, id={id}", g(seconds)),
        C::Probe { .. } => "PROBE".into(),
        C::ClearProbeFlags => "CLEAR_PROBE_FLAGS".into(),
        C::SetProbeErrInhibit { jog, home } => {
            format!("SETUP_SET_PROBE_ERR_INHIBIT {} {}", on(jog), on(home))
        }
        C::SetTermCond { cond, tolerance } => format!(
            "SET_TERM_COND termCond={}, tolerance={}",
            cond.code(),
            g(tolerance)
        ),
        C::Pause => "PAUSE".into(),
        C::Resume => "RESUME".into(),
        C::Step => "STEP".into(),
        C::FeedScale { .. } => "FEED_SCALE".into(),
        C::RapidScale { .. } => "RAPID_SCALE".into(),
        C::SetMaxFeedOverride { scale } => format!("SET_MAX_FEED_OVERRIDE {}", g(scale)),
        C::FeedScaleEnable { .. } => "FS_ENABLE".into(),
        C::FeedHoldEnable { .. } => "FH_ENABLE".into(),
        C::AdaptiveFeedEnable { .. } => "AF_ENABLE".into(),
        C::SpindleScaleEnable { .. } => "SS_ENABLE".into(),
        C::SetVelLimit { vel } => format!("SET_VEL_LIMIT vel={}", g(vel)),
        C::SetAccLimit { acc } => format!("SET_ACC acc={}", g(acc)),
        C::SetJerkLimit { jerk } => format!("SET_JERK jerk={}", g(jerk)),
        C::SetPlannerType { planner } => format!("SET_PLANNER_TYPE planner_type={planner}"),
        C::SetVel { vel, ini_maxvel } => {
            format!("SET_VEL vel={}, ini_maxvel={}", g(vel), g(ini_maxvel))
        }
        C::SetupArcBlends { .. } => "SETUP_ARC_BLENDS".into(),
        C::SetJointJerkLimit { joint, jerk } => {
            format!("SET_JOINT_JERK_LIMIT joint={joint}, jerk={}", g(jerk))
        }
        C::SetAxisJerkLimit { axis, jerk } => {
            format!("SET_AXIS_JERK_LIMIT axis={axis}, jerk={}", g(jerk))
        }
        C::SetJointComp { .. } => "SET_JOINT_COMP".into(),
        C::ClearJointComp { joint } => format!("CLEAR_JOINT_COMP joint={joint}"),
        C::SpindleOn { speed, .. } => spindle_on(speed, 0.0, 0.0),
        C::SpindleOff { .. } => "SPINDLE_OFF".into(),
        C::SpindleScale { .. } => "SPINDLE_SCALE".into(),
        // LinuxCNC's logger names neither the spindle nor the values.
        C::SetSpindleParams {
            max_pos,
            min_pos,
            max_neg,
            min_neg,
            ..
        } => format!(
            "SET_SPINDLE_PARAMS, {}, {}, {}, {}",
            e2(max_pos),
            e2(min_pos),
            e2(max_neg),
            e2(min_neg)
        ),
        C::SpindleBrake { on: engage, .. } => if engage {
            "SPINDLE_BRAKE_ENGAGE"
        } else {
            "SPINDLE_BRAKE_RELEASE"
        }
        .into(),
        C::SpindleOrient { .. } => "SPINDLE_ORIENT".into(),
        C::SetFeedPerRev { spindle, per_rev } => {
            format!("SET_SPINDLESYNC spindle={spindle}, sync={per_rev:.6}")
        }
        C::RigidTap { .. } => "RIGID_TAP".into(),
        C::SpindleSync {
            per_rev,
            velocity_mode,
            ..
        } => {
            // LinuxCNC's flags: non-zero in velocity mode.
            format!(
                "SET_SPINDLESYNC sync={per_rev:.6}, flags=0x{:08x}",
                u32::from(velocity_mode)
            )
        }
        C::SpindleCss {
            spindle,
            factor,
            x_offset,
        } => format!("SPINDLE_CSS spindle={spindle}, css_factor={factor:.6}, xoffset={x_offset:.6}"),
        C::SetDout { .. } => "SET_DOUT".into(),
        C::SetAout { .. } => "SET_AOUT".into(),
    }
}
