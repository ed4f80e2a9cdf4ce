//! `motmod`: the motion controller as a `loadrt` module.
//!
//! `loadrt motmod num_joints=3 ...` needs a kinematics module loaded
//! before it (`loadrt trivkins`); it creates the `motmod` component with
//! LinuxCNC's `motion.*`, `spindle.M.*`, `joint.N.*` and `axis.L.*` pins
//! and params, the threads `servo-thread` (and `base-thread` when
//! `base_period_nsec` is shorter than the servo period), and the functions
//! `motion-command-handler` and `motion-controller`. As in LinuxCNC the
//! HAL file adds the functions to the servo thread itself:
//!
//! ```text
//! addf motion-command-handler servo-thread
//! addf motion-controller servo-thread
//! ```
//!
//! Commands reach the controller through [`MotionHandle`] (this process)
//! or the shared-memory channel of [`crate::channel`] (any process, e.g.
//! `motion-cmd`): the handler function takes them each period and answers
//! each one; the controller publishes the status snapshot every cycle. Both functions
//! belong in the same thread; if a configuration puts them in threads
//! that preempt each other, the one that finds the controller busy skips
//! its period (as LinuxCNC's handler skips when its mutex is held).

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, Ordering::*};
use std::sync::Arc;
use std::time::Duration;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{
    Component, HalError, Host, In, Io, Out, Param, Pin, Result, RingReader, RingWriter, Ro,
    SeqLockWriter,
};

use crate::channel::{self, LastCommand, CMD_WORDS, STATUS_WORDS};

use crate::command::{Command, CommandResult, Reject};
use crate::core::{MotionConfig, MotionCore, MAX_IO, MAX_JOINTS, MAX_MISC_ERROR, MAX_SPINDLES};
use crate::events::{Event, EventRing};
use crate::kins::{kinematics_for, KinematicsType, AXIS_LETTERS, NUM_AXES};
use crate::mailbox::Mailbox;
use crate::registry::InstanceRegistry;

const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "key",
        kind: ParamKind::Int,
        help: "shared memory key (accepted for compatibility; unused)",
    },
    ParamDecl {
        name: "base_period_nsec",
        kind: ParamKind::Long,
        help: "fastest thread period (nsecs); 0 = the servo period",
    },
    ParamDecl {
        name: "base_thread_fp",
        kind: ParamKind::Int,
        help: "floating point in base thread? (deprecated, ignored)",
    },
    ParamDecl {
        name: "servo_period_nsec",
        kind: ParamKind::Long,
        help: "servo thread period (nsecs), default 1000000",
    },
    ParamDecl {
        name: "traj_period_nsec",
        kind: ParamKind::Long,
        help: "trajectory planner period (nsecs); 0 = the servo period",
    },
    ParamDecl {
        name: "num_spindles",
        kind: ParamKind::Int,
        help: "number of spindles (0-8), default 1",
    },
    ParamDecl {
        name: "num_joints",
        kind: ParamKind::Int,
        help: "number of joints (1-16), default 16",
    },
    ParamDecl {
        name: "num_extrajoints",
        kind: ParamKind::Int,
        help: "number of extra joints, not used in kinematics",
    },
    ParamDecl {
        name: "num_dio",
        kind: ParamKind::Int,
        help: "number of digital inputs/outputs (1-64), default 4",
    },
    ParamDecl {
        name: "names_din",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of digital inputs",
    },
    ParamDecl {
        name: "names_dout",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of digital outputs",
    },
    ParamDecl {
        name: "num_aio",
        kind: ParamKind::Int,
        help: "number of analog inputs/outputs (1-64), default 4",
    },
    ParamDecl {
        name: "names_ain",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of analog inputs",
    },
    ParamDecl {
        name: "names_aout",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of analog outputs",
    },
    ParamDecl {
        name: "num_misc_error",
        kind: ParamKind::Int,
        help: "number of misc error inputs (0-64), default 0",
    },
    ParamDecl {
        name: "names_misc_errors",
        kind: ParamKind::StrArray(MAX_MISC_ERROR),
        help: "names of misc error inputs",
    },
    ParamDecl {
        name: "unlock_joints_mask",
        kind: ParamKind::Int,
        help: "mask to select joints for unlock pins",
    },
];

/// The `motmod` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "motmod",
    params: PARAMS,
    help: "motion controller (needs a kinematics module loaded first)",
    load,
};

/// Digital or analog I/O pins: how many pairs and the names given.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct IoNames {
    /// Pairs of pins.
    pub count: usize,
    /// `names_din`/`names_ain`: named inputs, the rest are numbered.
    pub inputs: Vec<String>,
    /// `names_dout`/`names_aout`: named outputs, the rest are numbered.
    pub outputs: Vec<String>,
}

/// `motmod`'s module parameters, checked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MotmodParams {
    pub num_joints: usize,
    pub num_extrajoints: usize,
    pub num_spindles: usize,
    pub dio: IoNames,
    pub aio: IoNames,
    /// Misc-error inputs: their names if given by name.
    pub num_misc_error: usize,
    pub misc_error_names: Vec<String>,
    pub unlock_joints_mask: u32,
    /// Base thread period; the base thread exists only if shorter than
    /// the servo period.
    pub base_period_nsec: i64,
    /// Servo period, a whole multiple of the base period.
    pub servo_period_nsec: i64,
    pub traj_period_nsec: i64,
    pub base_thread_fp: bool,
}

fn bad(param: &str, reason: String) -> HalError {
    HalError::ModuleParam {
        module: "motmod".into(),
        param: param.into(),
        reason,
    }
}

/// LinuxCNC counts names up to the first empty one.
fn leading_names(names: &[String]) -> Vec<String> {
    names
        .iter()
        .take_while(|s| !s.is_empty())
        .cloned()
        .collect()
}

fn io_names(
    args: &ModuleArgs,
    num: &str,
    names_in: &str,
    names_out: &str,
    kind: &str,
) -> Result<IoNames> {
    let inputs = leading_names(args.str_array(names_in));
    let outputs = leading_names(args.str_array(names_out));
    let count = if !inputs.is_empty() || !outputs.is_empty() {
        if args.int(num).is_some() {
            return Err(bad(
                num,
                format!("can't specify both names and number for {kind} pins"),
            ));
        }
        inputs.len().max(outputs.len()) as i64
    } else {
        args.int(num).unwrap_or(4)
    };
    if !(1..=MAX_IO as i64).contains(&count) {
        return Err(bad(num, format!("{count} is out of range 1-{MAX_IO}")));
    }
    Ok(IoNames {
        count: count as usize,
        inputs,
        outputs,
    })
}

/// Checks `motmod`'s arguments against LinuxCNC's rules. `kins_type` is the
/// loaded kinematics' type (extra joints need `Both`).
pub fn parse_params(args: &ModuleArgs, kins_type: KinematicsType) -> Result<MotmodParams> {
    let num_joints = args.int("num_joints").unwrap_or(MAX_JOINTS as i64);
    if !(1..=MAX_JOINTS as i64).contains(&num_joints) {
        return Err(bad(
            "num_joints",
            format!("{num_joints} is out of range 1-{MAX_JOINTS}"),
        ));
    }
    let num_extrajoints = args.int("num_extrajoints").unwrap_or(0);
    if !(0..=num_joints).contains(&num_extrajoints) {
        return Err(bad(
            "num_extrajoints",
            format!("{num_extrajoints} is out of range 0-{num_joints} (num_joints)"),
        ));
    }
    if num_extrajoints > 0 && kins_type != KinematicsType::Both {
        return Err(bad(
            "num_extrajoints",
            "extra joints need KINEMATICS_BOTH kinematics (e.g. trivkins kinstype=both)".into(),
        ));
    }
    let num_spindles = args.int("num_spindles").unwrap_or(1);
    if !(0..=MAX_SPINDLES as i64).contains(&num_spindles) {
        return Err(bad(
            "num_spindles",
            format!("{num_spindles} is out of range 0-{MAX_SPINDLES}"),
        ));
    }
    let dio = io_names(args, "num_dio", "names_din", "names_dout", "digital")?;
    let aio = io_names(args, "num_aio", "names_ain", "names_aout", "analog")?;
    let misc_error_names = leading_names(args.str_array("names_misc_errors"));
    let num_misc_error = if !misc_error_names.is_empty() {
        if args.int("num_misc_error").is_some() {
            return Err(bad(
                "num_misc_error",
                "can't specify both names and number for misc error inputs".into(),
            ));
        }
        misc_error_names.len() as i64
    } else {
        args.int("num_misc_error").unwrap_or(0)
    };
    if !(0..=MAX_MISC_ERROR as i64).contains(&num_misc_error) {
        return Err(bad(
            "num_misc_error",
            format!("{num_misc_error} is out of range 0-{MAX_MISC_ERROR}"),
        ));
    }
    let servo = args.int("servo_period_nsec").unwrap_or(1_000_000);
    if servo <= 0 {
        return Err(bad(
            "servo_period_nsec",
            format!("{servo} is not a period: it must be positive"),
        ));
    }
    let mut base = args.int("base_period_nsec").unwrap_or(0);
    if base < 0 {
        return Err(bad(
            "base_period_nsec",
            format!("{base} is not a period: it must be positive (or 0 for the servo period)"),
        ));
    }
    if base == 0 {
        base = servo;
    }
    if servo < base {
        return Err(bad(
            "servo_period_nsec",
            format!("{servo} is shorter than base_period_nsec {base}"),
        ));
    }
    let mut traj = args.int("traj_period_nsec").unwrap_or(0);
    if traj < 0 {
        return Err(bad(
            "traj_period_nsec",
            format!("{traj} is not a period: it must be positive (or 0 for the servo period)"),
        ));
    }
    if traj == 0 {
        traj = servo;
    }
    // LinuxCNC rounds the servo period to a whole multiple of the base
    // period: ratio = (int)(servo_sec / base_sec + 0.5).
    let ratio = ((servo as f64 * 1e-9) / (base as f64 * 1e-9) + 0.5) as i64;
    let servo = base.checked_mul(ratio).filter(|&s| s > 0).ok_or_else(|| {
        bad(
            "servo_period_nsec",
            format!("{servo} ns is not a usable multiple of the base period {base} ns"),
        )
    })?;
    Ok(MotmodParams {
        num_joints: num_joints as usize,
        num_extrajoints: num_extrajoints as usize,
        num_spindles: num_spindles as usize,
        dio,
        aio,
        num_misc_error: num_misc_error as usize,
        misc_error_names,
        unlock_joints_mask: args.int("unlock_joints_mask").unwrap_or(0) as u32,
        base_period_nsec: base,
        servo_period_nsec: servo,
        traj_period_nsec: traj,
        base_thread_fp: args.int("base_thread_fp").unwrap_or(0) != 0,
    })
}

/// What a sender needs to reach a loaded `motmod`.
pub struct MotionLink {
    mailbox: Arc<Mailbox>,
    events: Arc<EventRing>,
    num_joints: usize,
}

/// The `motmod` of each HAL instance.
pub static MOTION: InstanceRegistry<MotionLink> = InstanceRegistry::new("motion controller");

/// How long a command may wait for the handler (LinuxCNC's default
/// `[EMCMOT]COMM_TIMEOUT`).
pub const COMMAND_TIMEOUT: Duration = Duration::from_secs(1);

/// The Rust interface to a `motmod` loaded in some HAL instance of this
/// process: send commands, read reported messages.
#[derive(Clone)]
pub struct MotionHandle {
    link: Arc<MotionLink>,
}

impl std::fmt::Debug for MotionHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MotionHandle")
            .field("num_joints", &self.link.num_joints)
            .finish()
    }
}

impl MotionHandle {
    /// The handle of the `motmod` loaded in `instance`, if any.
    pub fn attach(instance: &str) -> Option<MotionHandle> {
        MOTION.get(instance).map(|(_, link)| MotionHandle { link })
    }

    /// Sends a command and waits for its result; [`crate::Reject::Timeout`]
    /// if `motion-command-handler` does not take it within
    /// [`COMMAND_TIMEOUT`] (its thread is not running).
    pub fn command(&self, cmd: Command) -> CommandResult {
        self.link.mailbox.send(cmd, COMMAND_TIMEOUT)
    }

    /// Takes the messages reported since the last call.
    pub fn events(&self) -> Vec<Event> {
        self.link.events.drain()
    }

    /// Number of joints.
    pub fn num_joints(&self) -> usize {
        self.link.num_joints
    }
}

/// What both functions use: the controller, and the last command the
/// handler answered through the channel (which the controller publishes
/// with the status).
struct Controller {
    core: MotionCore,
    last: LastCommand,
    /// Channel commands answered so far.
    served: u64,
}

/// The [`Controller`], which each function claims with an atomic flag for
/// the duration of its body (never waiting).
struct CoreCell {
    busy: AtomicBool,
    ctl: UnsafeCell<Controller>,
}

// SAFETY: the core is only reached through `with`, which hands out the
// `&mut` only to the caller that flipped `busy` from false to true.
unsafe impl Sync for CoreCell {}

impl CoreCell {
    fn with<R>(&self, f: impl FnOnce(&mut Controller) -> R) -> Option<R> {
        if self
            .busy
            .compare_exchange(false, true, Acquire, Relaxed)
            .is_err()
        {
            return None;
        }
        // SAFETY: we hold the claim (see `impl Sync`).
        let r = f(unsafe { &mut *self.ctl.get() });
        self.busy.store(false, Release);
        Some(r)
    }
}

type FIn = Pin<f64, In>;
type FOut = Pin<f64, Out>;
type BIn = Pin<bool, In>;
type BOut = Pin<bool, Out>;

struct JointPins {
    coarse_pos_cmd: FOut,
    pos_cmd: FOut,
    pos_fb: FOut,
    motor_pos_cmd: FOut,
    motor_pos_fb: FIn,
    motor_offset: FOut,
    pos_lim_sw: BIn,
    neg_lim_sw: BIn,
    amp_enable: BOut,
    amp_fault: BIn,
    jog_counts: Pin<i32, In>,
    jog_enable: BIn,
    jog_scale: FIn,
    jog_vel_mode: BIn,
    vel_cmd: FOut,
    acc_cmd: FOut,
    jerk_cmd: FOut,
    backlash_corr: FOut,
    backlash_filt: FOut,
    backlash_vel: FOut,
    f_error: FOut,
    f_error_lim: FOut,
    free_pos_cmd: FOut,
    free_vel_lim: FOut,
    free_tp_enable: BOut,
    kb_jog_active: BOut,
    wheel_jog_active: BOut,
    in_position: BOut,
    pos_hard_limit: BOut,
    neg_hard_limit: BOut,
    active: BOut,
    error: BOut,
    f_errored: BOut,
    faulted: BOut,
    jog_accel_fraction: FIn,
    unlock: Option<(BOut, BIn)>,
    home_sw_in: BIn,
    homing: BOut,
    homed: BOut,
    home_state: Pin<i32, Out>,
    index_enable: Pin<bool, Io>,
    posthome_cmd: Option<FIn>,
}

impl JointPins {
    fn new(c: &Component, n: usize, lockable: bool) -> Result<JointPins> {
        let p = |item: &str| format!("joint.{n}.{item}");
        Ok(JointPins {
            coarse_pos_cmd: c.pin(&p("coarse-pos-cmd"))?,
            pos_cmd: c.pin(&p("pos-cmd"))?,
            pos_fb: c.pin(&p("pos-fb"))?,
            motor_pos_cmd: c.pin(&p("motor-pos-cmd"))?,
            motor_pos_fb: c.pin(&p("motor-pos-fb"))?,
            motor_offset: c.pin(&p("motor-offset"))?,
            pos_lim_sw: c.pin(&p("pos-lim-sw-in"))?,
            neg_lim_sw: c.pin(&p("neg-lim-sw-in"))?,
            amp_enable: c.pin(&p("amp-enable-out"))?,
            amp_fault: c.pin(&p("amp-fault-in"))?,
            jog_counts: c.pin(&p("jog-counts"))?,
            jog_enable: c.pin(&p("jog-enable"))?,
            jog_scale: c.pin(&p("jog-scale"))?,
            jog_vel_mode: c.pin(&p("jog-vel-mode"))?,
            vel_cmd: c.pin(&p("vel-cmd"))?,
            acc_cmd: c.pin(&p("acc-cmd"))?,
            jerk_cmd: c.pin(&p("jerk-cmd"))?,
            backlash_corr: c.pin(&p("backlash-corr"))?,
            backlash_filt: c.pin(&p("backlash-filt"))?,
            backlash_vel: c.pin(&p("backlash-vel"))?,
            f_error: c.pin(&p("f-error"))?,
            f_error_lim: c.pin(&p("f-error-lim"))?,
            free_pos_cmd: c.pin(&p("free-pos-cmd"))?,
            free_vel_lim: c.pin(&p("free-vel-lim"))?,
            free_tp_enable: c.pin(&p("free-tp-enable"))?,
            kb_jog_active: c.pin(&p("kb-jog-active"))?,
            wheel_jog_active: c.pin(&p("wheel-jog-active"))?,
            in_position: c.pin(&p("in-position"))?,
            pos_hard_limit: c.pin(&p("pos-hard-limit"))?,
            neg_hard_limit: c.pin(&p("neg-hard-limit"))?,
            active: c.pin(&p("active"))?,
            error: c.pin(&p("error"))?,
            f_errored: c.pin(&p("f-errored"))?,
            faulted: c.pin(&p("faulted"))?,
            jog_accel_fraction: c.pin_init(&p("jog-accel-fraction"), 1.0)?,
            unlock: if lockable {
                Some((c.pin(&p("unlock"))?, c.pin(&p("is-unlocked"))?))
            } else {
                None
            },
            // The homing module's pins.
            home_sw_in: c.pin(&p("home-sw-in"))?,
            homing: c.pin(&p("homing"))?,
            homed: c.pin(&p("homed"))?,
            home_state: c.pin(&p("home-state"))?,
            index_enable: c.pin(&p("index-enable"))?,
            posthome_cmd: None,
        })
    }
}

struct AxisPins {
    pos_cmd: FOut,
    teleop_vel_cmd: FOut,
    teleop_pos_cmd: FOut,
    teleop_vel_lim: FOut,
    teleop_tp_enable: BOut,
    // Inputs and outputs the external offsets will use.
    _eoffset_enable: BIn,
    _eoffset_clear: BIn,
    _eoffset_counts: Pin<i32, In>,
    _eoffset_scale: FIn,
    _eoffset: FOut,
    _eoffset_request: FOut,
    jog_enable: BIn,
    jog_scale: FIn,
    jog_counts: Pin<i32, In>,
    jog_vel_mode: BIn,
    kb_jog_active: BOut,
    wheel_jog_active: BOut,
    jog_accel_fraction: FIn,
}

impl AxisPins {
    fn new(c: &Component, l: char) -> Result<AxisPins> {
        let p = |item: &str| format!("axis.{l}.{item}");
        Ok(AxisPins {
            pos_cmd: c.pin(&p("pos-cmd"))?,
            teleop_vel_cmd: c.pin(&p("teleop-vel-cmd"))?,
            teleop_pos_cmd: c.pin(&p("teleop-pos-cmd"))?,
            teleop_vel_lim: c.pin(&p("teleop-vel-lim"))?,
            teleop_tp_enable: c.pin(&p("teleop-tp-enable"))?,
            _eoffset_enable: c.pin(&p("eoffset-enable"))?,
            _eoffset_clear: c.pin(&p("eoffset-clear"))?,
            _eoffset_counts: c.pin(&p("eoffset-counts"))?,
            _eoffset_scale: c.pin(&p("eoffset-scale"))?,
            _eoffset: c.pin(&p("eoffset"))?,
            _eoffset_request: c.pin(&p("eoffset-request"))?,
            jog_enable: c.pin(&p("jog-enable"))?,
            jog_scale: c.pin(&p("jog-scale"))?,
            jog_counts: c.pin(&p("jog-counts"))?,
            jog_vel_mode: c.pin(&p("jog-vel-mode"))?,
            kb_jog_active: c.pin(&p("kb-jog-active"))?,
            wheel_jog_active: c.pin(&p("wheel-jog-active"))?,
            jog_accel_fraction: c.pin_init(&p("jog-accel-fraction"), 1.0)?,
        })
    }
}

/// The spindle pins; spindle control arrives with the coordinated mode.
/// The controller reads the amp fault (a fault disables motion) and the
/// inhibit input.
struct SpindlePins {
    amp_fault: BIn,
    inhibit: BIn,
    _outputs: (BOut, BOut, BOut, BOut, [FOut; 5]),
    _orient: (FOut, Pin<i32, Out>, BOut, BOut, BIn, Pin<i32, In>),
    _feedback: (Pin<bool, Io>, FIn, FIn, BIn),
}

impl SpindlePins {
    fn new(c: &Component, n: usize) -> Result<SpindlePins> {
        let p = |item: &str| format!("spindle.{n}.{item}");
        Ok(SpindlePins {
            _feedback: (
                c.pin(&p("index-enable"))?,
                c.pin(&p("revs"))?,
                c.pin(&p("speed-in"))?,
                c.pin_init(&p("at-speed"), true)?,
            ),
            _outputs: (
                c.pin(&p("on"))?,
                c.pin(&p("forward"))?,
                c.pin(&p("reverse"))?,
                c.pin(&p("brake"))?,
                [
                    c.pin(&p("speed-out"))?,
                    c.pin(&p("speed-out-abs"))?,
                    c.pin(&p("speed-out-rps"))?,
                    c.pin(&p("speed-out-rps-abs"))?,
                    c.pin(&p("speed-cmd-rps"))?,
                ],
            ),
            inhibit: c.pin(&p("inhibit"))?,
            amp_fault: c.pin(&p("amp-fault-in"))?,
            _orient: (
                c.pin(&p("orient-angle"))?,
                c.pin(&p("orient-mode"))?,
                c.pin(&p("orient"))?,
                c.pin(&p("locked"))?,
                c.pin(&p("is-oriented"))?,
                c.pin(&p("orient-fault"))?,
            ),
        })
    }
}

/// The machine-wide pins and params.
struct MotionPins {
    probe_input: BIn,
    adaptive_feed: FIn,
    feed_hold: BIn,
    feed_inhibit: BIn,
    homing_inhibit: BIn,
    jog_inhibit: BIn,
    jog_stop: BIn,
    jog_stop_immediate: BIn,
    enable: BIn,
    switchkins_type: Option<FIn>,
    misc_error: Vec<BIn>,
    motion_enabled: BOut,
    in_position: BOut,
    coord_mode: BOut,
    teleop_mode: BOut,
    coord_error: BOut,
    on_soft_limit: BOut,
    current_vel: FOut,
    jog_is_active: BOut,
    is_all_homed: BOut,
    last_period: Pin<u32, Out>,
    debug_bit_0: Param<bool, Ro>,
    debug_float_3: Param<f64, Ro>,
    debug_s32_0: Param<i32, Ro>,
    /// Pins and params later milestones drive; they hold their defaults.
    _later: LaterPins,
}

/// Outputs of the queued coordinated planner, I/O and tool offsets (driven
/// once those parts exist; until then `motion.motion-type` and
/// `motion.program-line` read 0, "no segment executing", which is also
/// right in teleop and in the holding coordinated mode) and the stale
/// LinuxCNC debug params.
struct LaterPins {
    _tp_reverse: BOut,
    _feed: [FOut; 5],
    _dio: Vec<(BIn, BOut)>,
    _aio: Vec<(FIn, FOut)>,
    _motion_type: Pin<i32, Out>,
    _requested_vel: FOut,
    _distance_to_go: FOut,
    _program_line: Pin<i32, Out>,
    _interp_s32: [Pin<i32, Out>; 2],
    _interp_float: [FOut; 7],
    _interp_iscircle: BOut,
    _tooloffset: Vec<FOut>,
    _eoffset: (BOut, BOut),
    _debug_bit_1: Param<bool, Ro>,
    _debug_floats: [Param<f64, Ro>; 3],
    _debug_s32_1: Param<i32, Ro>,
    _traj: (Param<f64, Ro>, Param<f64, Ro>, Param<u32, Ro>),
    _tc: Vec<Param<f64, Ro>>,
}

fn io_pin_name(
    prefix_named: &str,
    prefix_num: &str,
    names: &[String],
    n: usize,
    numbered: &mut usize,
) -> String {
    match names.get(n) {
        Some(name) => format!("motion.{prefix_named}-{name}"),
        None => {
            let s = format!("motion.{prefix_num}-{:02}", *numbered);
            *numbered += 1;
            s
        }
    }
}

impl MotionPins {
    fn new(c: &Component, p: &MotmodParams, switchable: bool) -> Result<MotionPins> {
        let probe_input = c.pin("motion.probe-input")?;
        let adaptive_feed = c.pin_init("motion.adaptive-feed", 1.0)?;
        let feed_hold = c.pin("motion.feed-hold")?;
        let feed_inhibit = c.pin("motion.feed-inhibit")?;
        let homing_inhibit = c.pin("motion.homing-inhibit")?;
        let jog_inhibit = c.pin("motion.jog-inhibit")?;
        let jog_stop = c.pin("motion.jog-stop")?;
        let jog_stop_immediate = c.pin("motion.jog-stop-immediate")?;
        let tp_reverse = c.pin("motion.tp-reverse")?;
        // Default TRUE, so simple machines can leave it unconnected.
        let enable = c.pin_init("motion.enable", true)?;
        let is_all_homed = c.pin("motion.is-all-homed")?;
        let feed = [
            c.pin("motion.feed-upm")?,
            c.pin("motion.feed-inches-per-minute")?,
            c.pin("motion.feed-inches-per-second")?,
            c.pin("motion.feed-mm-per-minute")?,
            c.pin("motion.feed-mm-per-second")?,
        ];
        let (mut din, mut dout) = (0, 0);
        let mut dio = Vec::with_capacity(p.dio.count);
        for n in 0..p.dio.count {
            let i = io_pin_name("din", "digital-in", &p.dio.inputs, n, &mut din);
            let o = io_pin_name("dout", "digital-out", &p.dio.outputs, n, &mut dout);
            dio.push((c.pin(&i)?, c.pin(&o)?));
        }
        let (mut ain, mut aout) = (0, 0);
        let mut aio = Vec::with_capacity(p.aio.count);
        for n in 0..p.aio.count {
            let i = io_pin_name("ain", "analog-in", &p.aio.inputs, n, &mut ain);
            let o = io_pin_name("aout", "analog-out", &p.aio.outputs, n, &mut aout);
            aio.push((c.pin(&i)?, c.pin(&o)?));
        }
        let mut misc_error = Vec::with_capacity(p.num_misc_error);
        for n in 0..p.num_misc_error {
            let name = match p.misc_error_names.get(n) {
                Some(name) => format!("motion.err-{name}"),
                None => format!("motion.misc-error-{n:02}"),
            };
            misc_error.push(c.pin(&name)?);
        }
        let motion_enabled = c.pin("motion.motion-enabled")?;
        let in_position = c.pin("motion.in-position")?;
        let motion_type = c.pin("motion.motion-type")?;
        let coord_mode = c.pin("motion.coord-mode")?;
        let teleop_mode = c.pin("motion.teleop-mode")?;
        let coord_error = c.pin("motion.coord-error")?;
        let on_soft_limit = c.pin("motion.on-soft-limit")?;
        let current_vel = c.pin("motion.current-vel")?;
        let requested_vel = c.pin("motion.requested-vel")?;
        let distance_to_go = c.pin("motion.distance-to-go")?;
        let program_line = c.pin("motion.program-line")?;
        let jog_is_active = c.pin("motion.jog-is-active")?;
        let interp_s32 = [
            c.pin("motion.interp.line-number")?,
            c.pin("motion.interp.motion-type")?,
        ];
        let interp_float = [
            c.pin("motion.interp.feedrate")?,
            c.pin("motion.interp.arc-radius")?,
            c.pin("motion.interp.arc-center-x")?,
            c.pin("motion.interp.arc-center-y")?,
            c.pin("motion.interp.arc-center-z")?,
            c.pin("motion.interp.heading")?,
            c.pin("motion.interp.normal-heading")?,
        ];
        let interp_iscircle = c.pin("motion.interp.iscircle")?;
        let debug_bit_0 = c.param("motion.debug-bit-0", false)?;
        let debug_bit_1 = c.param("motion.debug-bit-1", false)?;
        let debug_float_0 = c.param("motion.debug-float-0", 0.0)?;
        let debug_float_1 = c.param("motion.debug-float-1", 0.0)?;
        let debug_float_2 = c.param("motion.debug-float-2", 0.0)?;
        let debug_float_3 = c.param("motion.debug-float-3", 0.0)?;
        let debug_s32_0 = c.param("motion.debug-s32-0", 0)?;
        let debug_s32_1 = c.param("motion.debug-s32-1", 0)?;
        let traj = (
            c.param("traj.pos_out", 0.0)?,
            c.param("traj.vel_out", 0.0)?,
            c.param("traj.active_tc", 0u32)?,
        );
        let mut tc = Vec::with_capacity(12);
        for n in 0..4 {
            tc.push(c.param(&format!("tc.{n}.pos"), 0.0)?);
            tc.push(c.param(&format!("tc.{n}.vel"), 0.0)?);
            tc.push(c.param(&format!("tc.{n}.acc"), 0.0)?);
        }
        let last_period = c.pin("motion.servo.last-period")?;
        let mut tooloffset = Vec::with_capacity(NUM_AXES);
        for l in AXIS_LETTERS {
            tooloffset.push(c.pin(&format!("motion.tooloffset.{l}"))?);
        }
        let switchkins_type = if switchable {
            Some(c.pin("motion.switchkins-type")?)
        } else {
            None
        };
        Ok(MotionPins {
            probe_input,
            adaptive_feed,
            feed_hold,
            feed_inhibit,
            homing_inhibit,
            jog_inhibit,
            jog_stop,
            jog_stop_immediate,
            enable,
            switchkins_type,
            misc_error,
            motion_enabled,
            in_position,
            coord_mode,
            teleop_mode,
            coord_error,
            on_soft_limit,
            current_vel,
            jog_is_active,
            is_all_homed,
            last_period,
            debug_bit_0,
            debug_float_3,
            debug_s32_0,
            _later: LaterPins {
                _tp_reverse: tp_reverse,
                _feed: feed,
                _dio: dio,
                _aio: aio,
                _motion_type: motion_type,
                _requested_vel: requested_vel,
                _distance_to_go: distance_to_go,
                _program_line: program_line,
                _interp_s32: interp_s32,
                _interp_float: interp_float,
                _interp_iscircle: interp_iscircle,
                _tooloffset: tooloffset,
                _eoffset: (
                    c.pin("motion.eoffset-limited")?,
                    c.pin("motion.eoffset-active")?,
                ),
                _debug_bit_1: debug_bit_1,
                _debug_floats: [debug_float_0, debug_float_1, debug_float_2],
                _debug_s32_1: debug_s32_1,
                _traj: traj,
                _tc: tc,
            },
        })
    }
}

/// Every pin the controller function reads or writes.
struct HalIo {
    motion: MotionPins,
    spindles: Vec<SpindlePins>,
    joints: Vec<JointPins>,
    axes: Vec<AxisPins>,
}

impl HalIo {
    /// Copies the HAL inputs into the core.
    fn read(&self, core: &mut MotionCore) {
        let m = &self.motion;
        let inp = &mut core.inputs;
        inp.enable = m.enable.get();
        inp.probe_input = m.probe_input.get();
        inp.adaptive_feed = m.adaptive_feed.get();
        inp.feed_hold = m.feed_hold.get();
        inp.feed_inhibit = m.feed_inhibit.get();
        inp.homing_inhibit = m.homing_inhibit.get();
        inp.jog_inhibit = m.jog_inhibit.get();
        inp.jog_stop = m.jog_stop.get();
        inp.jog_stop_immediate = m.jog_stop_immediate.get();
        if let Some(p) = &m.switchkins_type {
            inp.switchkins_type = p.get();
        }
        for (slot, pin) in inp.misc_error.iter_mut().zip(&m.misc_error) {
            *slot = pin.get();
        }
        for (slot, s) in inp.spindle_amp_fault.iter_mut().zip(&self.spindles) {
            *slot = s.amp_fault.get();
        }
        for (ji, jp) in core.joint_inputs.iter_mut().zip(&self.joints) {
            ji.motor_pos_fb = jp.motor_pos_fb.get();
            ji.pos_lim_sw = jp.pos_lim_sw.get();
            ji.neg_lim_sw = jp.neg_lim_sw.get();
            ji.amp_fault = jp.amp_fault.get();
            ji.home_sw = jp.home_sw_in.get();
            ji.index_enable = jp.index_enable.get();
            ji.jog_counts = jp.jog_counts.get();
            ji.jog_enable = jp.jog_enable.get();
            ji.jog_scale = jp.jog_scale.get();
            ji.jog_vel_mode = jp.jog_vel_mode.get();
            ji.jog_accel_fraction = jp.jog_accel_fraction.get();
            if let Some(p) = &jp.posthome_cmd {
                ji.posthome_cmd = p.get();
            }
            if let Some((_, is_unlocked)) = &jp.unlock {
                ji.is_unlocked = is_unlocked.get();
            }
        }
        for (ai, ap) in core.axis_inputs.iter_mut().zip(&self.axes) {
            ai.jog_counts = ap.jog_counts.get();
            ai.jog_enable = ap.jog_enable.get();
            ai.jog_scale = ap.jog_scale.get();
            ai.jog_vel_mode = ap.jog_vel_mode.get();
            ai.jog_accel_fraction = ap.jog_accel_fraction.get();
        }
    }

    /// Writes the core's results to the HAL outputs.
    fn write(&self, core: &MotionCore) {
        let m = &self.motion;
        m.motion_enabled.set(core.is_enabled());
        m.in_position.set(core.in_position());
        // LinuxCNC's COORD and TELEOP flags: kept while disabled.
        m.coord_mode.set(core.coord_mode());
        m.teleop_mode.set(core.teleop_mode());
        m.coord_error.set(core.error());
        m.on_soft_limit.set(core.on_soft_limit());
        m.current_vel.set(core.current_vel());
        m.jog_is_active.set(core.jog_is_active());
        m.is_all_homed.set(core.is_all_homed());
        m.debug_bit_0
            .set(core.num_joints() > 1 && core.joint_ref(1).free_tp.active);
        m.debug_float_3.set(match self.spindles.first() {
            Some(s) if s.inhibit.get() => 0.0,
            Some(_) => 1.0,
            None => 0.0,
        });
        m.debug_s32_0.set(core.override_limit_mask() as i32);
        for (j, jp) in self.joints.iter().enumerate() {
            let jt = core.joint_ref(j);
            jp.motor_offset.set(jt.motor_offset);
            jp.motor_pos_cmd.set(jt.motor_pos_cmd);
            jp.pos_cmd.set(jt.pos_cmd);
            jp.pos_fb.set(jt.pos_fb);
            jp.amp_enable.set(jt.enabled);
            jp.coarse_pos_cmd.set(jt.coarse_pos);
            jp.vel_cmd.set(jt.vel_cmd);
            jp.acc_cmd.set(jt.acc_cmd);
            jp.jerk_cmd.set(jt.jerk_cmd);
            jp.backlash_corr.set(jt.backlash_corr);
            jp.backlash_filt.set(jt.backlash_filt);
            jp.backlash_vel.set(jt.backlash_vel);
            jp.f_error.set(jt.ferror);
            jp.f_error_lim.set(jt.ferror_limit);
            jp.free_pos_cmd.set(jt.free_tp.pos_cmd);
            jp.free_vel_lim.set(jt.free_tp.max_vel);
            jp.free_tp_enable.set(jt.free_tp.enable);
            jp.kb_jog_active.set(jt.kb_jog_active);
            jp.wheel_jog_active.set(jt.wheel_jog_active);
            jp.active.set(jt.active);
            jp.in_position.set(jt.inpos);
            jp.error.set(jt.error);
            jp.pos_hard_limit.set(jt.phl);
            jp.neg_hard_limit.set(jt.nhl);
            jp.f_errored.set(jt.ferror_flag);
            jp.faulted.set(jt.fault);
            jp.homing.set(jt.homing);
            jp.homed.set(jt.homed);
            jp.home_state.set(core.home_state(j).number());
            // Only the edges: the encoder drives the same signal.
            if let Some(v) = core.index_enable_drive(j) {
                jp.index_enable.set(v);
            }
            if let Some((unlock, _)) = &jp.unlock {
                unlock.set(core.unlock_output(j));
            }
        }
        let (pose, _) = core.carte_pos_cmd();
        for (a, ap) in self.axes.iter().enumerate() {
            ap.pos_cmd.set(pose.0[a]);
            let ax = core.axis_ref(a);
            ap.teleop_pos_cmd.set(ax.teleop_tp.pos_cmd);
            ap.teleop_vel_cmd.set(ax.teleop_tp.curr_vel);
            ap.teleop_vel_lim.set(ax.teleop_tp.max_vel);
            ap.teleop_tp_enable.set(ax.teleop_tp.enable);
            ap.kb_jog_active.set(ax.kb_jog_active);
            ap.wheel_jog_active.set(ax.wheel_jog_active);
        }
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let instance = host.instance().name().to_string();
    let (_, kins) = kinematics_for(&instance).ok_or_else(|| HalError::ModuleLoad {
        module: "motmod".into(),
        reason: "no kinematics module is loaded: load one (e.g. 'loadrt trivkins') before motmod"
            .into(),
    })?;
    let p = parse_params(args, kins.kins_type())?;

    let mut b = host.new_rt_component("motmod")?;
    let c = b.component();
    let motion = MotionPins::new(c, &p, kins.is_switchable())?;
    let mut spindles = Vec::with_capacity(p.num_spindles);
    for n in 0..p.num_spindles {
        spindles.push(SpindlePins::new(c, n)?);
    }
    let mut joints = Vec::with_capacity(p.num_joints);
    for n in 0..p.num_joints {
        let lockable = n < 32 && p.unlock_joints_mask & (1 << n) != 0;
        joints.push(JointPins::new(c, n, lockable)?);
    }
    let first_extra = p.num_joints - p.num_extrajoints;
    for (n, jp) in joints.iter_mut().enumerate().skip(first_extra) {
        jp.posthome_cmd = Some(c.pin(&format!("joint.{n}.posthome-cmd"))?);
    }
    let mut axes = Vec::with_capacity(NUM_AXES);
    for l in AXIS_LETTERS {
        axes.push(AxisPins::new(c, l)?);
    }
    let io = HalIo {
        motion,
        spindles,
        joints,
        axes,
    };

    let core = MotionCore::new(
        MotionConfig {
            num_joints: p.num_joints,
            num_extrajoints: p.num_extrajoints,
            num_spindles: p.num_spindles,
            num_misc_error: p.num_misc_error,
            unlock_joints_mask: p.unlock_joints_mask,
        },
        kins,
    );
    let events = core.events().clone();
    let cell = Arc::new(CoreCell {
        busy: AtomicBool::new(false),
        ctl: UnsafeCell::new(Controller {
            core,
            last: LastCommand::default(),
            served: 0,
        }),
    });
    let mailbox = Arc::new(Mailbox::default());

    // The shared-memory command channel (see `channel`).
    // The ring is created here (owned by motmod) and read here; clients
    // open its writing end.
    RingWriter::create(c, channel::CMD_RING, channel::RING_DEPTH, CMD_WORDS)?;
    let mut cmd_ring = RingReader::open(host.instance(), channel::CMD_RING)?;
    let mut reply_ring = RingWriter::create(
        c,
        channel::REPLY_RING,
        channel::RING_DEPTH,
        channel::REPLY_WORDS,
    )?;
    c.region(channel::LOCK, 16)?;
    let mut status = SeqLockWriter::create(c, channel::STATUS, STATUS_WORDS)?;
    let mut status_buf = [0u64; STATUS_WORDS];
    cell.with(|ctl| {
        channel::fill_status(&ctl.core, ctl.last, ctl.served, &mut status_buf);
        status.write(&status_buf);
    });

    if p.servo_period_nsec > p.base_period_nsec {
        host.create_thread("base-thread", p.base_period_nsec, p.base_thread_fp, None)?;
    }
    host.create_thread("servo-thread", p.servo_period_nsec, true, None)?;

    // The handler reads the inputs its commands depend on itself, so a
    // command sees this period's values even if it runs first.
    let h_inputs = (
        io.motion.enable.clone(),
        io.motion.jog_inhibit.clone(),
        io.motion.homing_inhibit.clone(),
    );
    let safe_amps: Vec<BOut> = io.joints.iter().map(|j| j.amp_enable.clone()).collect();

    let ctl_cell = cell.clone();
    let mut last_ns: Option<u64> = None;
    b.funct("motion-controller", true, move |ctx| {
        let now = ctx.now_ns();
        let period = last_ns.map_or(0, |l| now.wrapping_sub(l));
        last_ns = Some(now);
        io.motion.last_period.set(period as u32);
        ctl_cell.with(|ctl| {
            let core = &mut ctl.core;
            io.read(core);
            core.cycle(ctx.fperiod());
            io.write(core);
            channel::fill_status(core, ctl.last, ctl.served, &mut status_buf);
            status.write(&status_buf);
        });
    })?;

    let h_cell = cell.clone();
    let h_mailbox = mailbox.clone();
    let mut rec = [0u64; CMD_WORDS];
    b.funct("motion-command-handler", true, move |_ctx| {
        if !h_mailbox.has_command() && cmd_ring.is_empty() {
            return;
        }
        h_cell.with(|ctl| {
            let core = &mut ctl.core;
            core.inputs.enable = h_inputs.0.get();
            core.inputs.jog_inhibit = h_inputs.1.get();
            core.inputs.homing_inhibit = h_inputs.2.get();
            h_mailbox.serve(|cmd| core.command(cmd));
            // Channel commands: only as many as there is room to answer.
            for _ in 0..channel::MAX_PER_PERIOD {
                if reply_ring.len() >= reply_ring.capacity() || !cmd_ring.pop(&mut rec) {
                    break;
                }
                let (serial, result) = match channel::decode_command(&rec) {
                    Ok((serial, cmd)) => (serial, core.command(&cmd)),
                    Err((serial, error)) => (serial, Err(Reject::Malformed { error })),
                };
                reply_ring.push(&channel::encode_reply(serial, &result));
                ctl.last = LastCommand {
                    serial,
                    code: result.as_ref().err().map_or(0, channel::reject_code),
                };
                ctl.served += 1;
            }
        });
    })?;

    let registration = MOTION
        .register(
            &instance,
            "motmod",
            Arc::new(MotionLink {
                mailbox,
                events,
                num_joints: p.num_joints,
            }),
        )
        .map_err(|e| HalError::ModuleLoad {
            module: "motmod".into(),
            reason: e.to_string(),
        })?;
    let safe_cell = cell;
    b.on_safe_state(move || {
        let _keep = &registration;
        for a in &safe_amps {
            a.set(false);
        }
        safe_cell.with(|ctl| ctl.core.force_disable());
    });
    b.ready()
}
