//! Whether a host is alive, told by a lock file it holds with flock. A PID
//! would lie across PID namespaces and after reuse; a held flock cannot
//! outlive its holder.

use std::fs::File;
use std::os::fd::AsRawFd;
use std::os::unix::fs::MetadataExt;

use crate::error::{HalError, Result};
use crate::paths;

fn flock(f: &File, op: libc::c_int) -> std::io::Result<()> {
    // SAFETY: flock on a file descriptor we own; no memory is involved.
    let rc = unsafe { libc::flock(f.as_raw_fd(), op | libc::LOCK_NB) };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// True if some process holds the instance's lock file.
pub(crate) fn host_alive(instance: &str) -> Result<bool> {
    let path = match paths::lock(instance) {
        Ok(p) => p,
        // No runtime directory of our own: no host of ours. A host of
        // root or the hal group is in /run/hal, which we could not use.
        Err(HalError::NoRuntimeDir { .. }) => return Ok(false),
        Err(e) => return Err(e),
    };
    let f = match paths::open_existing(&path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
            return Err(paths::denied("opening host lock file", &path))
        }
        Err(e) => return Err(paths::open_error("opening host lock file", &path, e)),
    };
    match flock(&f, libc::LOCK_SH) {
        // We got it, so nobody holds it exclusively: no host. Dropping the
        // file releases our shared lock.
        Ok(()) => Ok(false),
        Err(e) if e.raw_os_error() == Some(libc::EWOULDBLOCK) => Ok(true),
        Err(e) => Err(HalError::io("testing host lock file", &path, e)),
    }
}

/// The exclusive lock a host holds for its whole life.
pub(crate) struct HostLock {
    file: File,
    path: std::path::PathBuf,
}

impl HostLock {
    /// Takes the instance's lock, or fails with `AlreadyRunning`. Creates
    /// the runtime directory if needed; a new lock file is created
    /// exclusively and given to the hal group, one left by a dead host is
    /// reused only if it is a plain file (a planted link or FIFO is
    /// refused).
    pub(crate) fn acquire(instance: &str) -> Result<HostLock> {
        paths::ensure_runtime_dir()?;
        let path = paths::lock(instance)?;
        let group = paths::HalGroup::lookup();
        // The file may be unlinked by an exiting host between our open and
        // our flock; then we would hold a lock on a dead inode. Retry until
        // the locked file is the one at the path.
        for _ in 0..100 {
            let (file, created) = match paths::create_new(&path) {
                Ok(f) => (f, true),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    match paths::open_existing(&path) {
                        Ok(f) => (f, false),
                        // Removed meanwhile by an exiting host: try again.
                        Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
                            return Err(paths::denied("opening host lock file", &path))
                        }
                        Err(e) => {
                            return Err(paths::open_error("opening host lock file", &path, e))
                        }
                    }
                }
                Err(e) => return Err(HalError::io("creating host lock file", &path, e)),
            };
            match flock(&file, libc::LOCK_EX) {
                Ok(()) => {}
                Err(e) if e.raw_os_error() == Some(libc::EWOULDBLOCK) => {
                    return Err(HalError::AlreadyRunning {
                        instance: instance.to_string(),
                    })
                }
                Err(e) => return Err(HalError::io("locking host lock file", &path, e)),
            }
            let held = file
                .metadata()
                .map_err(|e| HalError::io("checking host lock file", &path, e))?;
            match std::fs::symlink_metadata(&path) {
                Ok(m) if m.ino() == held.ino() && m.dev() == held.dev() => {
                    // A dead host's file keeps its owner; ours (or root's)
                    // is given to the group, so members can test it.
                    if created
                        || held.uid() == nix::unistd::geteuid().as_raw()
                        || nix::unistd::geteuid().is_root()
                    {
                        paths::share_fd(&file, &group, &path)?;
                    }
                    return Ok(HostLock { file, path });
                }
                _ => continue,
            }
        }
        Err(HalError::io(
            "locking host lock file",
            &path,
            std::io::Error::other("the lock file keeps changing under us"),
        ))
    }
}

impl Drop for HostLock {
    fn drop(&mut self) {
        // Unlink while still holding the lock, so that nobody can lock the
        // old inode after we are gone and think they are the host.
        let _ = std::fs::remove_file(&self.path);
        let _ = &self.file;
    }
}
