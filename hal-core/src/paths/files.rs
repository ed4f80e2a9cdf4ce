//! Making runtime files so that nothing planted at their names is followed:
//! new files with `O_CREAT | O_EXCL | O_NOFOLLOW`, existing ones with
//! `O_NOFOLLOW` and a check of what was opened; each given to the hal group
//! on its descriptor.

use std::fs::{File, OpenOptions};
use std::os::fd::{AsFd, AsRawFd};
use std::os::unix::fs::{FileTypeExt, MetadataExt, OpenOptionsExt};
use std::os::unix::net::UnixListener;
use std::path::Path;

use nix::fcntl::AtFlags;
use nix::unistd::{fchownat, geteuid, Gid};

use super::group::{share_fd, HalGroup};
use crate::error::{HalError, Result};

/// Creates `path`, which must not exist, for reading and writing; a link or
/// any file already there makes it fail with `AlreadyExists`. The file is
/// private (0600) until [`share_fd`] gives it to the group.
pub(crate) fn create_new(path: &Path) -> std::io::Result<File> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .create_new(true)
        .mode(0o600)
        .custom_flags(libc::O_NOFOLLOW | libc::O_CLOEXEC)
        .open(path)
}

/// What [`open_existing`] found at a name instead of a regular file.
#[derive(Debug)]
struct NotRegularFile;

impl std::fmt::Display for NotRegularFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("not a regular file")
    }
}

impl std::error::Error for NotRegularFile {}

/// Opens an existing regular file read-only without following a link at
/// `path` and without blocking on a FIFO planted there.
pub(crate) fn open_existing(path: &Path) -> std::io::Result<File> {
    let f = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC)
        .open(path)?;
    if !f.metadata()?.is_file() {
        return Err(std::io::Error::other(NotRegularFile));
    }
    Ok(f)
}

/// The error of opening runtime file `path` (for `op`) without following
/// a link: a link (`ELOOP` under `O_NOFOLLOW`) or anything but a regular
/// file at the name is [`HalError::PlantedFile`], saying why it is
/// refused; other failures are [`HalError::Io`].
pub(crate) fn open_error(op: &'static str, path: &Path, e: std::io::Error) -> HalError {
    let reason = if e.raw_os_error() == Some(libc::ELOOP) {
        "it is a symbolic link, and runtime files are never opened through one \
         (no HAL host makes it: remove it once you know who planted it)"
    } else if e
        .get_ref()
        .is_some_and(|inner| inner.is::<NotRegularFile>())
    {
        "it is not a regular file (no HAL host makes it: remove it once you know who \
         planted it)"
    } else {
        return HalError::io(op, path, e);
    };
    HalError::PlantedFile {
        op,
        path: path.to_path_buf(),
        reason,
    }
}

/// Creates a fresh log file at `path` (one left by an earlier host is
/// removed first), opened for appending and given to the hal group.
pub fn create_log(path: &Path) -> Result<File> {
    match std::fs::remove_file(path) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(HalError::io("removing the old log", path, e)),
    }
    let f = OpenOptions::new()
        .append(true)
        .create_new(true)
        .mode(0o600)
        .custom_flags(libc::O_NOFOLLOW | libc::O_CLOEXEC)
        .open(path)
        .map_err(|e| HalError::io("creating the log", path, e))?;
    share_fd(&f, &HalGroup::lookup(), path)?;
    Ok(f)
}

/// Binds a listening socket at `path`, replacing a stale one: the caller
/// must hold the instance's lock, which says nobody else serves there.
/// `bind` never follows a link; the socket file is then checked through an
/// `O_PATH` descriptor and given to the hal group with mode 0660 (a client
/// needs write permission to connect).
pub fn bind_socket(path: &Path) -> Result<UnixListener> {
    match std::fs::remove_file(path) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(HalError::io("removing a stale socket", path, e)),
    }
    let listener =
        UnixListener::bind(path).map_err(|e| HalError::io("binding the socket", path, e))?;
    let node = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_PATH | libc::O_NOFOLLOW | libc::O_CLOEXEC)
        .open(path)
        .map_err(|e| HalError::io("opening the socket just bound", path, e))?;
    let meta = node
        .metadata()
        .map_err(|e| HalError::io("examining the socket just bound", path, e))?;
    if !meta.file_type().is_socket() || meta.uid() != geteuid().as_raw() {
        return Err(HalError::io(
            "binding the socket",
            path,
            std::io::Error::other("another file took its place"),
        ));
    }
    let group = HalGroup::lookup();
    let shared = group.gid.is_some_and(|gid| {
        fchownat(
            node.as_fd(),
            "",
            None,
            Some(Gid::from_raw(gid)),
            AtFlags::AT_EMPTY_PATH,
        )
        .is_ok()
    });
    // fchmod refuses O_PATH descriptors; the descriptor's /proc link
    // reaches the same inode without a second lookup of `path`.
    let by_fd = format!("/proc/self/fd/{}", node.as_raw_fd());
    let mode = if shared { 0o660 } else { 0o600 };
    std::fs::set_permissions(&by_fd, std::os::unix::fs::PermissionsExt::from_mode(mode))
        .map_err(|e| HalError::io("setting the mode of the socket", path, e))?;
    Ok(listener)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    fn temp(tag: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("hal-files-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir(&d).unwrap();
        d
    }

    #[test]
    fn planted_links_are_never_followed() {
        let d = temp("links");
        let target = d.join("target");
        std::fs::write(&target, "precious\n").unwrap();
        let link = d.join("hal-x.lock");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        assert_eq!(
            create_new(&link).unwrap_err().kind(),
            std::io::ErrorKind::AlreadyExists
        );
        assert!(open_existing(&link).is_err());
        // The log replaces the link by a file of its own.
        let log = d.join("hal-x.log");
        std::os::unix::fs::symlink(&target, &log).unwrap();
        use std::io::Write;
        create_log(&log).unwrap().write_all(b"note\n").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "precious\n");
        assert_eq!(std::fs::read_to_string(&log).unwrap(), "note\n");
        assert!(!std::fs::symlink_metadata(&log)
            .unwrap()
            .file_type()
            .is_symlink());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_fifo_is_not_a_lock_file() {
        let d = temp("fifo");
        let p = d.join("hal-x.lock");
        nix::unistd::mkfifo(&p, nix::sys::stat::Mode::from_bits_truncate(0o600)).unwrap();
        assert!(open_existing(&p).is_err());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn sockets_and_files_ignore_the_umask() {
        let d = temp("modes");
        // SAFETY: umask only changes this process's file-creation mask.
        let old = unsafe { libc::umask(0o077) };
        let sock = bind_socket(&d.join("s.sock"));
        let log = create_log(&d.join("l.log"));
        // SAFETY: as above.
        unsafe { libc::umask(old) };
        let (_sock, _log) = (sock.unwrap(), log.unwrap());
        let group = HalGroup::lookup();
        for name in ["s.sock", "l.log"] {
            let meta = std::fs::metadata(d.join(name)).unwrap();
            let want = match group.gid {
                Some(gid) if meta.gid() == gid => 0o660,
                _ => 0o600,
            };
            assert_eq!(meta.permissions().mode() & 0o777, want, "{name}");
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}
