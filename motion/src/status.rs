//! The controller's status as a client sees it: the decoded snapshot
//! ([`MotionStatus`], one [`JointState`] per joint, one [`AxisState`] per
//! world axis) and its text form for terminals.

use std::fmt;

use crate::command::result_name;
use crate::homing::HomeState;
use crate::kins::AXIS_LETTERS;

/// The last command the channel answered: its serial and result code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LastCommand {
    /// Serial number (0: none yet).
    pub serial: u64,
    /// 0 accepted, else the [`reject_code`](crate::command::reject_code).
    pub code: u64,
}

/// One world axis in a [`MotionStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisState {
    /// The kinematics compute this axis.
    pub in_kinematics: bool,
    /// Teleop planner enabled.
    pub tp_enable: bool,
    /// A keyboard (command) jog moves the axis.
    pub kb_jogging: bool,
    /// The jog wheel moves the axis.
    pub wheel_jogging: bool,
    /// The teleop planner moves.
    pub moving: bool,
    /// Commanded position (the world pose's coordinate).
    pub pos_cmd: f64,
    /// Teleop velocity.
    pub vel_cmd: f64,
    /// Position limits.
    pub min_limit: f64,
    /// Upper limit.
    pub max_limit: f64,
}

/// One joint in a [`MotionStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointState {
    /// The joint is active.
    pub active: bool,
    /// Amplifier enabled (`joint.N.amp-enable-out`).
    pub amp_enabled: bool,
    /// At rest.
    pub in_position: bool,
    /// What was wrong.
    pub error: bool,
    /// The positive limit switch is tripped.
    pub pos_hard_limit: bool,
    /// The negative limit switch is tripped.
    pub neg_hard_limit: bool,
    /// Following error tripped.
    pub following_error: bool,
    /// Amplifier fault.
    pub faulted: bool,
    /// The joint is homed.
    pub homed: bool,
    /// The joint is homing.
    pub homing: bool,
    /// A keyboard jog of this joint is active.
    pub jogging: bool,
    /// The homing state (`joint.N.home-state`).
    pub home_state: HomeState,
    /// Commanded position.
    pub pos_cmd: f64,
    /// Position feedback.
    pub pos_fb: f64,
    /// Commanded velocity.
    pub vel_cmd: f64,
    /// Following error and its current limit.
    pub ferror: f64,
    /// The following-error limit now.
    pub ferror_limit: f64,
    /// Soft limits.
    pub min_limit: f64,
    /// Upper limit.
    pub max_limit: f64,
}

/// A consistent copy of the controller's status.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MotionStatus {
    /// True when enabled (amplifiers on).
    pub enabled: bool,
    /// "DISABLED", "FREE", "TELEOP" or "COORD".
    pub mode: &'static str,
    /// The TELEOP flag: in teleop mode, or entering it on enable.
    pub teleop_mode: bool,
    /// The COORD flag: in coordinated mode, or entering it on enable.
    pub coord_mode: bool,
    /// At rest.
    pub in_position: bool,
    /// What was wrong.
    pub error: bool,
    /// A homed joint is commanded beyond its soft limits.
    pub on_soft_limit: bool,
    /// A jog runs.
    pub jog_active: bool,
    /// Homing runs.
    pub homing_active: bool,
    /// Every active joint is homed.
    pub all_homed: bool,
    /// `motion.enable` as last read.
    pub enable_input: bool,
    /// Servo cycles run.
    pub heartbeat: u64,
    /// The last command answered through the channel.
    pub last: LastCommand,
    /// Commands answered through the channel.
    pub served: u64,
    /// Messages the controller reported since it loaded (LinuxCNC's
    /// error messages: faults, limits, probe and jog messages).
    pub events_reported: u64,
    /// The last of them, if any.
    pub last_event: Option<crate::events::Event>,
    /// Faults among those messages (the ones that stop a program): 0
    /// also from a controller that does not report them.
    pub faults_reported: u64,
    /// The last fault, if any, kept when later messages are not faults.
    pub last_fault: Option<crate::fault::Fault>,
    /// The free-mode SCALE.
    pub scale: f64,
    /// Joints whose hard limits are overridden.
    pub override_mask: u64,
    /// Every joint.
    pub joints: Vec<JointState>,
    /// The nine world axes, X Y Z A B C U V W.
    pub axes: Vec<AxisState>,
    /// The coordinated planner and probing.
    pub traj: TrajState,
    /// The spindles, one per `num_spindles`.
    pub spindles: Vec<SpindleState>,
    /// The digital and analog inputs and outputs.
    pub io: IoState,
    /// The external axis offsets.
    pub eoffset: EoffsetState,
}

/// The external axis offsets in a [`MotionStatus`] (all zero from a
/// controller that does not report them).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EoffsetState {
    /// `motion.eoffset-active`: some applied offset is not zero.
    pub active: bool,
    /// `motion.eoffset-limited`: an axis with an offset is on a soft limit.
    pub limited: bool,
    /// The applied offsets (`axis.L.eoffset`), X Y Z A B C U V W.
    pub applied: [f64; 9],
    /// The requested offsets (`axis.L.eoffset-request`).
    pub requested: [f64; 9],
}

/// The synchronised I/O in a [`MotionStatus`] (`motion.digital-in-NN`
/// and the rest), `num_dio` and `num_aio` of each.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IoState {
    /// `motion.digital-in-NN`.
    pub din: Vec<bool>,
    /// `motion.digital-out-NN`.
    pub dout: Vec<bool>,
    /// `motion.analog-in-NN`.
    pub ain: Vec<f64>,
    /// `motion.analog-out-NN`.
    pub aout: Vec<f64>,
}

/// One spindle in a [`MotionStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpindleState {
    /// Commanded on (M3/M4).
    pub on: bool,
    /// The brake is applied.
    pub brake: bool,
    /// `spindle.N.at-speed` as last read.
    pub at_speed: bool,
    /// Commanded speed, rpm (sign: direction; positive forward).
    pub speed: f64,
    /// The spindle override.
    pub scale: f64,
    /// `spindle.N.speed-out`: the speed with the override, rpm.
    pub speed_out: f64,
    /// `spindle.N.speed-in`: the measured speed, revolutions per second.
    pub speed_in: f64,
    /// Where an M19 orientation is.
    pub orient: crate::core::OrientState,
    /// `spindle.N.orient-fault` of the last failed orientation.
    pub orient_fault: i32,
}

/// The coordinated planner and probing in a [`MotionStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrajState {
    /// The motion id executing, or the last one run.
    pub exec_id: i32,
    /// Moves queued, the executing one included.
    pub depth: u64,
    /// The queue is full: wait before queueing more.
    pub queue_full: bool,
    /// PAUSE is in effect (also after a single step).
    pub paused: bool,
    /// A single step runs.
    pub stepping: bool,
    /// An abort is bringing the queued motion to a stop.
    pub aborting: bool,
    /// The S-curve planner is in use.
    pub scurve: bool,
    /// A probing move runs.
    pub probing: bool,
    /// The last probing move found what it looked for.
    pub probe_tripped: bool,
    /// `motion.probe-input` as last read.
    pub probe_input: bool,
    /// Path speed now, and the speed asked for.
    pub current_vel: f64,
    /// The path speed asked for now.
    pub requested_vel: f64,
    /// Distance left in the executing move.
    pub distance_to_go: f64,
    /// Feed and rapid override, and the net scale in effect.
    pub feed_scale: f64,
    /// The rapid override.
    pub rapid_scale: f64,
    /// The net feed scale in effect.
    pub net_scale: f64,
    /// The executing move's type (LinuxCNC's `motion.motion-type`; 0 none).
    pub motion_type: i32,
    /// Where the last probing move tripped (or ended).
    pub probed: [f64; 9],
    /// The world feedback pose.
    pub pos_fb: [f64; 9],
    /// Where the last queued move ends (the next one starts there).
    pub goal: [f64; 9],
    /// The executing move waits for the spindle at speed.
    pub waiting_for_atspeed: bool,
    /// Per axis, the executing move's end minus the commanded position.
    pub dtg: [f64; 9],
    /// The override enable bits for the next move (`SS_ENABLED` and the
    /// others); `None` from a controller that does not report them.
    pub enables: Option<u8>,
    /// LinuxCNC's kinematics type number (1 identity, 2 forward only, 3
    /// inverse only, 4 both); `None` when not reported.
    pub kinematics_type: Option<i32>,
}

impl fmt::Display for MotionStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.fmt_machine(f)?;
        self.fmt_traj(f)?;
        self.fmt_joints(f)?;
        self.fmt_axes(f)?;
        self.fmt_eoffsets(f)
    }
}

/// "yes" or "no".
fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

/// The names of the flags that are on, each after a space.
fn flag_names(flags: &[(bool, &str)]) -> String {
    let mut out = String::new();
    for &(on, name) in flags {
        if on {
            out.push(' ');
            out.push_str(name);
        }
    }
    out
}

impl MotionStatus {
    /// The machine-wide lines, and the last command.
    fn fmt_machine(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let yn = yes_no;
        writeln!(
            f,
            "mode {}  enabled {}  enable-input {}  in-position {}  error {}  scale {}",
            self.mode,
            yn(self.enabled),
            yn(self.enable_input),
            yn(self.in_position),
            yn(self.error),
            self.scale
        )?;
        writeln!(
            f,
            "jog-active {}  on-soft-limit {}  all-homed {}  override-mask {:#x}  heartbeat {}",
            yn(self.jog_active),
            yn(self.on_soft_limit),
            yn(self.all_homed),
            self.override_mask,
            self.heartbeat
        )?;
        if !self.enabled && (self.teleop_mode || self.coord_mode) {
            let m = if self.teleop_mode { "TELEOP" } else { "COORD" };
            writeln!(f, "mode on enable: {m}")?;
        }
        if let Some(fault) = &self.last_fault {
            writeln!(
                f,
                "last fault: {fault} (message {} of {}; faults reported: {})",
                fault.number, self.events_reported, self.faults_reported
            )?;
        }
        Ok(())
    }

    /// The coordinated planner's line, the probe's, the last command's.
    fn fmt_traj(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = &self.traj;
        if self.coord_mode || t.depth > 0 {
            let flags = flag_names(&[
                (t.paused, "paused"),
                (t.stepping, "stepping"),
                (t.aborting, "aborting"),
                (t.queue_full, "queue-full"),
                (t.probing, "probing"),
                (t.scurve, "s-curve"),
                (t.waiting_for_atspeed, "waiting-for-spindle-at-speed"),
            ]);
            writeln!(
                f,
                "line {}  queued {}  speed {:.6}  requested {:.6}  to-go {:.6}  feed {}  rapid {}{}",
                t.exec_id,
                t.depth,
                t.current_vel,
                t.requested_vel,
                t.distance_to_go,
                t.feed_scale,
                t.rapid_scale,
                flags
            )?;
        }
        if t.probe_tripped {
            let p = &t.probed;
            writeln!(
                f,
                "probe tripped at X {:.6} Y {:.6} Z {:.6}",
                p[0], p[1], p[2]
            )?;
        }
        if self.last.serial == 0 {
            writeln!(f, "last command: none")
        } else {
            writeln!(
                f,
                "last command: serial {} {} (code {})",
                self.last.serial,
                result_name(self.last.code),
                self.last.code
            )
        }
    }

    /// The joint table.
    fn fmt_joints(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "joint active amp homed {:>12} {:>12} {:>12} {:>10}  flags",
            "pos-cmd", "pos-fb", "vel-cmd", "ferror"
        )?;
        for (n, j) in self.joints.iter().enumerate() {
            let mut flags = flag_names(&[
                (j.in_position, "inpos"),
                (j.jogging, "jogging"),
                (j.homing, "homing"),
                (j.error, "error"),
                (j.pos_hard_limit, "+hard-limit"),
                (j.neg_hard_limit, "-hard-limit"),
                (j.following_error, "ferror"),
                (j.faulted, "amp-fault"),
            ]);
            if j.home_state != HomeState::Idle {
                flags.push_str(" home-state=");
                flags.push_str(j.home_state.name());
            }
            writeln!(
                f,
                "{n:<5} {:<6} {:<3} {:<5} {:>12.6} {:>12.6} {:>12.6} {:>10.6} {}",
                yes_no(j.active),
                yes_no(j.amp_enabled),
                yes_no(j.homed),
                j.pos_cmd,
                j.pos_fb,
                j.vel_cmd,
                j.ferror,
                flags.trim_start()
            )?;
        }
        Ok(())
    }

    /// The table of the axes the kinematics compute (none if they compute
    /// none).
    fn fmt_axes(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.axes.iter().any(|a| a.in_kinematics) {
            writeln!(
                f,
                "axis {:>12} {:>12} {:>12} {:>12}  flags",
                "pos-cmd", "vel-cmd", "min-limit", "max-limit"
            )?;
        }
        for (a, x) in self.axes.iter().enumerate() {
            if !x.in_kinematics {
                continue;
            }
            let flags = flag_names(&[
                (x.moving, "moving"),
                (x.kb_jogging, "jogging"),
                (x.wheel_jogging, "wheel"),
            ]);
            writeln!(
                f,
                "{:<4} {:>12.6} {:>12.6} {:>12} {:>12} {}",
                AXIS_LETTERS[a].to_ascii_uppercase(),
                x.pos_cmd,
                x.vel_cmd,
                limit_text(x.min_limit),
                limit_text(x.max_limit),
                flags.trim_start()
            )?;
        }
        Ok(())
    }
}

impl MotionStatus {
    /// The external offsets line as `motion-cmd status` prints it
    /// (`external offsets: Z 0.500000 (request 0.500000) active`), or
    /// `None` while no offset is applied, requested or flagged.
    pub fn external_offsets_line(&self) -> Option<String> {
        struct Line<'a>(&'a MotionStatus);
        impl fmt::Display for Line<'_> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.fmt_eoffsets(f)
            }
        }
        let line = Line(self).to_string();
        (!line.is_empty()).then(|| line.trim_end().to_string())
    }

    /// The external offsets line: the axes whose offset or request is not
    /// zero, and the flags (nothing when there are none).
    fn fmt_eoffsets(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = &self.eoffset;
        let used: Vec<usize> = (0..9)
            .filter(|&a| e.applied[a] != 0.0 || e.requested[a] != 0.0)
            .collect();
        if used.is_empty() && !e.active && !e.limited {
            return Ok(());
        }
        write!(f, "external offsets:")?;
        for a in used {
            write!(
                f,
                " {} {:.6} (request {:.6})",
                AXIS_LETTERS[a].to_ascii_uppercase(),
                e.applied[a],
                e.requested[a]
            )?;
        }
        let flags = flag_names(&[(e.active, "active"), (e.limited, "limited")]);
        writeln!(f, "{flags}")
    }
}

/// A limit for the status table: huge values (the ±1e99 "no limit"
/// default) in exponent form, which `{}` would spell out in 100 digits.
fn limit_text(v: f64) -> String {
    if v.abs() >= 1e9 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
