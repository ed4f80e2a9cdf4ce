//! `task-cmd stat`: the machine's state as one snapshot for programs (the
//! Python `linuxcnc.stat`), in LinuxCNC's names and numbers. Each line is
//! `NAME=KIND:VALUE`, KIND one of `i` (an integer), `f` (a number), `s`
//! (a text), `I` and `F` (integers or numbers separated by spaces). A
//! record of a list is `LIST.INDEX.FIELD`. The names come from the tables
//! below only; a reader takes whatever names arrive, so a value task
//! cannot supply is absent rather than made up.

use std::fmt::Write as _;

use motion::MotionStatus;

use crate::error::LaunchError;
use crate::program::{ProgramView, RunState};
use crate::task::{MachineState, Mode, Task, TaskRequest};

/// The machine's settings the snapshot reports, from the INI file.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct TrajInfo {
    /// Machine units per millimetre (`[TRAJ]LINEAR_UNITS`).
    pub linear_units: f64,
    /// Machine units per degree (`[TRAJ]ANGULAR_UNITS`).
    pub angular_units: f64,
    /// The servo period in seconds (`[EMCMOT]SERVO_PERIOD`).
    pub cycle_time: f64,
    /// `[TRAJ]DEFAULT_LINEAR_VELOCITY`, per second.
    pub velocity: f64,
    /// `[TRAJ]DEFAULT_LINEAR_ACCELERATION`.
    pub acceleration: f64,
    /// `[TRAJ]MAX_LINEAR_ACCELERATION`.
    pub max_acceleration: f64,
}

impl TrajInfo {
    /// The settings of `ini`, with LinuxCNC's defaults.
    pub(crate) fn from_ini(ini: &hal_lang::ini::Ini) -> Result<TrajInfo, LaunchError> {
        let traj = crate::config::TrajSettings::from_ini(ini)?;
        let angular = ini.get("TRAJ", "ANGULAR_UNITS").unwrap_or("degree").trim();
        let angular_units = match angular {
            "deg" | "degree" | "degrees" => 1.0,
            "rad" | "radian" | "radians" => std::f64::consts::PI / 180.0,
            "grad" | "gon" => 400.0 / 360.0,
            other => other
                .parse::<f64>()
                .ok()
                .filter(|v| *v > 0.0)
                .unwrap_or(1.0),
        };
        let servo_ns = ini.real("EMCMOT", "SERVO_PERIOD")?.unwrap_or(1_000_000.0);
        Ok(TrajInfo {
            linear_units: crate::program::ProgramConfig::from_ini(ini).user_per_mm,
            angular_units,
            cycle_time: servo_ns * 1e-9,
            velocity: traj.default_velocity,
            acceleration: traj.default_acceleration,
            max_acceleration: traj.max_acceleration,
        })
    }
}

/// One value of the snapshot.
pub(crate) enum Value {
    /// An integer.
    Int(i64),
    /// A number.
    Float(f64),
    /// A text (control characters, newlines among them, become spaces).
    Text(String),
    /// Integers.
    Ints(Vec<i64>),
    /// Numbers.
    Floats(Vec<f64>),
}

/// What the fields read from: task, motion's snapshot, the program side.
pub(crate) struct Ctx<'a> {
    task: &'a Task,
    motion: Option<&'a MotionStatus>,
    program: Option<ProgramView<'a>>,
}

/// A field: its name, and its value when task can supply it.
type Field = (&'static str, fn(&Ctx) -> Option<Value>);

/// A field of a part (motion's snapshot, a joint, an axis, a spindle).
type Of<T> = (&'static str, fn(&T) -> Value);

/// A field of a tool table slot.
type ToolField = (
    &'static str,
    fn(Option<&crate::iocontrol::tooltable::Tool>) -> Value,
);

/// LinuxCNC's number of joints in its status lists.
const MAX_JOINTS: usize = 16;

fn bit(b: bool) -> Value {
    Value::Int(i64::from(b))
}

fn floats(v: impl IntoIterator<Item = f64>) -> Value {
    Value::Floats(v.into_iter().collect())
}

/// Joint values padded to LinuxCNC's sixteen.
fn per_joint(m: &MotionStatus, f: impl Fn(&motion::channel::JointState) -> f64) -> Value {
    let mut v: Vec<f64> = m.joints.iter().map(f).collect();
    v.resize(MAX_JOINTS.max(v.len()), 0.0);
    Value::Floats(v)
}

fn offset(c: &Ctx, which: usize) -> Option<Value> {
    let p = c.task.program.as_ref()?;
    Some(floats(p.offsets()[which]))
}

/// G54 ... G59.3 as LinuxCNC's index 1 ... 9.
fn g5x_index(p: &ProgramView) -> Option<i64> {
    const CODES: [i32; 9] = [540, 550, 560, 570, 580, 590, 591, 592, 593];
    p.codes
        .g
        .iter()
        .find_map(|g| CODES.iter().position(|c| c == g))
        .map(|i| i as i64 + 1)
}

/// Where each of the interpreter's modal G-codes (in
/// [`rs274ngc::ActiveCodes`]'s order: motion, plane, distance, IJK
/// distance, feed mode, units, cutter compensation, tool length,
/// coordinate system, control mode, retract mode, spindle mode, lathe
/// mode) goes in LinuxCNC's 17 (0: the line; 2, 12, 16: not kept here).
const GCODE_SLOTS: [usize; 13] = [1, 3, 6, 14, 7, 5, 4, 9, 8, 11, 10, 13, 15];

/// The active G-codes in LinuxCNC's layout, -1 where there is none.
fn linuxcnc_gcodes(p: &ProgramView) -> Vec<i64> {
    let mut v = vec![-1i64; 17];
    v[0] = p.read_line.into();
    for (code, slot) in p.codes.g.iter().zip(GCODE_SLOTS) {
        v[slot] = (*code).into();
    }
    v
}

/// LinuxCNC's interpreter settings: the line read, the feed rate, the
/// spindle speed, the blend tolerance (G64 P) and the naive-CAM
/// tolerance (G64 Q).
fn linuxcnc_settings(p: &ProgramView) -> [f64; 5] {
    [
        f64::from(p.read_line),
        p.codes.feed,
        p.codes.speed,
        p.codes.tolerance,
        p.codes.naivecam_tolerance,
    ]
}

/// The active M-codes in LinuxCNC's layout of 10: the line, stopping
/// (none between blocks), spindle, tool change (none), mist (9 when no
/// coolant runs, -1 when only flood does), flood, overrides.
fn linuxcnc_mcodes(p: &ProgramView) -> Vec<i64> {
    let m = &p.codes.m;
    let has = |code: i32| m.contains(&code);
    let mut v = vec![-1i64; 10];
    v[0] = p.read_line.into();
    v[2] = m.first().map_or(-1, |c| (*c).into());
    v[4] = if has(7) {
        7
    } else if has(8) {
        -1
    } else {
        9
    };
    v[5] = if has(8) { 8 } else { -1 };
    v[6] = m
        .iter()
        .find(|c| (48..=51).contains(*c))
        .map_or(-1, |c| (*c).into());
    v
}

/// LinuxCNC's interpreter state: IDLE 1, READING 2, PAUSED 3.
fn interp_state(c: &Ctx) -> Option<Value> {
    let p = c.task.program.as_ref()?;
    Some(Value::Int(match p.run_state() {
        RunState::Idle if p.settled() => 1,
        RunState::Idle | RunState::Running => 2,
        RunState::Paused | RunState::Held => 3,
    }))
}

/// LinuxCNC's execution state: DONE 2, or WAITING_FOR_MOTION 3 while
/// motion has moves queued or is not at rest.
fn exec_state(c: &Ctx) -> Option<Value> {
    let m = c.motion?;
    let moving = m.traj.depth > 0 || !m.in_position;
    Some(Value::Int(if moving { 3 } else { 2 }))
}

/// The task-level fields.
const FIELDS: &[Field] = &[
    ("task_state", |c| {
        // LinuxCNC reports a machine that is off as ESTOP_RESET.
        Some(Value::Int(match c.task.state {
            MachineState::Estop => 1,
            MachineState::Off => 2,
            MachineState::On => 4,
        }))
    }),
    ("task_mode", |c| {
        Some(Value::Int(match c.task.mode {
            Mode::Manual => 1,
            Mode::Auto => 2,
            Mode::Mdi => 3,
        }))
    }),
    ("estop", |c| Some(bit(c.task.state == MachineState::Estop))),
    ("interp_state", interp_state),
    ("exec_state", exec_state),
    ("task_paused", |c| {
        let p = c.task.program.as_ref()?;
        Some(bit(matches!(
            p.run_state(),
            RunState::Paused | RunState::Held
        )))
    }),
    ("file", |c| {
        let f = c.program.as_ref()?.file;
        Some(Value::Text(
            f.map_or(String::new(), |f| f.display().to_string()),
        ))
    }),
    ("read_line", |c| {
        Some(Value::Int(c.program.as_ref()?.read_line.into()))
    }),
    ("gcodes", |c| {
        let p = c.program.as_ref()?;
        Some(Value::Ints(linuxcnc_gcodes(p)))
    }),
    ("mcodes", |c| {
        let p = c.program.as_ref()?;
        Some(Value::Ints(linuxcnc_mcodes(p)))
    }),
    ("settings", |c| {
        Some(floats(linuxcnc_settings(c.program.as_ref()?)))
    }),
    ("program_units", |c| {
        // LinuxCNC: 1 inch (G20), 2 mm (G21).
        let g = &c.program.as_ref()?.codes.g;
        Some(Value::Int(if g.contains(&200) { 1 } else { 2 }))
    }),
    ("g5x_index", |c| {
        g5x_index(c.program.as_ref()?).map(Value::Int)
    }),
    ("g5x_offset", |c| offset(c, 0)),
    ("g92_offset", |c| offset(c, 1)),
    ("tool_offset", |c| offset(c, 2)),
    ("tool_in_spindle", |c| {
        Some(Value::Int(c.task.io.tool_in_spindle().into()))
    }),
    ("pocket_prepped", |c| {
        // The table slot prepared, -1 for none, as LinuxCNC's.
        Some(Value::Int(
            c.task.io.prepped_slot().map_or(-1, |s| s as i64),
        ))
    }),
    ("tool_from_pocket", |c| {
        Some(Value::Int(c.task.io.outputs().tool_from_pocket.into()))
    }),
    ("mist", |c| Some(bit(c.task.io.outputs().coolant_mist))),
    ("flood", |c| Some(bit(c.task.io.outputs().coolant_flood))),
    ("lube", |c| Some(bit(c.task.io.outputs().lube))),
    ("lube_level", |c| Some(bit(c.task.pins.inputs().lube_level))),
    ("queued_mdi_commands", |c| {
        Some(Value::Int(c.program.as_ref()?.queued_mdi as i64))
    }),
    ("feedrate", |c| Some(Value::Float(c.task.overrides.feed))),
    ("rapidrate", |c| Some(Value::Float(c.task.overrides.rapid))),
    ("max_velocity", |c| {
        Some(Value::Float(c.task.overrides.max_velocity))
    }),
    ("linear_units", |c| {
        Some(Value::Float(c.task.traj_info.linear_units))
    }),
    ("angular_units", |c| {
        Some(Value::Float(c.task.traj_info.angular_units))
    }),
    ("cycle_time", |c| {
        Some(Value::Float(c.task.traj_info.cycle_time))
    }),
    ("velocity", |c| {
        Some(Value::Float(c.task.traj_info.velocity))
    }),
    ("acceleration", |c| {
        Some(Value::Float(c.task.traj_info.acceleration))
    }),
    ("max_acceleration", |c| {
        Some(Value::Float(c.task.traj_info.max_acceleration))
    }),
    ("optional_stop", |c| {
        Some(bit(c.task.switches.optional_stop))
    }),
    ("block_delete", |c| Some(bit(c.task.switches.block_delete))),
    ("call_level", |c| {
        Some(Value::Int(c.program.as_ref()?.call_level as i64))
    }),
    ("rotation_xy", |c| {
        Some(Value::Float(c.program.as_ref()?.rotation_xy))
    }),
    ("interpreter_errcode", |c| {
        Some(Value::Int(c.program.as_ref()?.interpreter_errcode.into()))
    }),
    ("dtg", |c| Some(floats(c.motion?.traj.dtg))),
    ("kinematics_type", |c| {
        Some(Value::Int(c.motion?.traj.kinematics_type?.into()))
    }),
    ("feed_override_enabled", |c| {
        enabled(c, motion::sizes::FS_ENABLED)
    }),
    ("adaptive_feed_enabled", |c| {
        enabled(c, motion::sizes::AF_ENABLED)
    }),
    ("feed_hold_enabled", |c| {
        enabled(c, motion::sizes::FH_ENABLED)
    }),
];

/// Whether motion's override enable `bit` (M48 to M53) is set for the
/// next move.
fn enabled(c: &Ctx, bit_mask: u8) -> Option<Value> {
    Some(bit(c.motion?.traj.enables? & bit_mask != 0))
}

/// The fields motion's snapshot supplies.
const MOTION_FIELDS: &[Of<MotionStatus>] = &[
    ("enabled", |m| bit(m.enabled)),
    ("inpos", |m| bit(m.in_position)),
    ("motion_mode", |m| {
        // LinuxCNC's TRAJ_MODE_FREE 1, COORD 2, TELEOP 3.
        Value::Int(match m.mode {
            "COORD" => 2,
            "TELEOP" => 3,
            _ => 1,
        })
    }),
    ("homed", |m| {
        let mut v: Vec<i64> = m.joints.iter().map(|j| i64::from(j.homed)).collect();
        v.resize(MAX_JOINTS.max(v.len()), 0);
        Value::Ints(v)
    }),
    // Per joint, LinuxCNC's limit mask: 1 the negative limit switch, 2
    // the positive one, 4 below the soft limit, 8 above it.
    ("limit", |m| {
        let mut v: Vec<i64> = m.joints.iter().map(limit_mask).collect();
        v.resize(MAX_JOINTS.max(v.len()), 0);
        Value::Ints(v)
    }),
    // LinuxCNC's joint override_limits: an override is in effect.
    ("override_limits", |m| bit(m.override_mask != 0)),
    ("joints", |m| {
        Value::Int(m.joints.iter().filter(|j| j.active).count() as i64)
    }),
    ("axis_mask", |m| {
        let mask = m
            .axes
            .iter()
            .enumerate()
            .filter(|(_, a)| a.in_kinematics)
            .fold(0i64, |acc, (i, _)| acc | (1 << i));
        Value::Int(mask)
    }),
    ("position", |m| floats(m.axes.iter().map(|a| a.pos_cmd))),
    ("actual_position", |m| floats(m.traj.pos_fb)),
    ("joint_position", |m| per_joint(m, |j| j.pos_cmd)),
    ("joint_actual_position", |m| per_joint(m, |j| j.pos_fb)),
    ("probed_position", |m| floats(m.traj.probed)),
    ("probe_tripped", |m| bit(m.traj.probe_tripped)),
    ("probe_val", |m| bit(m.traj.probe_input)),
    ("probing", |m| bit(m.traj.probing)),
    ("motion_line", |m| Value::Int(m.traj.exec_id.into())),
    // The line executing: motion's, as LinuxCNC reports it.
    ("current_line", |m| Value::Int(m.traj.exec_id.into())),
    ("queue", |m| Value::Int(m.traj.depth as i64)),
    ("queue_full", |m| bit(m.traj.queue_full)),
    ("paused", |m| bit(m.traj.paused)),
    ("current_vel", |m| Value::Float(m.traj.current_vel)),
    ("distance_to_go", |m| Value::Float(m.traj.distance_to_go)),
    ("motion_type", |m| Value::Int(m.traj.motion_type.into())),
    ("spindles", |m| Value::Int(m.spindles.len() as i64)),
    ("din", |m| {
        Value::Ints(m.io.din.iter().map(|b| i64::from(*b)).collect())
    }),
    ("dout", |m| {
        Value::Ints(m.io.dout.iter().map(|b| i64::from(*b)).collect())
    }),
    ("ain", |m| floats(m.io.ain.iter().copied())),
    ("aout", |m| floats(m.io.aout.iter().copied())),
];

/// The fields of each of `stat.joint`.
const JOINT_FIELDS: &[Of<motion::channel::JointState>] = &[
    ("homed", |j| bit(j.homed)),
    ("homing", |j| bit(j.homing)),
    ("enabled", |j| bit(j.amp_enabled)),
    ("fault", |j| bit(j.faulted)),
    ("inpos", |j| bit(j.in_position)),
    ("input", |j| Value::Float(j.pos_fb)),
    ("output", |j| Value::Float(j.pos_cmd)),
    ("velocity", |j| Value::Float(j.vel_cmd)),
    ("ferror_current", |j| Value::Float(j.ferror)),
    ("min_hard_limit", |j| bit(j.neg_hard_limit)),
    ("max_hard_limit", |j| bit(j.pos_hard_limit)),
    ("min_soft_limit", |j| bit(below_soft_limit(j))),
    ("max_soft_limit", |j| bit(above_soft_limit(j))),
    ("min_position_limit", |j| Value::Float(j.min_limit)),
    ("max_position_limit", |j| Value::Float(j.max_limit)),
];

/// A homed joint commanded below its lower soft limit (an unhomed joint
/// has no soft limits, as in LinuxCNC).
fn below_soft_limit(j: &motion::channel::JointState) -> bool {
    j.homed && j.pos_cmd < j.min_limit
}

/// A homed joint commanded above its upper soft limit.
fn above_soft_limit(j: &motion::channel::JointState) -> bool {
    j.homed && j.pos_cmd > j.max_limit
}

/// A joint's bits of `stat.limit`.
fn limit_mask(j: &motion::channel::JointState) -> i64 {
    i64::from(j.neg_hard_limit)
        | i64::from(j.pos_hard_limit) << 1
        | i64::from(below_soft_limit(j)) << 2
        | i64::from(above_soft_limit(j)) << 3
}

/// The fields of each of `stat.axis`.
const AXIS_FIELDS: &[Of<motion::channel::AxisState>] = &[
    ("velocity", |a| Value::Float(a.vel_cmd)),
    ("min_position_limit", |a| Value::Float(a.min_limit)),
    ("max_position_limit", |a| Value::Float(a.max_limit)),
];

/// The fields of each of `stat.spindle`.
const SPINDLE_FIELDS: &[Of<motion::channel::SpindleState>] = &[
    ("enabled", |s| bit(s.on)),
    ("brake", |s| bit(s.brake)),
    ("at_speed", |s| bit(s.at_speed)),
    ("speed", |s| Value::Float(if s.on { s.speed } else { 0.0 })),
    ("direction", |s| {
        Value::Int(match (s.on, s.speed) {
            (false, _) => 0,
            (true, v) if v < 0.0 => -1,
            (true, _) => 1,
        })
    }),
    ("override", |s| Value::Float(s.scale)),
    ("orient_fault", |s| Value::Int(s.orient_fault.into())),
];

/// The fields of each of `stat.tool_table` (an empty slot: id -1).
const TOOL_FIELDS: &[ToolField] = &[
    ("id", |t| Value::Int(t.map_or(-1, |t| t.number.into()))),
    ("pocketno", |t| Value::Int(t.map_or(0, |t| t.pocket.into()))),
    ("diameter", |t| Value::Float(t.map_or(0.0, |t| t.diameter))),
    ("frontangle", |t| {
        Value::Float(t.map_or(0.0, |t| t.front_angle))
    }),
    ("backangle", |t| {
        Value::Float(t.map_or(0.0, |t| t.back_angle))
    }),
    ("orientation", |t| {
        Value::Int(t.map_or(0, |t| t.orientation.into()))
    }),
];

/// The offset fields of a tool, one per axis.
const TOOL_OFFSETS: [&str; 9] = [
    "xoffset", "yoffset", "zoffset", "aoffset", "boffset", "coffset", "uoffset", "voffset",
    "woffset",
];

fn push(out: &mut String, name: &str, v: &Value) {
    let _ = match v {
        Value::Int(i) => writeln!(out, "{name}=i:{i}"),
        Value::Float(f) => writeln!(out, "{name}=f:{f}"),
        Value::Text(t) => {
            let one_line: String = t
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect();
            writeln!(out, "{name}=s:{one_line}")
        }
        Value::Ints(v) => {
            let t: Vec<String> = v.iter().map(i64::to_string).collect();
            writeln!(out, "{name}=I:{}", t.join(" "))
        }
        Value::Floats(v) => {
            let t: Vec<String> = v.iter().map(f64::to_string).collect();
            writeln!(out, "{name}=F:{}", t.join(" "))
        }
    };
}

fn push_records<T>(out: &mut String, list: &str, items: &[T], fields: &[Of<T>]) {
    for (i, item) in items.iter().enumerate() {
        for (name, f) in fields {
            push(out, &format!("{list}.{i}.{name}"), &f(item));
        }
    }
}

/// Joint `i`'s INI settings, as LinuxCNC's `stat.joint` has them.
fn push_joint_info(out: &mut String, i: usize, info: &crate::task_stat_joint::JointInfo) {
    let fields = [
        ("jointType", Value::Int(info.joint_type)),
        ("units", Value::Float(info.units)),
        ("backlash", Value::Float(info.backlash)),
        ("max_ferror", Value::Float(info.max_ferror)),
        ("min_ferror", Value::Float(info.min_ferror)),
    ];
    for (name, v) in &fields {
        push(out, &format!("joint.{i}.{name}"), v);
    }
}

impl Task {
    /// The `stat` snapshot.
    pub(crate) fn stat_lines(&self) -> String {
        let status = self
            .motion
            .as_ref()
            .and_then(crate::motion_setup::MotionLink::status);
        let ctx = Ctx {
            task: self,
            motion: status.as_ref(),
            program: self.program.as_ref().map(crate::program::Program::view),
        };
        let mut out = String::new();
        for (name, f) in FIELDS {
            if let Some(v) = f(&ctx) {
                push(&mut out, name, &v);
            }
        }
        if let Some(m) = &status {
            for (name, f) in MOTION_FIELDS {
                push(&mut out, name, &f(m));
            }
            let joints = m.joints.iter().filter(|j| j.active).count();
            push_records(&mut out, "joint", &m.joints[..joints], JOINT_FIELDS);
            for (i, info) in self.joint_info.iter().take(joints).enumerate() {
                push_joint_info(&mut out, i, info);
            }
            // One flag for every joint, as LinuxCNC's task reports it: any
            // overridden limit.
            let overridden = bit(m.override_mask != 0);
            for i in 0..joints {
                push(&mut out, &format!("joint.{i}.override_limits"), &overridden);
            }
            push_records(&mut out, "axis", &m.axes, AXIS_FIELDS);
            push_records(&mut out, "spindle", &m.spindles, SPINDLE_FIELDS);
            // M51 enables or disables the override of every spindle.
            if let Some(enables) = m.traj.enables {
                let on = bit(enables & motion::sizes::SS_ENABLED != 0);
                for i in 0..m.spindles.len() {
                    push(&mut out, &format!("spindle.{i}.override_enabled"), &on);
                }
            }
        }
        let table = self.io.table();
        for (i, slot) in table.slots.iter().enumerate() {
            let tool = slot.as_ref();
            for (name, f) in TOOL_FIELDS {
                push(&mut out, &format!("tool_table.{i}.{name}"), &f(tool));
            }
            for (a, name) in TOOL_OFFSETS.iter().enumerate() {
                let v = tool.map_or(0.0, |t| t.offset[a]);
                push(
                    &mut out,
                    &format!("tool_table.{i}.{name}"),
                    &Value::Float(v),
                );
            }
        }
        out
    }
}

/// Parses `stat`, `set-dout N on|off` and `set-aout N VALUE`; `None`
/// when `words` is none of them.
pub(crate) fn parse(words: &[&str]) -> Option<Result<TaskRequest, LaunchError>> {
    let (name, rest) = words.split_first()?;
    let request: &'static str = match *name {
        "stat" => {
            return Some(if rest.is_empty() {
                Ok(TaskRequest::Stat)
            } else {
                Err(bad(
                    "stat",
                    format!("takes no arguments, not {}", rest.len()),
                ))
            })
        }
        "set-dout" => "set-dout",
        "set-aout" => "set-aout",
        _ => return None,
    };
    Some(parse_output(request, rest))
}

fn bad(request: &'static str, why: String) -> LaunchError {
    LaunchError::BadArgument { request, why }
}

fn parse_output(request: &'static str, rest: &[&str]) -> Result<TaskRequest, LaunchError> {
    let [index, value] = rest else {
        return Err(bad(
            request,
            format!("takes 2 arguments, not {}", rest.len()),
        ));
    };
    let index = index
        .parse::<i32>()
        .ok()
        .filter(|i| (0..64).contains(i))
        .ok_or_else(|| {
            bad(
                request,
                format!("N must be an output number 0..63, not '{index}'"),
            )
        })?;
    if request == "set-dout" {
        let on = match *value {
            "on" => true,
            "off" => false,
            _ => {
                return Err(bad(
                    request,
                    format!("the value must be on or off, not '{value}'"),
                ))
            }
        };
        return Ok(TaskRequest::SetDout { index, on });
    }
    let value = value
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| bad(request, format!("VALUE must be a number, not '{value}'")))?;
    Ok(TaskRequest::SetAout { index, value })
}

impl Task {
    /// Sets a motion digital or analog output at once, as M64/M65/M68.
    pub(crate) fn output_request(&mut self, req: &TaskRequest) -> Result<String, LaunchError> {
        let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
        let (cmd, done) = match *req {
            TaskRequest::SetDout { index, on } => (
                motion::Command::SetDout {
                    index,
                    on,
                    now: true,
                },
                format!(
                    "motion.digital-out-{index:02} {}",
                    if on { "on" } else { "off" }
                ),
            ),
            TaskRequest::SetAout { index, value } => (
                motion::Command::SetAout {
                    index,
                    value,
                    now: true,
                },
                format!("motion.analog-out-{index:02} {value}"),
            ),
            _ => return Err(bad("set-dout", "not an output request".into())),
        };
        m.command(cmd)
            .map(|()| done)
            .map_err(|source| LaunchError::MotionRefused { source })
    }
}

#[cfg(test)]
#[path = "task_stat_tests.rs"]
mod tests;
