//! Where an instance's files live, and how they are made.
//!
//! The shared-memory segment is `/dev/shm/hal-NAME`, created exclusively
//! by the host (a squatter's file there is refused, a dead host's removed
//! under the instance lock). Every other runtime file — the host's lock,
//! its control socket, a detached host's log, the launcher's task socket —
//! lives in the private runtime directory ([`runtime_dir`]; never by name
//! in /tmp). Segment, socket, lock and log belong to the hal group
//! ([`HalGroup`]) with mode 0660 whatever the umask.

mod dir;
mod files;
mod group;

use std::os::unix::fs::OpenOptionsExt;
use std::path::PathBuf;

use crate::error::Result;

pub use dir::{ensure_runtime_dir, runtime_dir, SYSTEM_RUNTIME_DIR};
pub use files::{bind_socket, create_log};
pub use group::{denied, HalGroup, DEFAULT_GROUP};

pub(crate) use files::{create_new, open_error, open_existing};
pub(crate) use group::share_fd;

/// The shared-memory segment (a file in /dev/shm).
pub fn segment(instance: &str) -> PathBuf {
    PathBuf::from(format!("/dev/shm/hal-{instance}"))
}

/// Fails with the hal group's advice if the segment of `instance` exists
/// but this user may not open it: why a running instance is out of reach.
pub fn segment_access(instance: &str) -> Result<()> {
    let path = segment(instance);
    match std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC)
        .open(&path)
    {
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
            Err(denied("opening shared memory segment", &path))
        }
        _ => Ok(()),
    }
}

/// `hal-<instance><suffix>` in the runtime directory.
pub fn runtime_file(instance: &str, suffix: &str) -> Result<PathBuf> {
    Ok(runtime_dir()?.join(format!("hal-{instance}{suffix}")))
}

/// The lock file the host holds with flock while alive.
pub fn lock(instance: &str) -> Result<PathBuf> {
    runtime_file(instance, ".lock")
}

/// The host's control socket.
pub fn socket(instance: &str) -> Result<PathBuf> {
    runtime_file(instance, ".sock")
}

/// Where a detached host (`realtime start`) writes its messages.
pub fn log(instance: &str) -> Result<PathBuf> {
    runtime_file(instance, ".log")
}
