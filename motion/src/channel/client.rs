//! [`MotionClient`]: sends commands and reads status from any process
//! attached to the instance.

use std::fmt;
use std::sync::atomic::Ordering::*;
use std::time::{Duration, Instant};

use hal_core::{HalError, Instance, Region, RingReader, RingWriter, SeqLockReader};

use super::{
    decode_reply, decode_status, encode_command, CMD_RING, LOCK, REPLY_RING, REPLY_WORDS, STATUS,
    STATUS_WORDS,
};
use crate::command::{reject_code, Command, Reject, WireError};
use crate::status::MotionStatus;

/// How long a command may wait for the handler (LinuxCNC's default
/// `[EMCMOT]COMM_TIMEOUT`).
pub const COMMAND_TIMEOUT: Duration = Duration::from_secs(1);

/// A command the controller accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Accepted {
    /// Its serial number.
    pub serial: u64,
}

/// A command the controller refused (or that got no answer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rejected {
    /// Its serial number.
    pub serial: u64,
    /// Why.
    pub reason: Reject,
}

impl Rejected {
    /// The reason code on the wire.
    pub fn code(&self) -> u64 {
        reject_code(&self.reason)
    }
}

impl fmt::Display for Rejected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "rejected (serial {}, code {}): {}",
            self.serial,
            self.code(),
            self.reason
        )
    }
}

impl std::error::Error for Rejected {}

/// Errors reaching the channel at all.
#[derive(Debug)]
pub enum ClientError {
    /// The instance is not running, or has no `motmod` loaded.
    Hal(HalError),
    /// The status snapshot could not be read consistently or is corrupt.
    Status(WireError),
}

impl fmt::Display for ClientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClientError::Hal(HalError::NotFound { kind: "region", .. }) => {
                f.write_str("motmod is not loaded in this HAL instance")
            }
            ClientError::Hal(e) => write!(f, "{e}"),
            ClientError::Status(e) => write!(f, "status: {e}"),
        }
    }
}

impl std::error::Error for ClientError {}

impl From<HalError> for ClientError {
    fn from(e: HalError) -> Self {
        ClientError::Hal(e)
    }
}

/// A sender of commands and reader of status from any process attached to
/// the instance. One client at a time holds the sender lock while it sends
/// a command and waits for its answer.
pub struct MotionClient {
    cmd: RingWriter,
    reply: RingReader,
    status: SeqLockReader,
    lock: Region,
    timeout: Duration,
    _inst: Instance,
}

impl std::fmt::Debug for MotionClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MotionClient")
            .field("timeout", &self.timeout)
            .finish()
    }
}

/// A per-process counter so clients of one process hold distinct tokens.
static NEXT_TOKEN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl MotionClient {
    /// Attaches to the running HAL instance `instance` and its `motmod`.
    pub fn attach(instance: &str) -> Result<MotionClient, ClientError> {
        MotionClient::open(&Instance::attach(instance)?)
    }

    /// Opens the channel of the `motmod` of an instance already attached.
    pub fn open(inst: &Instance) -> Result<MotionClient, ClientError> {
        Ok(MotionClient {
            cmd: RingWriter::open(inst, CMD_RING)?,
            reply: RingReader::open(inst, REPLY_RING)?,
            status: SeqLockReader::open(inst, STATUS)?,
            lock: inst.region(LOCK)?,
            timeout: COMMAND_TIMEOUT,
            _inst: inst.clone(),
        })
    }

    /// Sets how long [`send`](Self::send) waits for an answer.
    pub fn with_timeout(mut self, timeout: Duration) -> MotionClient {
        self.timeout = timeout;
        self
    }

    /// Takes the sender lock (word 0 of the lock region), breaking it if
    /// its holder's process is gone. False on timeout.
    fn lock(&self, token: u64, deadline: Instant) -> bool {
        let w = &self.lock.words()[0];
        loop {
            match w.compare_exchange(0, token, Acquire, Relaxed) {
                Ok(_) => return true,
                Err(holder) => {
                    let pid = holder >> 32;
                    let alive = std::path::Path::new(&format!("/proc/{pid}")).exists();
                    if !alive {
                        let _ = w.compare_exchange(holder, 0, AcqRel, Relaxed);
                        continue;
                    }
                }
            }
            if Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    fn unlock(&self, token: u64) {
        let _ = self.lock.words()[0].compare_exchange(token, 0, Release, Relaxed);
    }

    /// Sends `cmd` and waits for its answer. [`Reject::Timeout`] if the
    /// controller did not answer in time (its thread is not running, or
    /// another sender held the channel).
    pub fn send(&mut self, cmd: Command) -> Result<Accepted, Rejected> {
        let deadline = Instant::now() + self.timeout;
        let token = (u64::from(std::process::id()) << 32)
            | (NEXT_TOKEN.fetch_add(1, Relaxed) & 0xffff_ffff).max(1);
        if !self.lock(token, deadline) {
            return Err(Rejected {
                serial: 0,
                reason: Reject::Timeout,
            });
        }
        let r = self.send_locked(cmd, deadline);
        self.unlock(token);
        r
    }

    fn send_locked(&mut self, cmd: Command, deadline: Instant) -> Result<Accepted, Rejected> {
        // Drop answers left by a sender that gave up waiting.
        let mut buf = [0u64; REPLY_WORDS];
        while self.reply.pop(&mut buf) {}
        let serial = {
            let s = self.lock.words()[1].fetch_add(1, AcqRel).wrapping_add(1);
            if s == 0 {
                self.lock.words()[1].fetch_add(1, AcqRel).wrapping_add(1)
            } else {
                s
            }
        };
        let timeout = Rejected {
            serial,
            reason: Reject::Timeout,
        };
        let rec = encode_command(serial, &cmd);
        while !self.cmd.push(&rec) {
            if Instant::now() > deadline {
                return Err(timeout);
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        loop {
            while self.reply.pop(&mut buf) {
                match decode_reply(&buf) {
                    Ok((s, r)) if s == serial => {
                        return match r {
                            Ok(()) => Ok(Accepted { serial }),
                            Err(reason) => Err(Rejected { serial, reason }),
                        }
                    }
                    // Someone else's or corrupt: not ours.
                    _ => {}
                }
            }
            if Instant::now() > deadline {
                return Err(timeout);
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    /// A consistent snapshot of the controller's status.
    pub fn status(&self) -> Result<MotionStatus, ClientError> {
        let mut w = [0u64; STATUS_WORDS];
        if !self.status.read(&mut w) {
            return Err(ClientError::Status(WireError::BadStatus));
        }
        decode_status(&w).map_err(ClientError::Status)
    }
}
