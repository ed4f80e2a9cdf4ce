//! Which realtime permissions a host process had in force, read from
//! /proc and /sys: each HAL thread's scheduling policy, priority and
//! allowed CPUs, the process's locked memory, its rtprio and memlock
//! limits and capabilities, and the kernel, CPU governor and isolated
//! CPUs (the fields of LinuxCNC's latency status bar).

use std::fmt::Write as _;
use std::path::Path;

/// `CAP_IPC_LOCK`: lock memory beyond the memlock limit.
const CAP_IPC_LOCK: u32 = 14;
/// `CAP_SYS_RAWIO`: raw I/O ports.
const CAP_SYS_RAWIO: u32 = 17;
/// `CAP_SYS_NICE`: SCHED_FIFO beyond the rtprio limit.
const CAP_SYS_NICE: u32 = 23;

/// How one HAL thread was scheduled.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ThreadPlacement {
    /// The HAL thread's name.
    pub name: String,
    /// `SCHED_FIFO`, `SCHED_OTHER`, ...
    pub policy: String,
    /// The realtime priority (0 outside the realtime classes).
    pub rt_priority: u32,
    /// The CPUs it may run on, as the kernel lists them (`1`, `0-3`).
    pub cpus: String,
}

/// What a host process was allowed, and how its threads ran.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Permissions {
    /// One entry per HAL thread found among the process's tasks.
    pub threads: Vec<ThreadPlacement>,
    /// Locked memory in kB (`VmLck`).
    pub locked_kb: Option<u64>,
    /// The soft rtprio limit (`None`: unreadable).
    pub rtprio_limit: Option<String>,
    /// The soft memlock limit.
    pub memlock_limit: Option<String>,
    /// Effective capabilities that matter here.
    pub capabilities: Vec<&'static str>,
    /// Whether the kernel is PREEMPT_RT.
    pub preempt_rt: bool,
    /// The CPU frequency governor of the first HAL thread's CPU.
    pub governor: Option<String>,
    /// CPUs isolated from the scheduler (`isolcpus=`), empty if none.
    pub isolated: String,
}

impl Permissions {
    /// Whether every HAL thread ran under SCHED_FIFO.
    pub fn realtime(&self) -> bool {
        !self.threads.is_empty() && self.threads.iter().all(|t| t.policy == "SCHED_FIFO")
    }
}

/// The name the kernel gives the OS thread of HAL thread `hal_name`: the
/// host names it `hal-NAME`, and the kernel keeps 15 bytes.
fn task_name(hal_name: &str) -> String {
    let full = format!("hal-{hal_name}");
    let mut end = full.len().min(15);
    while !full.is_char_boundary(end) {
        end -= 1;
    }
    full[..end].to_string()
}

/// Reads what process `pid` (a HAL host) had in force for the HAL threads
/// `hal_threads`.
pub fn read(pid: u32, hal_threads: &[String]) -> Permissions {
    read_from(Path::new("/proc"), Path::new("/sys"), pid, hal_threads)
}

fn read_from(proc: &Path, sys: &Path, pid: u32, hal_threads: &[String]) -> Permissions {
    let pdir = proc.join(pid.to_string());
    let mut p = Permissions::default();
    let tasks: Vec<_> = std::fs::read_dir(pdir.join("task"))
        .map(|d| d.filter_map(|e| e.ok()).map(|e| e.path()).collect())
        .unwrap_or_default();
    for name in hal_threads {
        let want = task_name(name);
        let Some(task) = tasks
            .iter()
            .find(|t| std::fs::read_to_string(t.join("comm")).is_ok_and(|c| c.trim_end() == want))
        else {
            continue;
        };
        let stat = std::fs::read_to_string(task.join("stat")).unwrap_or_default();
        let (rt_priority, policy) = sched_of_stat(&stat).unwrap_or((0, u32::MAX));
        let status = std::fs::read_to_string(task.join("status")).unwrap_or_default();
        p.threads.push(ThreadPlacement {
            name: name.clone(),
            policy: policy_name(policy).to_string(),
            rt_priority,
            cpus: status_field(&status, "Cpus_allowed_list:").unwrap_or_default(),
        });
    }
    let status = std::fs::read_to_string(pdir.join("status")).unwrap_or_default();
    p.locked_kb = status_field(&status, "VmLck:")
        .and_then(|v| v.split_whitespace().next().and_then(|n| n.parse().ok()));
    if let Some(eff) =
        status_field(&status, "CapEff:").and_then(|h| u64::from_str_radix(&h, 16).ok())
    {
        for (bit, name) in [
            (CAP_SYS_NICE, "cap_sys_nice"),
            (CAP_IPC_LOCK, "cap_ipc_lock"),
            (CAP_SYS_RAWIO, "cap_sys_rawio"),
        ] {
            if eff & (1 << bit) != 0 {
                p.capabilities.push(name);
            }
        }
    }
    let limits = std::fs::read_to_string(pdir.join("limits")).unwrap_or_default();
    p.rtprio_limit = soft_limit(&limits, "Max realtime priority");
    p.memlock_limit = soft_limit(&limits, "Max locked memory");
    p.preempt_rt = std::fs::read_to_string(sys.join("kernel/realtime"))
        .is_ok_and(|s| s.trim() == "1")
        || std::fs::read_to_string(proc.join("sys/kernel/version"))
            .is_ok_and(|v| v.contains("PREEMPT_RT"));
    let cpu = p
        .threads
        .first()
        .and_then(|t| t.cpus.split([',', '-']).next().map(str::to_string))
        .filter(|c| !c.is_empty())
        .unwrap_or_else(|| "0".into());
    p.governor = std::fs::read_to_string(sys.join(format!(
        "devices/system/cpu/cpu{cpu}/cpufreq/scaling_governor"
    )))
    .ok()
    .map(|s| s.trim().to_string());
    p.isolated = std::fs::read_to_string(sys.join("devices/system/cpu/isolated"))
        .map(|s| s.trim().to_string())
        .unwrap_or_default();
    p
}

/// Fields 40 (rt_priority) and 41 (policy) of a `stat` line; the command
/// name in field 2 may hold spaces and parentheses, so fields are counted
/// after its closing parenthesis.
fn sched_of_stat(stat: &str) -> Option<(u32, u32)> {
    let rest = &stat[stat.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // `rest` starts at field 3.
    Some((f.get(40 - 3)?.parse().ok()?, f.get(41 - 3)?.parse().ok()?))
}

fn policy_name(policy: u32) -> &'static str {
    match policy {
        0 => "SCHED_OTHER",
        1 => "SCHED_FIFO",
        2 => "SCHED_RR",
        3 => "SCHED_BATCH",
        5 => "SCHED_IDLE",
        6 => "SCHED_DEADLINE",
        _ => "unknown",
    }
}

/// The value of a `Key:\tvalue` line of a /proc status file.
fn status_field(status: &str, key: &str) -> Option<String> {
    status
        .lines()
        .find_map(|l| l.strip_prefix(key))
        .map(|v| v.trim().to_string())
}

/// The soft limit of a /proc limits line (`Max locked memory  8388608
/// 8388608  bytes`), with its unit.
fn soft_limit(limits: &str, name: &str) -> Option<String> {
    let rest = limits.lines().find_map(|l| l.strip_prefix(name))?;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let soft = *f.first()?;
    Some(match (soft, f.get(2)) {
        ("unlimited", _) => "unlimited".to_string(),
        // In kB, as the locked memory beside it (VmLck) is.
        (v, Some(&"bytes")) => match v.parse::<u64>() {
            Ok(bytes) => format!("{} kB", bytes / 1024),
            Err(_) => format!("{v} bytes"),
        },
        (v, _) => v.to_string(),
    })
}

/// The permissions as lines of text: what was in force, and for each
/// thread without realtime, how to grant it.
pub fn describe(p: &Permissions) -> String {
    let mut s = String::new();
    for t in &p.threads {
        let _ = writeln!(
            s,
            "  {:<14} {} priority {}, CPUs {}",
            t.name, t.policy, t.rt_priority, t.cpus
        );
    }
    let none = "unknown".to_string();
    let _ = writeln!(
        s,
        "  memory locked: {} (memlock limit {}); rtprio limit {}; capabilities: {}",
        p.locked_kb.map_or(none.clone(), |k| format!("{k} kB")),
        p.memlock_limit.as_ref().unwrap_or(&none),
        p.rtprio_limit.as_ref().unwrap_or(&none),
        if p.capabilities.is_empty() {
            "none".to_string()
        } else {
            p.capabilities.join(", ")
        }
    );
    let _ = writeln!(
        s,
        "  kernel: {}; CPU governor: {}; isolated CPUs: {}",
        if p.preempt_rt {
            "PREEMPT_RT"
        } else {
            "not realtime (no PREEMPT_RT)"
        },
        p.governor.as_deref().unwrap_or("none"),
        if p.isolated.is_empty() {
            "none"
        } else {
            &p.isolated
        }
    );
    if !p.realtime() {
        s.push_str(
            "  The threads ran WITHOUT realtime scheduling: these figures are far worse than \
             the machine can do. Grant it: add the user to the group 'hal' with \
             '@hal - rtprio 99' and '@hal - memlock unlimited' in \
             /etc/security/limits.d/hal.conf (the Debian package installs both), then log \
             in again.\n",
        );
    } else if p.locked_kb == Some(0) {
        s.push_str(
            "  Memory was not locked: page faults may add latency. Grant '@hal - memlock \
             unlimited' in /etc/security/limits.d/hal.conf.\n",
        );
    }
    if p.governor.as_deref().is_some_and(|g| g != "performance") {
        s.push_str(
            "  The CPU governor is not 'performance': frequency changes add latency spikes.\n",
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_fields_after_a_tricky_command_name() {
        // Fields 3..41 after "(a) b)": state, then 36 fields up to
        // rt_priority (40) and policy (41).
        let mut fields = vec!["S".to_string()];
        fields.extend((4..40).map(|n| n.to_string()));
        fields.push("90".into());
        fields.push("1".into());
        fields.push("0".into());
        let line = format!("123 (a) b) {}", fields.join(" "));
        assert_eq!(sched_of_stat(&line), Some((90, 1)));
        assert_eq!(sched_of_stat("garbage"), None);
    }

    #[test]
    fn limits_and_status_lines() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
                      Max locked memory         8388608              8388608              bytes     \n\
                      Max realtime priority     0                    0                    \n";
        assert_eq!(
            soft_limit(limits, "Max locked memory").as_deref(),
            Some("8192 kB")
        );
        assert_eq!(
            soft_limit(limits, "Max realtime priority").as_deref(),
            Some("0")
        );
        assert_eq!(
            status_field("VmLck:\t   12 kB\n", "VmLck:").as_deref(),
            Some("12 kB")
        );
        assert_eq!(task_name("servo-thread"), "hal-servo-threa");
        assert_eq!(task_name("base"), "hal-base");
    }

    #[test]
    fn this_process_reads_as_a_host() {
        // A thread named like a HAL thread's executor, in this process.
        // std names a thread from inside it, before the closure runs: the
        // closure says when it runs.
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        let (ready_tx, ready_rx) = std::sync::mpsc::channel::<()>();
        let t = std::thread::Builder::new()
            .name("hal-perm-test".into())
            .spawn(move || {
                let _ = ready_tx.send(());
                let _ = rx.recv();
            })
            .unwrap();
        ready_rx.recv().unwrap();
        let p = read(std::process::id(), &["perm-test".to_string()]);
        tx.send(()).unwrap();
        t.join().unwrap();
        assert_eq!(p.threads.len(), 1, "{p:?}");
        assert_eq!(p.threads[0].policy, "SCHED_OTHER");
        assert!(!p.threads[0].cpus.is_empty());
        assert!(p.locked_kb.is_some());
        assert!(p.rtprio_limit.is_some() && p.memlock_limit.is_some());
        assert!(!p.realtime());
        assert!(
            describe(&p).contains("WITHOUT realtime"),
            "{}",
            describe(&p)
        );
    }
}
