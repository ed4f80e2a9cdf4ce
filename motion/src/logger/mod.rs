//! `motion-logger`: stands in for `motmod` and logs every command it
//! receives, as LinuxCNC's motion-logger does for its motion tests.
//!
//! [`Logger::create`] makes motmod's command channel (the regions of
//! [`crate::channel`]) on a user component of its own, so task and
//! `motion-cmd` attach to it as they would to motmod. [`Logger::serve`]
//! takes each waiting command, answers it as motion would, publishes the
//! status first (as motmod does) and hands one [`line::line`] per command
//! to the caller. Behind the channel runs a motion core that never moves:
//! state commands (enable, modes, joint and axis settings, overrides)
//! change it and are answered with its verdict; queued moves (lines,
//! arcs, dwells, probes) are logged and accepted without being planned,
//! so the machine stays in position; homing marks joints homed at once,
//! as LinuxCNC's logger does.

pub mod line;

use std::sync::Arc;

use hal_core::{Component, Instance, Result, RingReader, RingWriter, SeqLockWriter};

use crate::channel::{
    self, decode_command, encode_reply, fill_status, LastCommand, CMD_WORDS, REPLY_WORDS,
    STATUS_WORDS,
};
use crate::command::{Command, Reject};
use crate::kins::trivkins::Trivkins;
use crate::kins::KinematicsType;
use crate::sizes::MAX_JOINTS;
use crate::{MotionConfig, MotionCore};

/// The program's help text (its man page is made from it).
pub const USAGE: &str = "\
usage: motion-logger [--instance NAME] [LOGFILE]

Stands in for the motion controller (motmod) and logs every motion command
it receives, one line each, to LOGFILE (created or emptied when the first
line comes), or to standard output without one. Task, halui and
motion-cmd attach to it as to motmod; each command is answered as motion
would answer it. Queued moves (lines, arcs, dwells, probes) are accepted
and logged but not run, so the machine stays in position, and homing
marks joints homed at once. HAL files load it with
'loadusr -W motion-logger out.motion-logger', in place of 'loadrt motmod'.

Lines follow LinuxCNC's motion-logger: the command's name and its fields
as name=value with numbers as printf's %.6g ('SET_LINE x=1, ..., w=9,
id=2, motion_type=2, vel=1.5, ini_maxvel=4, acc=1000, turn=-1',
'JOINT_HOME joint=-1', 'COORD'). SET_LINE's turn, LinuxCNC's locking
indexer joint, is always -1 here (motion knows the indexer from
SET_AXIS_LOCKING_JOINT); SPINDLE_CSS writes no line of its own: SPINDLE_ON shows its factor and offset ('SPINDLE_ON speed=500.000000,
css_factor=0.000000, xoffset=0.000000'), as LinuxCNC's command carries
them; commands LinuxCNC's logger does not know are named in its style
with all their fields.

options:
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

pins:
  motion-logger.reopen-log bit io  set it to close the log file: the next
                                   line starts it anew; cleared when done";

/// The stand-in motion controller and its channel.
pub struct Logger {
    core: MotionCore,
    commands: RingReader,
    replies: RingWriter,
    status: SeqLockWriter,
    buf: Box<[u64; STATUS_WORDS]>,
    record: [u64; CMD_WORDS],
    last: LastCommand,
    served: u64,
}

impl std::fmt::Debug for Logger {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Logger")
            .field("served", &self.served)
            .finish()
    }
}

impl Logger {
    /// Makes motmod's channel regions on `comp` (a component of `inst`)
    /// and publishes the first status. Fails as motmod's load would if a
    /// motion controller already has them.
    pub fn create(inst: &Instance, comp: &Component) -> Result<Logger> {
        RingWriter::create(comp, channel::CMD_RING, channel::RING_DEPTH, CMD_WORDS)?;
        let commands = RingReader::open(inst, channel::CMD_RING)?;
        let replies =
            RingWriter::create(comp, channel::REPLY_RING, channel::RING_DEPTH, REPLY_WORDS)?;
        comp.region(channel::LOCK, 16)?;
        let status = SeqLockWriter::create(comp, channel::STATUS, STATUS_WORDS)?;
        let mut logger = Logger {
            core: stand_in_core()?,
            commands,
            replies,
            status,
            buf: Box::new([0u64; STATUS_WORDS]),
            record: [0u64; CMD_WORDS],
            last: LastCommand::default(),
            served: 0,
        };
        logger.tick(0.001);
        Ok(logger)
    }

    /// Answers every waiting command there is room to answer; `log` gets
    /// each one's line. Returns how many were served.
    pub fn serve(&mut self, log: &mut dyn FnMut(&str)) -> usize {
        let mut n = 0;
        while self.replies.len() < self.replies.capacity() && self.commands.pop(&mut self.record) {
            let (serial, result) = match decode_command(&self.record) {
                Ok((serial, cmd)) => {
                    if let Some(text) = self.text_of(&cmd) {
                        log(&text);
                    }
                    (serial, self.apply(&cmd))
                }
                Err((serial, error)) => {
                    log(&format!("ERROR: unknown command ({error})"));
                    (serial, Err(Reject::Malformed { error }))
                }
            };
            self.last = LastCommand {
                serial,
                code: result.as_ref().err().map_or(0, channel::reject_code),
            };
            self.served += 1;
            // The status first: a sender that has its answer never reads
            // a status older than its command.
            self.publish();
            self.replies.push(&encode_reply(serial, &result));
            n += 1;
        }
        n
    }

    /// One period of the core: joints follow their commands (nothing
    /// moves them), the status is published.
    pub fn tick(&mut self, period: f64) {
        for j in 0..self.core.num_joints() {
            let cmd = self.core.joint(j).motor_pos_cmd;
            if let Some(input) = self.core.joint_inputs.get_mut(j) {
                input.motor_pos_fb = cmd;
            }
        }
        self.core.inputs.enable = true;
        self.core.cycle(period);
        self.publish();
    }

    fn publish(&mut self) {
        fill_status(&self.core, self.last, self.served, &mut self.buf[..]);
        self.status.write(&self.buf[..]);
    }

    /// The log line of `cmd`, if it has one of its own. LinuxCNC's
    /// SPINDLE_ON carries the constant-surface-speed factor and X offset
    /// that ours sends before it as SPINDLE_CSS: that one writes no line,
    /// and SPINDLE_ON's line shows what the spindle then has, as
    /// LinuxCNC's logger writes it.
    fn text_of(&self, cmd: &Command) -> Option<String> {
        match *cmd {
            Command::SpindleCss { .. } => None,
            Command::SpindleOn { spindle, speed, .. } => {
                let n = usize::try_from(spindle)
                    .ok()
                    .filter(|&n| n < crate::sizes::MAX_SPINDLES)
                    .unwrap_or(0);
                let s = self.core.spindle(n);
                Some(line::spindle_on(speed, s.css_factor, s.css_x_offset))
            }
            _ => Some(line::line(cmd)),
        }
    }

    /// What the stand-in does with `cmd`, and its answer.
    fn apply(&mut self, cmd: &Command) -> std::result::Result<(), Reject> {
        match *cmd {
            Command::Line { .. }
            | Command::Circle { .. }
            | Command::Dwell { .. }
            | Command::Probe { .. } => Ok(()),
            Command::Home { joint } | Command::Unhome { joint } => {
                let homed = matches!(cmd, Command::Home { .. });
                let n = self.core.num_joints();
                match usize::try_from(joint) {
                    Ok(j) if j < n => self.core.set_homed(j, homed),
                    Ok(_) => {
                        return Err(Reject::NoSuchJoint {
                            joint,
                            num_joints: n,
                        })
                    }
                    Err(_) => (0..n).for_each(|j| self.core.set_homed(j, homed)),
                }
                Ok(())
            }
            _ => self.core.command(cmd),
        }
    }
}

/// Joints of the stand-in: nine, one per world axis.
pub const JOINTS: usize = 9;

/// A core of [`JOINTS`] joints, identity kinematics over X Y Z A B C U V W.
fn stand_in_core() -> Result<MotionCore> {
    let kins = Trivkins::new("xyzabcuvw", KinematicsType::Identity).map_err(|e| {
        hal_core::HalError::ModuleParam {
            module: "motion-logger".into(),
            param: "kinematics".into(),
            reason: e.to_string(),
        }
    })?;
    Ok(MotionCore::new(
        MotionConfig {
            num_joints: JOINTS.min(MAX_JOINTS),
            ..MotionConfig::default()
        },
        Arc::new(kins),
    ))
}

#[cfg(test)]
mod tests;
