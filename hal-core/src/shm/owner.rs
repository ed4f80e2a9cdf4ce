//! Judging the owner a lock word names ([`StaleOwner`] for the segment):
//! a thread id above the system's largest, a thread that does not exist,
//! a kernel thread, a thread that has exited, or a process that has not
//! mapped this segment cannot be holding the segment's lock. A process
//! whose mappings this user may not read is given the benefit of the
//! doubt.

use std::os::unix::fs::MetadataExt;

use super::mutex::StaleOwner;
use super::segment::Segment;

/// `PF_KTHREAD` in the flags field of `/proc/<tid>/stat`.
const PF_KTHREAD: u64 = 0x0020_0000;
/// The largest `pid_max` Linux allows (2^22).
const PID_MAX_LIMIT: u32 = 1 << 22;

impl StaleOwner for Segment {
    fn impossible(&self, tid: u32) -> Option<String> {
        let pid_max = std::fs::read_to_string("/proc/sys/kernel/pid_max")
            .ok()
            .and_then(|s| s.trim().parse::<u32>().ok())
            .unwrap_or(PID_MAX_LIMIT);
        if tid >= pid_max {
            return Some(format!(
                "is not a possible thread id (pid_max is {pid_max})"
            ));
        }
        let stat = match std::fs::read_to_string(format!("/proc/{tid}/stat")) {
            Ok(s) => s,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Some("does not exist".into())
            }
            Err(_) => return None,
        };
        // Fields after the command's closing parenthesis: state, ppid,
        // pgrp, session, tty_nr, tpgid, flags, ...
        let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
        let mut fields = rest.split_whitespace();
        let state = fields.next().unwrap_or("");
        if matches!(state, "Z" | "X" | "x") {
            return Some("has exited".into());
        }
        let flags: u64 = fields.nth(5).and_then(|f| f.parse().ok()).unwrap_or(0);
        if flags & PF_KTHREAD != 0 {
            return Some("is a kernel thread".into());
        }
        let ino = self.file().metadata().ok()?.ino();
        let maps = std::fs::read_to_string(format!("/proc/{tid}/maps")).ok()?;
        let mapped = maps.lines().any(|l| {
            l.split_whitespace().nth(4) == Some(&ino.to_string())
                && l.contains(&*self.path().to_string_lossy())
        });
        (!mapped).then(|| "has not mapped the instance's shared memory".into())
    }

    fn recovered(&self, tid: u32, why: &str) {
        eprintln!(
            "HAL: instance '{}': the structural lock named thread {tid} as its holder, which {why}: \
             the lock word was damaged; lock recovered (any half-made change is undone)",
            self.instance()
        );
    }
}
