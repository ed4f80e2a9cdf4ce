//! What the realtime side and a fieldbus's non-realtime helper share per
//! drive: atomics only, so neither ever waits for the other.

use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering::*};

/// Where a node's restart (NMT reset and configuration again, after a
/// communication fault and an explicit fault reset) stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Restart {
    /// Nothing asked.
    Idle,
    /// The realtime side asked; the helper has not started.
    Requested,
    /// The helper is bringing the node up.
    Running,
    /// The node is operational again.
    Done,
    /// It could not be brought up (the helper logged why).
    Failed,
}

impl Restart {
    fn from_u8(v: u8) -> Restart {
        match v {
            1 => Restart::Requested,
            2 => Restart::Running,
            3 => Restart::Done,
            4 => Restart::Failed,
            _ => Restart::Idle,
        }
    }
}

/// One drive's shared state.
#[derive(Debug, Default)]
pub struct DriveShared {
    restart: AtomicU8,
    diagnose: AtomicBool,
    /// 0x1001, as the helper last read it.
    pub error_register: AtomicU32,
}

impl DriveShared {
    /// Where the restart stands.
    pub fn restart(&self) -> Restart {
        Restart::from_u8(self.restart.load(Acquire))
    }

    /// Moves the restart on.
    pub fn set_restart(&self, r: Restart) {
        self.restart.store(r as u8, Release);
    }

    /// Asks the helper to read the drive's error register and history.
    pub fn request_diagnosis(&self) {
        self.diagnose.store(true, Release);
    }

    /// Takes a diagnosis request.
    pub fn take_diagnosis(&self) -> bool {
        self.diagnose.swap(false, AcqRel)
    }
}
