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
use hal_core::{
    Component, HalError, Host, Result, RingReader, RingWriter, RtComponentBuilder, SeqLockWriter,
};

use crate::channel::{self, LastCommand, CMD_WORDS, STATUS_WORDS};
use crate::command::Reject;
use crate::core::{MotionConfig, MotionCore};
use crate::kins::kinematics_for;
use crate::mailbox::Mailbox;

pub use handle::{MotionHandle, MotionLink, MOTION};
pub use params::parse_params;
use pins::{BIn, BOut, HalIo};

/// The `motmod` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "motmod",
    params: params::PARAMS,
    help: "motion controller (needs a kinematics module loaded first)",
    load,
};

/// What both functions use: the controller, the last command the
/// handler answered through the channel, and the status snapshot both
/// publish.
struct Controller {
    core: MotionCore,
    last: LastCommand,
    /// Channel commands answered so far.
    served: u64,
    /// The status snapshot's writer and the buffer it is filled in (set
    /// once the channel exists).
    status: Option<(SeqLockWriter, Box<[u64; STATUS_WORDS]>)>,
}

impl Controller {
    /// Writes the status snapshot from the controller as it is now.
    fn publish(&mut self) {
        let Controller {
            core,
            last,
            served,
            status,
        } = self;
        if let Some((writer, buf)) = status {
            channel::fill_status(core, *last, *served, &mut buf[..]);
            writer.write(&buf[..]);
        }
    }
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

impl CoreCell {
    /// A cell holding `core`, not yet claimed.
    fn new(core: MotionCore) -> CoreCell {
        CoreCell {
            busy: AtomicBool::new(false),
            ctl: UnsafeCell::new(Controller {
                core,
                last: LastCommand::default(),
                served: 0,
                status: None,
            }),
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
    let io = HalIo::new(b.component(), &p, kins.is_switchable())?;
    let core = MotionCore::new(
        MotionConfig {
            num_joints: p.num_joints,
            num_extrajoints: p.num_extrajoints,
            num_spindles: p.num_spindles,
            num_misc_error: p.num_misc_error,
            num_dio: p.dio.count,
            num_aio: p.aio.count,
            unlock_joints_mask: p.unlock_joints_mask,
            servo_period_nsec: p.servo_period_nsec as u64,
        },
        kins,
    );
    let events = core.events().clone();
    let cell = Arc::new(CoreCell::new(core));
    let mailbox = Arc::new(Mailbox::default());
    let channel = ChannelEnds::create(host, b.component(), &cell)?;

    if p.servo_period_nsec > p.base_period_nsec {
        host.create_thread("base-thread", p.base_period_nsec, p.base_thread_fp, None)?;
    }
    host.create_thread("servo-thread", p.servo_period_nsec, true, None)?;

    let mut handler = CommandHandler {
        inputs: (
            io.motion.enable.clone(),
            io.motion.jog_inhibit.clone(),
            io.motion.homing_inhibit.clone(),
        ),
        mailbox: mailbox.clone(),
        commands: channel.commands,
        replies: channel.replies,
        record: [0; CMD_WORDS],
    };
    let safe_amps: Vec<BOut> = io.joints.iter().map(|j| j.amp_enable.clone()).collect();
    add_controller(&mut b, io, cell.clone())?;
    let h_cell = cell.clone();
    b.funct("motion-command-handler", true, move |_ctx| {
        handler.run(&h_cell)
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

/// The ends of the shared-memory channel (see [`crate::channel`]) that
/// `motmod` owns.
struct ChannelEnds {
    /// Where clients' commands arrive.
    commands: RingReader,
    /// Where the answers go.
    replies: RingWriter,
}

impl ChannelEnds {
    /// Creates the channel's regions (the command ring is created here,
    /// owned by motmod, and read here; clients open its writing end) and
    /// publishes the first status (the writer then stays with the
    /// controller).
    fn create(host: &Host, c: &Component, cell: &CoreCell) -> Result<ChannelEnds> {
        RingWriter::create(c, channel::CMD_RING, channel::RING_DEPTH, CMD_WORDS)?;
        let commands = RingReader::open(host.instance(), channel::CMD_RING)?;
        let replies = RingWriter::create(
            c,
            channel::REPLY_RING,
            channel::RING_DEPTH,
            channel::REPLY_WORDS,
        )?;
        c.region(channel::LOCK, 16)?;
        let status = SeqLockWriter::create(c, channel::STATUS, STATUS_WORDS)?;
        let buf = Box::new([0u64; STATUS_WORDS]);
        cell.with(|ctl| {
            ctl.status = Some((status, buf));
            ctl.publish();
        });
        Ok(ChannelEnds { commands, replies })
    }
}

/// Exports `motion-controller`: the pins in, one cycle, the pins out, the
/// status published.
fn add_controller(b: &mut RtComponentBuilder<'_>, io: HalIo, cell: Arc<CoreCell>) -> Result<()> {
    let mut last_ns: Option<u64> = None;
    b.funct("motion-controller", true, move |ctx| {
        let now = ctx.now_ns();
        let period = last_ns.map_or(0, |l| now.wrapping_sub(l));
        last_ns = Some(now);
        io.motion.last_period.set(period as u32);
        cell.with(|ctl| {
            let core = &mut ctl.core;
            io.read(core);
            core.cycle(ctx.fperiod());
            io.write(core);
            ctl.publish();
        });
    })
}

/// What `motion-command-handler` uses.
struct CommandHandler {
    /// `motion.enable`, `motion.jog-inhibit`, `motion.homing-inhibit`:
    /// read by the handler itself, so a command sees this period's values
    /// even if it runs first.
    inputs: (BIn, BIn, BIn),
    mailbox: Arc<Mailbox>,
    commands: RingReader,
    replies: RingWriter,
    /// The command record being read.
    record: [u64; CMD_WORDS],
}

impl CommandHandler {
    /// One period: the in-process command, then the channel's commands
    /// (only as many as there is room to answer). The status is published
    /// before the answers go out, so a client that has its answer never
    /// reads a status older than its command (motion-cmd takes the goal
    /// of a queued move from it).
    fn run(&mut self, cell: &CoreCell) {
        if !self.mailbox.has_command() && self.commands.is_empty() {
            return;
        }
        cell.with(|ctl| {
            let core = &mut ctl.core;
            core.inputs.enable = self.inputs.0.get();
            core.inputs.jog_inhibit = self.inputs.1.get();
            core.inputs.homing_inhibit = self.inputs.2.get();
            self.mailbox.serve(|cmd| core.command(cmd));
            let mut answers = [[0u64; channel::REPLY_WORDS]; channel::MAX_PER_PERIOD];
            let mut answered = 0;
            let room = self.replies.capacity() - self.replies.len();
            while answered < channel::MAX_PER_PERIOD.min(room)
                && self.commands.pop(&mut self.record)
            {
                let (serial, result) = match channel::decode_command(&self.record) {
                    Ok((serial, cmd)) => (serial, ctl.core.command(&cmd)),
                    Err((serial, error)) => (serial, Err(Reject::Malformed { error })),
                };
                answers[answered] = channel::encode_reply(serial, &result);
                answered += 1;
                ctl.last = LastCommand {
                    serial,
                    code: result.as_ref().err().map_or(0, channel::reject_code),
                };
                ctl.served += 1;
            }
            if answered > 0 {
                ctl.publish();
            }
            for answer in &answers[..answered] {
                self.replies.push(answer);
            }
        });
    }
}
