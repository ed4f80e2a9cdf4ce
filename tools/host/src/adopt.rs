//! Programs that `loadusr` started, adopted by the host.
//!
//! As in LinuxCNC, a program started by a one-shot `halcmd loadusr` outlives
//! halcmd; it ends with `unloadusr` (when it is a component) or with the
//! instance: before the host shuts down it asks every adopted program still
//! running to end (SIGTERM), waits a moment, then kills what is left. The
//! host holds a pidfd of each program, so a PID reused after the program
//! ended is never signalled, and adopts only a direct child of the process
//! that asks (checked with the socket's peer credentials while the child
//! cannot have been reaped), so a client cannot make the host signal
//! someone else's process.

use std::os::fd::{AsFd, AsRawFd, FromRawFd, OwnedFd};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use nix::poll::{poll, PollFd, PollFlags, PollTimeout};

use crate::error::HostError;

/// One adopted program.
struct Program {
    pidfd: OwnedFd,
    pid: i32,
    name: String,
}

/// The programs a host has adopted.
#[derive(Default)]
pub struct Adopted {
    programs: Mutex<Vec<Program>>,
}

impl Adopted {
    /// An empty list.
    pub fn new() -> Adopted {
        Adopted::default()
    }

    /// Adopts process `pid` (a decimal number), named `name` in messages,
    /// which must be a child of `requester` (the peer's PID).
    pub fn adopt(&self, pid: &str, name: &str, requester: Option<i32>) -> Result<(), HostError> {
        let pid: i32 = pid
            .parse()
            .ok()
            .filter(|p| *p > 0)
            .ok_or_else(|| HostError::BadPid {
                pid: pid.to_string(),
            })?;
        let requester = requester.ok_or(HostError::NoPeer)?;
        let pidfd = pidfd_open(pid).map_err(|source| HostError::Process { pid, source })?;
        // With the pidfd held, `pid` names this process for good; and as the
        // requester's unreaped child it cannot have been reused before.
        match parent_of(pid) {
            Ok(parent) if parent == requester => {}
            Ok(parent) => {
                return Err(HostError::NotAChild {
                    pid,
                    parent,
                    requester,
                })
            }
            Err(source) => return Err(HostError::Process { pid, source }),
        }
        let mut list = lock(&self.programs);
        // Forget programs that have ended meanwhile.
        list.retain(|p| !exited(&p.pidfd));
        list.push(Program {
            pidfd,
            pid,
            name: name.to_string(),
        });
        Ok(())
    }

    /// How many adopted programs are still running.
    #[cfg(test)]
    fn running(&self) -> usize {
        lock(&self.programs)
            .iter()
            .filter(|p| !exited(&p.pidfd))
            .count()
    }

    /// Ends every adopted program still running: SIGTERM, up to `grace` for
    /// them to exit, then SIGKILL (and a moment for that). Returns a note
    /// for each program that had to be killed or could not be signalled.
    pub fn stop_all(&self, grace: Duration) -> Vec<String> {
        let list = std::mem::take(&mut *lock(&self.programs));
        let mut notes = Vec::new();
        let mut left: Vec<&Program> = Vec::new();
        for p in &list {
            if exited(&p.pidfd) {
                continue;
            }
            match pidfd_signal(&p.pidfd, libc::SIGTERM) {
                Ok(()) => left.push(p),
                Err(e) => notes.push(format!("cannot stop '{}' (process {}): {e}", p.name, p.pid)),
            }
        }
        wait_exited(&mut left, grace);
        for p in &left {
            notes.push(format!(
                "'{}' (process {}) did not end within {} s of SIGTERM; killed",
                p.name,
                p.pid,
                grace.as_secs_f64()
            ));
            let _ = pidfd_signal(&p.pidfd, libc::SIGKILL);
        }
        wait_exited(&mut left, Duration::from_secs(2));
        notes
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Waits up to `limit` until the programs in `left` have exited; those
/// still running stay in `left`.
fn wait_exited(left: &mut Vec<&Program>, limit: Duration) {
    let end = Instant::now() + limit;
    loop {
        left.retain(|p| !exited(&p.pidfd));
        let remaining = end.saturating_duration_since(Instant::now());
        if left.is_empty() || remaining.is_zero() {
            return;
        }
        let mut fds: Vec<PollFd> = left
            .iter()
            .map(|p| PollFd::new(p.pidfd.as_fd(), PollFlags::POLLIN))
            .collect();
        let ms = remaining.as_millis().min(1000) as u16;
        let _ = poll(&mut fds, PollTimeout::from(ms.max(1)));
    }
}

/// Whether the process behind `pidfd` has exited (its pidfd is readable).
fn exited(pidfd: &OwnedFd) -> bool {
    let mut fds = [PollFd::new(pidfd.as_fd(), PollFlags::POLLIN)];
    matches!(poll(&mut fds, PollTimeout::ZERO), Ok(n) if n > 0)
}

fn pidfd_open(pid: i32) -> std::io::Result<OwnedFd> {
    // SAFETY: pidfd_open takes a PID and flags and returns a new file
    // descriptor or -1; no memory of ours is involved.
    let fd = unsafe { libc::syscall(libc::SYS_pidfd_open, pid, 0) };
    if fd < 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: the kernel just gave us this descriptor; nobody else owns it.
    Ok(unsafe { OwnedFd::from_raw_fd(fd as i32) })
}

fn pidfd_signal(pidfd: &OwnedFd, sig: libc::c_int) -> std::io::Result<()> {
    // SAFETY: pidfd_send_signal with a descriptor we own, no siginfo
    // (null) and no flags; no memory of ours is written.
    let rc = unsafe {
        libc::syscall(
            libc::SYS_pidfd_send_signal,
            pidfd.as_raw_fd(),
            sig,
            std::ptr::null::<libc::siginfo_t>(),
            0,
        )
    };
    if rc < 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}

/// The parent PID of `pid`, from /proc/PID/stat (after the command name,
/// which may hold spaces and parentheses: the last `)` ends it).
fn parent_of(pid: i32) -> std::io::Result<i32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat"))?;
    let after = stat
        .rsplit_once(')')
        .map(|(_, rest)| rest)
        .ok_or_else(|| std::io::Error::other("malformed /proc stat"))?;
    // " S PPID ..."
    after
        .split_whitespace()
        .nth(1)
        .and_then(|p| p.parse().ok())
        .ok_or_else(|| std::io::Error::other("malformed /proc stat"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::Command;

    #[test]
    fn only_children_of_the_requester_are_adopted_and_all_are_stopped() {
        let adopted = Adopted::new();
        let me = std::process::id() as i32;
        let mut child = Command::new("sleep").arg("60").spawn().unwrap();
        let pid = child.id().to_string();
        let e = adopted
            .adopt(&pid, "sleep", Some(me + 1))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not of the requester"), "{e}");
        assert!(adopted.adopt("0", "x", Some(me)).is_err());
        assert!(adopted.adopt("nan", "x", Some(me)).is_err());
        assert!(adopted.adopt(&pid, "sleep", None).is_err());
        adopted.adopt(&pid, "sleep", Some(me)).unwrap();
        assert_eq!(adopted.running(), 1);
        let notes = adopted.stop_all(Duration::from_secs(10));
        assert!(notes.is_empty(), "{notes:?}");
        let status = child.wait().unwrap();
        assert_eq!(
            std::os::unix::process::ExitStatusExt::signal(&status),
            Some(libc::SIGTERM)
        );
        assert_eq!(adopted.running(), 0);
    }

    #[test]
    fn a_program_that_ignores_sigterm_is_killed() {
        let adopted = Adopted::new();
        let me = std::process::id() as i32;
        let mut child = Command::new("sh")
            .args([
                "-c",
                "trap '' TERM; echo ready; while :; do sleep 0.05; done",
            ])
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // The trap is set once the shell has said so.
        let mut line = String::new();
        std::io::BufRead::read_line(
            &mut std::io::BufReader::new(child.stdout.take().unwrap()),
            &mut line,
        )
        .unwrap();
        adopted
            .adopt(&child.id().to_string(), "stubborn", Some(me))
            .unwrap();
        let notes = adopted.stop_all(Duration::from_millis(200));
        assert!(notes[0].contains("killed"), "{notes:?}");
        let status = child.wait().unwrap();
        assert_eq!(
            std::os::unix::process::ExitStatusExt::signal(&status),
            Some(libc::SIGKILL)
        );
    }
}
