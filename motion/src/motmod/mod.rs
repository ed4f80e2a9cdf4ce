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

mod handle;
mod params;
mod pins;

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, Ordering::*};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{HalError, Host, Result, RingReader, RingWriter, SeqLockWriter};

use crate::channel::{self, LastCommand, CMD_WORDS, STATUS_WORDS};
use crate::command::Reject;
use crate::core::{MotionConfig, MotionCore};
use crate::kins::{kinematics_for, AXIS_LETTERS, NUM_AXES};
use crate::mailbox::Mailbox;

pub use handle::{MotionHandle, MotionLink, COMMAND_TIMEOUT, MOTION};
pub use params::{parse_params, IoNames, MotmodParams};
use pins::{AxisPins, BOut, HalIo, JointPins, MotionPins, SpindlePins};

/// The `motmod` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "motmod",
    params: params::PARAMS,
    help: "motion controller (needs a kinematics module loaded first)",
    load,
};

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
            servo_period_nsec: p.servo_period_nsec as u64,
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
