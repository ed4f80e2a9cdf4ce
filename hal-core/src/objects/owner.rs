//! Whether the process that made a user-space component is still alive,
//! and the removal of components whose process is gone.
//!
//! A user-space component's process holds an open-file-description lock
//! (`F_OFD_SETLK`) on one byte of the segment file, at the offset of the
//! component's record, for as long as the component exists. The kernel drops
//! the lock when the last descriptor of that open file goes away, which
//! happens however the process ends: return from main, panic, SIGKILL. A
//! byte nobody holds therefore marks a component whose owner died; the host
//! checks for such components periodically and removes them with everything
//! they own, as if they had exited cleanly. Unlike a PID, a lock cannot be
//! confused by PID reuse or PID namespaces.
//!
//! The lock is taken and dropped inside the transaction that creates or
//! removes the record, so a checker (which also works inside a transaction)
//! never sees a live component without its lock, and a record reused for a
//! new component never finds the old owner's lock still there.

use std::fs::{File, OpenOptions};
use std::os::fd::AsFd;
use std::sync::atomic::Ordering::*;

use super::component::{remove_component_tx, ComponentKind};
use super::list;
use super::Instance;
use crate::error::{HalError, Result};
use crate::shm::{CompRec, Segment};

fn byte_lock(kind: libc::c_short, off: u64) -> libc::flock {
    libc::flock {
        l_type: kind,
        l_whence: libc::SEEK_SET as libc::c_short,
        l_start: off as libc::off_t,
        l_len: 1,
        // Must be zero for open-file-description locks.
        l_pid: 0,
    }
}

/// Marks this process as the owner of the component record at `off`.
pub(crate) fn claim(seg: &Segment, off: u64) -> Result<()> {
    let lock = byte_lock(libc::F_WRLCK as libc::c_short, off);
    nix::fcntl::fcntl(seg.file().as_fd(), nix::fcntl::FcntlArg::F_OFD_SETLK(&lock))
        .map(drop)
        .map_err(|source| HalError::Os {
            op: "locking the component's owner byte in the segment file",
            source,
        })
}

/// Gives up ownership of the component record at `off`. Releasing a byte
/// this process does not hold changes nothing.
pub(crate) fn release(seg: &Segment, off: u64) {
    let lock = byte_lock(libc::F_UNLCK as libc::c_short, off);
    let _ = nix::fcntl::fcntl(seg.file().as_fd(), nix::fcntl::FcntlArg::F_OFD_SETLK(&lock));
}

/// A separate open file description of the segment file, from which the
/// locks of every process (this one included) are visible.
struct Probe {
    file: File,
}

impl Probe {
    fn open(seg: &Segment) -> Result<Probe> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(seg.path())
            .map_err(|e| HalError::io("opening the segment to check owners", seg.path(), e))?;
        Ok(Probe { file })
    }

    /// Whether some process holds the owner byte at `off`.
    fn held(&self, off: u64) -> Result<bool> {
        let mut lock = byte_lock(libc::F_WRLCK as libc::c_short, off);
        nix::fcntl::fcntl(
            self.file.as_fd(),
            nix::fcntl::FcntlArg::F_OFD_GETLK(&mut lock),
        )
        .map_err(|source| HalError::Os {
            op: "testing a component's owner byte in the segment file",
            source,
        })?;
        Ok(lock.l_type != libc::F_UNLCK as libc::c_short)
    }
}

impl Instance {
    /// Removes every user-space component whose process has ended without
    /// removing it (killed, crashed), with its pins, params, functions and
    /// regions; pins it had linked are unlinked first, keeping their
    /// signals. Returns the names of the components removed. The host calls
    /// this periodically; anyone may.
    pub fn reap_dead_components(&self) -> Result<Vec<String>> {
        let probe = Probe::open(&self.seg)?;
        self.tx(|tx| {
            let seg = tx.seg();
            let mut dead = Vec::new();
            for item in list::iter::<CompRec>(seg, &tx.header().comps) {
                let (off, c) = item?;
                if ComponentKind::from_code(c.kind.load(Relaxed)) == ComponentKind::User
                    && !probe.held(off)?
                {
                    dead.push((off, c.name.get()));
                }
            }
            for (off, _) in &dead {
                remove_component_tx(tx, *off)?;
            }
            Ok(dead.into_iter().map(|(_, name)| name).collect())
        })
    }
}
