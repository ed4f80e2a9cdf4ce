//! Choosing, creating and checking the private runtime directory.
//!
//! * `HAL_RUNTIME_DIR`, when set, names it;
//! * root uses `/run/hal`, and so does any user who may write there (the
//!   members of the hal group, when the directory exists: the package's
//!   tmpfiles.d entry makes it 0770 root:hal at boot), so that members share
//!   instances that root or other members started;
//! * anyone else uses `$XDG_RUNTIME_DIR/hal` (or `/run/user/UID/hal` when
//!   the variable is unset but the directory exists).
//!
//! A directory that anyone but its owner and the hal group could write
//! into, that belongs to neither root nor this user, or that sits in a
//! world-writable parent without the sticky bit, is refused: whoever could
//! plant a file there could make the host write through it.

use std::os::fd::AsFd;
use std::os::unix::fs::{DirBuilderExt, MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

use nix::sys::stat::{fchmod, Mode};
use nix::unistd::{access, fchown, geteuid, AccessFlags, Gid};

use super::group::HalGroup;
use crate::error::{HalError, Result};

/// The runtime directory of a root host and of the hal group's members.
pub const SYSTEM_RUNTIME_DIR: &str = "/run/hal";

/// Where the directory came from (it decides how it is created).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// `HAL_RUNTIME_DIR`.
    Env,
    /// `/run/hal`.
    System,
    /// The user's own runtime directory.
    User,
}

fn choose() -> Result<(PathBuf, Source)> {
    if let Some(dir) = std::env::var_os("HAL_RUNTIME_DIR").filter(|d| !d.is_empty()) {
        let dir = PathBuf::from(dir);
        if !dir.is_absolute() {
            return Err(HalError::RuntimeDir {
                path: dir,
                reason: "HAL_RUNTIME_DIR must be an absolute path".into(),
            });
        }
        return Ok((dir, Source::Env));
    }
    let system = Path::new(SYSTEM_RUNTIME_DIR);
    if geteuid().is_root() || access(system, AccessFlags::W_OK | AccessFlags::X_OK).is_ok() {
        return Ok((system.to_path_buf(), Source::System));
    }
    let user_dir = std::env::var_os("XDG_RUNTIME_DIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .filter(|d| d.is_absolute())
        .or_else(|| {
            let d = PathBuf::from(format!("/run/user/{}", geteuid()));
            d.is_dir().then_some(d)
        });
    match user_dir {
        Some(d) => Ok((d.join("hal"), Source::User)),
        None => Err(HalError::NoRuntimeDir {
            uid: geteuid().as_raw(),
        }),
    }
}

/// The runtime directory, checked if it exists. A directory that does not
/// exist yet is returned as it is: nothing runs there, and whoever looks
/// for a file in it finds none.
pub fn runtime_dir() -> Result<PathBuf> {
    let (dir, _) = choose()?;
    match std::fs::symlink_metadata(&dir) {
        Ok(meta) => check(&dir, &meta, &HalGroup::lookup())?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(HalError::io("examining the runtime directory", &dir, e)),
    }
    Ok(dir)
}

/// The runtime directory, created if missing (as `/run/hal`: 0770, owner
/// root, group hal; as any other: 0700), then checked. Only one level is
/// created: the parent (`$XDG_RUNTIME_DIR`, `/run`) must exist.
pub fn ensure_runtime_dir() -> Result<PathBuf> {
    let (dir, source) = choose()?;
    let group = HalGroup::lookup();
    match std::fs::DirBuilder::new().mode(0o700).create(&dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => return Err(HalError::io("creating the runtime directory", &dir, e)),
    }
    if source == Source::System && geteuid().is_root() {
        give_system_dir_to_group(&dir, &group)?;
    }
    let meta = std::fs::symlink_metadata(&dir)
        .map_err(|e| HalError::io("examining the runtime directory", &dir, e))?;
    check(&dir, &meta, &group)?;
    Ok(dir)
}

/// As root: makes `/run/hal` 0770 root:hal when the group exists (a
/// directory made before the group was, or by hand, is brought in line).
fn give_system_dir_to_group(dir: &Path, group: &HalGroup) -> Result<()> {
    let Some(gid) = group.gid else {
        return Ok(());
    };
    let f = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_DIRECTORY | libc::O_NOFOLLOW | libc::O_CLOEXEC)
        .open(dir)
        .map_err(|e| HalError::io("opening the runtime directory", dir, e))?;
    let meta = f
        .metadata()
        .map_err(|e| HalError::io("examining the runtime directory", dir, e))?;
    if meta.uid() != 0 {
        // Not ours to change; `check` says what is wrong with it.
        return Ok(());
    }
    let fail = |e: nix::Error| {
        HalError::io(
            "giving the runtime directory to the hal group",
            dir,
            e.into(),
        )
    };
    if meta.gid() != gid {
        fchown(f.as_fd(), None, Some(Gid::from_raw(gid))).map_err(fail)?;
    }
    if meta.mode() & 0o7777 != 0o770 {
        fchmod(f.as_fd(), Mode::from_bits_truncate(0o770)).map_err(fail)?;
    }
    Ok(())
}

/// Refuses a runtime directory that someone other than its owner and the
/// hal group could write into, or that is owned by neither root nor us.
pub(crate) fn check(dir: &Path, meta: &std::fs::Metadata, group: &HalGroup) -> Result<()> {
    check_with(dir, meta, group, geteuid().as_raw())?;
    check_parents(dir)
}

/// The rules of [`check`] for the directory itself, for user `euid`.
fn check_with(dir: &Path, meta: &std::fs::Metadata, group: &HalGroup, euid: u32) -> Result<()> {
    let refuse = |reason: String| {
        Err(HalError::RuntimeDir {
            path: dir.to_path_buf(),
            reason,
        })
    };
    if meta.file_type().is_symlink() {
        return refuse("it is a symbolic link; name the directory itself".into());
    }
    if !meta.is_dir() {
        return refuse("it is not a directory".into());
    }
    let (uid, gid, mode) = (meta.uid(), meta.gid(), meta.mode() & 0o7777);
    if uid != 0 && uid != euid {
        return refuse(format!(
            "it belongs to uid {uid}, which is neither root nor you (uid {euid})"
        ));
    }
    if mode & 0o002 != 0 {
        return refuse(format!(
            "every user may write into it (mode {mode:04o}); make it 0700 or 0770 with the group '{}'",
            group.name
        ));
    }
    if mode & 0o020 != 0 && group.gid != Some(gid) {
        return refuse(format!(
            "its group (gid {gid}) may write into it (mode {mode:04o}) and is not the group '{}'",
            group.name
        ));
    }
    Ok(())
}

/// A world-writable parent without the sticky bit would let anyone
/// replace the runtime directory itself.
fn check_parents(dir: &Path) -> Result<()> {
    let full = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    for parent in full.ancestors().skip(1) {
        let Ok(meta) = std::fs::metadata(parent) else {
            continue;
        };
        let mode = meta.mode() & 0o7777;
        if mode & 0o002 != 0 && mode & 0o1000 == 0 {
            return Err(HalError::RuntimeDir {
                path: dir.to_path_buf(),
                reason: format!(
                    "its parent {} may be written by every user and has no sticky bit (mode {mode:04o})",
                    parent.display()
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    fn temp(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("hal-rtdir-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir(&d).unwrap();
        d
    }

    fn chmod(p: &Path, mode: u32) {
        std::fs::set_permissions(p, std::fs::Permissions::from_mode(mode)).unwrap();
    }

    /// Why `p` is refused, or None when it passes.
    fn refusal(p: &Path, group: &HalGroup, euid: u32) -> Option<String> {
        let meta = std::fs::symlink_metadata(p).unwrap();
        check_with(p, &meta, group, euid)
            .err()
            .map(|e| e.to_string())
    }

    #[test]
    fn private_and_group_directories_pass_others_are_refused() {
        let d = temp("modes");
        let me = geteuid().as_raw();
        let gid = std::fs::metadata(&d).unwrap().gid();
        let ours = HalGroup {
            name: "hal".into(),
            gid: Some(gid),
        };
        let other = HalGroup {
            name: "hal".into(),
            gid: Some(gid.wrapping_add(4242)),
        };
        chmod(&d, 0o700);
        assert_eq!(refusal(&d, &other, me), None);
        chmod(&d, 0o770);
        assert_eq!(refusal(&d, &ours, me), None);
        let e = refusal(&d, &other, me).unwrap();
        assert!(e.contains("its group") && e.contains("'hal'"), "{e}");
        chmod(&d, 0o1777);
        let e = refusal(&d, &ours, me).unwrap();
        assert!(e.contains("every user may write"), "{e}");
        chmod(&d, 0o755);
        // Owned by a third user: as root, give it to one; otherwise
        // pretend to be another user.
        let e = if me == 0 {
            std::os::unix::fs::chown(&d, Some(54321), None).unwrap();
            refusal(&d, &ours, me).unwrap()
        } else {
            refusal(&d, &ours, me + 1000).unwrap()
        };
        assert!(e.contains("neither root nor you"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn links_files_and_unsafe_parents_are_refused() {
        let d = temp("kinds");
        let group = HalGroup {
            name: "hal".into(),
            gid: None,
        };
        let me = geteuid().as_raw();
        let link = d.join("link");
        std::os::unix::fs::symlink(&d, &link).unwrap();
        assert!(refusal(&link, &group, me)
            .unwrap()
            .contains("symbolic link"));
        let file = d.join("file");
        std::fs::write(&file, "").unwrap();
        assert!(refusal(&file, &group, me)
            .unwrap()
            .contains("not a directory"));
        // A world-writable parent without the sticky bit.
        let inner = d.join("inner");
        std::fs::create_dir(&inner).unwrap();
        chmod(&inner, 0o700);
        chmod(&d, 0o777);
        let e = check_parents(&inner).unwrap_err().to_string();
        assert!(e.contains("no sticky bit"), "{e}");
        chmod(&d, 0o1777);
        assert!(check_parents(&inner).is_ok());
        chmod(&d, 0o700);
        std::fs::remove_dir_all(&d).unwrap();
    }
}
