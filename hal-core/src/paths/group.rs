//! The `hal` group: the one door to an instance. Segment, socket, lock and
//! log are given to it with mode 0660 on the open descriptor, so neither
//! the umask nor the creator's own group decides who may use an instance;
//! and a user it refuses is told which group lets them in and how to join.

use std::os::fd::AsFd;
use std::os::unix::fs::MetadataExt;
use std::path::Path;

use nix::sys::stat::{fchmod, Mode};
use nix::unistd::{fchown, getegid, geteuid, getgroups, Gid, Group, Uid, User};

use crate::error::{HalError, Result};

/// The group's name when `HAL_GROUP` does not name another.
pub const DEFAULT_GROUP: &str = "hal";

/// The group that shares instances: its name, and its id if it exists.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HalGroup {
    /// `HAL_GROUP`, or `hal`.
    pub name: String,
    /// The group id, or `None` when no such group exists.
    pub gid: Option<u32>,
}

impl HalGroup {
    /// The group named by `HAL_GROUP` (default `hal`), looked up now.
    pub fn lookup() -> HalGroup {
        let name = std::env::var("HAL_GROUP")
            .ok()
            .filter(|n| !n.is_empty())
            .unwrap_or_else(|| DEFAULT_GROUP.to_string());
        HalGroup::named(&name)
    }

    /// The group `name`, looked up now.
    pub fn named(name: &str) -> HalGroup {
        // A name with a NUL, or a failing lookup, is a group that does
        // not exist: nothing is shared through it.
        let gid = Group::from_name(name)
            .ok()
            .flatten()
            .map(|g| g.gid.as_raw());
        HalGroup {
            name: name.to_string(),
            gid,
        }
    }

    /// Whether this process has the group among its groups (it may be a
    /// member listed in /etc/group whose session started before joining).
    pub fn in_session(&self) -> bool {
        let Some(gid) = self.gid.map(Gid::from_raw) else {
            return false;
        };
        getegid() == gid || getgroups().is_ok_and(|g| g.contains(&gid))
    }

    /// Whether the group database lists `user` as a member (or as the
    /// group's primary user).
    fn lists(&self, user: &User) -> bool {
        let Some(gid) = self.gid else {
            return false;
        };
        user.gid.as_raw() == gid
            || Group::from_gid(Gid::from_raw(gid))
                .ok()
                .flatten()
                .is_some_and(|g| g.mem.contains(&user.name))
    }
}

/// Gives a file we just created to the group with mode 0660, on its open
/// descriptor (no path, so nothing can be swapped in between). Without the
/// group, or when this process may not give files to it (a user outside
/// it), the file stays private: mode 0600.
pub(crate) fn share_fd(fd: impl AsFd, group: &HalGroup, path: &Path) -> Result<()> {
    let fd = fd.as_fd();
    let shared = match group.gid {
        Some(gid) => match fchown(fd, None, Some(Gid::from_raw(gid))) {
            Ok(()) => true,
            Err(nix::errno::Errno::EPERM) => false,
            Err(e) => {
                return Err(HalError::io(
                    "giving a runtime file to the hal group",
                    path,
                    e.into(),
                ))
            }
        },
        None => false,
    };
    let mode = if shared { 0o660 } else { 0o600 };
    fchmod(fd, Mode::from_bits_truncate(mode))
        .map_err(|e| HalError::io("setting the mode of a runtime file", path, e.into()))
}

fn user_name(uid: u32) -> String {
    User::from_uid(Uid::from_raw(uid))
        .ok()
        .flatten()
        .map_or_else(|| format!("uid {uid}"), |u| u.name)
}

fn group_name(gid: u32) -> String {
    Group::from_gid(Gid::from_raw(gid))
        .ok()
        .flatten()
        .map_or_else(|| format!("gid {gid}"), |g| g.name)
}

/// The error for a refused open or connect of `path`: says who the file
/// belongs to and what the user can do to be let in.
pub fn denied(op: &'static str, path: &Path) -> HalError {
    let group = HalGroup::lookup();
    let meta = std::fs::metadata(path).ok();
    let me = User::from_uid(geteuid()).ok().flatten();
    let me_name = me
        .as_ref()
        .map_or_else(|| format!("uid {}", geteuid()), |u| u.name.clone());
    let owner = meta.as_ref().map(|m| (m.uid(), m.gid()));
    let g = &group.name;
    let advice = match (group.gid, owner) {
        (None, _) => format!(
            "instances are shared through the group '{g}', which does not exist: \
             create it (sudo groupadd --system {g}), add each user \
             (sudo usermod -aG {g} USER, then log in again) and restart the instance"
        ),
        (Some(gid), Some((uid, file_gid))) if file_gid != gid => format!(
            "it belongs to user {} and group {}, not to the group '{g}' that shares \
             instances: start the instance as root or as a member of '{g}'",
            user_name(uid),
            group_name(file_gid)
        ),
        (Some(_), _) if group.in_session() => format!(
            "you are in the group '{g}', but the file does not let the group in \
             (mode {:o}): restart the instance",
            meta.as_ref().map_or(0, |m| m.mode() & 0o7777)
        ),
        (Some(_), _) if me.as_ref().is_some_and(|u| group.lists(u)) => format!(
            "you joined the group '{g}' after this session began: \
             log in again (or run `newgrp {g}`)"
        ),
        (Some(_), _) => format!(
            "only members of the group '{g}' may use it, and you ({me_name}) are not one: \
             join it with `sudo usermod -aG {g} {me_name}`, then log in again"
        ),
    };
    HalError::PermissionDenied {
        op,
        path: path.to_path_buf(),
        advice,
    }
}
