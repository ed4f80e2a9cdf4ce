//! The hand-off of one command at a time from a non-realtime sender to the
//! realtime `motion-command-handler`, and of its result back.
//!
//! As in LinuxCNC there is at most one command in flight: a sender writes
//! the command, marks it posted and waits; the handler, once per period,
//! takes a posted command, applies it and posts the result. The realtime
//! side only does atomic loads, a compare-and-swap and plain copies of
//! `Copy` data: it never waits for the sender. Senders in several threads
//! queue on a mutex on their side.
//!
//! Other processes use the shared-memory channel of [`crate::channel`]
//! instead; the handler serves both, through the same
//! [`MotionCore::command`](crate::core::MotionCore::command).

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicU32, Ordering::*};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::command::{Command, CommandResult, Reject};

const EMPTY: u32 = 0;
const POSTED: u32 = 1;
const TAKEN: u32 = 2;
const ANSWERED: u32 = 3;

/// A one-slot command mailbox.
pub struct Mailbox {
    state: AtomicU32,
    cmd: UnsafeCell<Command>,
    reply: UnsafeCell<CommandResult>,
    senders: Mutex<()>,
}

// SAFETY: `cmd` is written only by the sender holding `senders` while the
// state is EMPTY and read by the handler only after it moved the state from
// POSTED to TAKEN (acquire, pairing with the sender's release store of
// POSTED). `reply` is written only by the handler while the state is TAKEN
// and read by the sender only after it saw ANSWERED (acquire, pairing with
// the handler's release store). So no cell is ever accessed by two threads
// at once.
unsafe impl Sync for Mailbox {}

impl Default for Mailbox {
    fn default() -> Self {
        Mailbox {
            state: AtomicU32::new(EMPTY),
            cmd: UnsafeCell::new(Command::Abort),
            reply: UnsafeCell::new(Ok(())),
            senders: Mutex::new(()),
        }
    }
}

impl std::fmt::Debug for Mailbox {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mailbox")
            .field("state", &self.state.load(Relaxed))
            .finish()
    }
}

impl Mailbox {
    /// Posts `cmd` and waits for the handler's answer. If the handler has
    /// not taken the command within `timeout` it is withdrawn and the
    /// result is [`Reject::Timeout`].
    pub fn send(&self, cmd: Command, timeout: Duration) -> CommandResult {
        let _g = self.senders.lock().unwrap_or_else(|e| e.into_inner());
        if self.state.load(Acquire) != EMPTY {
            // A handler died holding a command: the controller is gone.
            return Err(Reject::Timeout);
        }
        // SAFETY: state is EMPTY and we hold `senders` (see `impl Sync`).
        unsafe { *self.cmd.get() = cmd };
        self.state.store(POSTED, Release);
        let start = Instant::now();
        loop {
            match self.state.load(Acquire) {
                ANSWERED => {
                    // SAFETY: the handler is done with `reply`.
                    let r = unsafe { *self.reply.get() };
                    self.state.store(EMPTY, Release);
                    return r;
                }
                // Not taken in time: withdraw it (unless taken just now,
                // in which case the answer follows within a period).
                POSTED
                    if start.elapsed() > timeout
                        && self
                            .state
                            .compare_exchange(POSTED, EMPTY, AcqRel, Acquire)
                            .is_ok() =>
                {
                    return Err(Reject::Timeout);
                }
                TAKEN if start.elapsed() > timeout * 10 => return Err(Reject::Timeout),
                _ => {}
            }
            std::thread::sleep(Duration::from_micros(100));
        }
    }

    /// Whether a command waits to be taken (realtime side).
    pub fn has_command(&self) -> bool {
        self.state.load(Relaxed) == POSTED
    }

    /// Takes a posted command, if any, answers it with `apply` and returns
    /// true (realtime side).
    pub fn serve(&self, apply: impl FnOnce(&Command) -> CommandResult) -> bool {
        if self
            .state
            .compare_exchange(POSTED, TAKEN, Acquire, Relaxed)
            .is_err()
        {
            return false;
        }
        // SAFETY: we moved POSTED to TAKEN, so the sender does not touch
        // the cells until we store ANSWERED.
        let cmd = unsafe { *self.cmd.get() };
        let r = apply(&cmd);
        // SAFETY: still TAKEN: the sender reads the reply only once we
        // store ANSWERED below.
        unsafe { *self.reply.get() = r };
        self.state.store(ANSWERED, Release);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;

    #[test]
    fn commands_are_answered_in_order() {
        let mb = Arc::new(Mailbox::default());
        let stop = Arc::new(AtomicBool::new(false));
        let server = {
            let (mb, stop) = (mb.clone(), stop.clone());
            std::thread::spawn(move || {
                let mut seen = Vec::new();
                while !stop.load(Relaxed) {
                    mb.serve(|c| {
                        seen.push(*c);
                        match c {
                            Command::JogAbort { joint } if *joint < 0 => Err(Reject::NoSuchJoint {
                                joint: *joint,
                                num_joints: 3,
                            }),
                            _ => Ok(()),
                        }
                    });
                    std::thread::sleep(Duration::from_micros(50));
                }
                seen
            })
        };
        let t = Duration::from_secs(5);
        assert_eq!(mb.send(Command::Enable, t), Ok(()));
        assert_eq!(
            mb.send(Command::JogAbort { joint: -1 }, t),
            Err(Reject::NoSuchJoint {
                joint: -1,
                num_joints: 3
            })
        );
        assert_eq!(mb.send(Command::Disable, t), Ok(()));
        stop.store(true, Relaxed);
        let seen = server.join().unwrap();
        assert_eq!(
            seen,
            [
                Command::Enable,
                Command::JogAbort { joint: -1 },
                Command::Disable
            ]
        );
    }

    #[test]
    fn an_unserved_command_times_out_and_is_withdrawn() {
        let mb = Mailbox::default();
        assert_eq!(
            mb.send(Command::Enable, Duration::from_millis(20)),
            Err(Reject::Timeout)
        );
        assert!(!mb.has_command());
        assert!(!mb.serve(|_| Ok(())), "nothing left to take");
    }
}
