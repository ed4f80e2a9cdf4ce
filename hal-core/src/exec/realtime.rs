//! Realtime set-up of executor threads: SCHED_FIFO priority, CPU placement,
//! memory locking and timer slack, and a plain account of any permission
//! that is missing.

use std::fmt::Write as _;

use crate::error::{HalError, Result};

/// Priority of the fastest thread; each slower one gets one less.
pub const TOP_PRIORITY: i32 = 90;

/// How the host asks for realtime scheduling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RealtimeMode {
    /// Use SCHED_FIFO when permitted, else run without it and say why.
    Auto,
    /// Never use SCHED_FIFO (threads are serialised by a lock instead).
    Off,
}

/// Whether the current process may use SCHED_FIFO at `priority`: tries it
/// on a short-lived probe thread so the caller's own policy is untouched.
pub fn probe_fifo(priority: i32) -> Result<()> {
    let handle = std::thread::spawn(move || set_fifo(priority));
    handle.join().unwrap_or(Err(HalError::FifoProbePanicked))
}

/// Puts the calling thread under SCHED_FIFO at `priority`.
pub fn set_fifo(priority: i32) -> Result<()> {
    let param = libc::sched_param {
        sched_priority: priority,
    };
    // SAFETY: pthread_setschedparam on the calling thread with a valid param.
    let rc = unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) };
    if rc == 0 {
        Ok(())
    } else {
        Err(explain_fifo_failure(rc, priority))
    }
}

fn explain_fifo_failure(rc: i32, priority: i32) -> HalError {
    let mut hint = String::new();
    if rc == libc::EPERM {
        let limit = rlimit(libc::RLIMIT_RTPRIO);
        let _ = write!(
            hint,
            ": the rtprio limit is {} and the process lacks CAP_SYS_NICE. Grant it with \
             a line '@hal - rtprio 99' in /etc/security/limits.d/hal.conf (then log in \
             again), or 'setcap cap_sys_nice+ep' on the host binary, or run 'ulimit -r 99' \
             as root before starting",
            limit.map_or("unknown".to_string(), |l| l.to_string())
        );
        if let Ok(rt) = std::fs::read_to_string("/proc/sys/kernel/sched_rt_runtime_us") {
            if rt.trim() == "0" {
                hint.push_str(
                    "; also kernel.sched_rt_runtime_us is 0, which forbids realtime tasks",
                );
            }
        }
    }
    HalError::FifoRefused {
        priority,
        source: std::io::Error::from_raw_os_error(rc),
        hint,
    }
}

/// The kernel id of the calling thread.
pub fn current_tid() -> i32 {
    nix::unistd::gettid().as_raw()
}

/// The CPUs this process may run on, in order.
pub fn allowed_cpus() -> Vec<usize> {
    match nix::sched::sched_getaffinity(nix::unistd::Pid::from_raw(0)) {
        Ok(set) => (0..nix::sched::CpuSet::count())
            .filter(|&c| set.is_set(c).unwrap_or(false))
            .collect(),
        Err(_) => Vec::new(),
    }
}

/// Moves thread `tid` to `cpu`, or back to every CPU of `allowed` for
/// `None`.
pub fn place_thread(tid: i32, cpu: Option<usize>, allowed: &[usize]) -> Result<()> {
    let mut set = nix::sched::CpuSet::new();
    let cpus = match cpu {
        Some(c) => std::slice::from_ref(&c).to_vec(),
        None => allowed.to_vec(),
    };
    if cpus.is_empty() {
        return Ok(());
    }
    for &c in &cpus {
        set.set(c).map_err(|source| HalError::Affinity {
            action: format!("CPU {c} cannot be used"),
            source,
        })?;
    }
    nix::sched::sched_setaffinity(nix::unistd::Pid::from_raw(tid), &set).map_err(|source| {
        HalError::Affinity {
            action: match cpu {
                Some(c) => format!("moving the thread to CPU {c} failed"),
                None => "letting the thread run on every CPU failed".to_string(),
            },
            source,
        }
    })
}

/// The CPUs thread `tid` may run on (`sched_getaffinity`).
pub fn thread_affinity(tid: i32) -> Result<Vec<usize>> {
    let set = nix::sched::sched_getaffinity(nix::unistd::Pid::from_raw(tid)).map_err(|source| {
        HalError::Affinity {
            action: format!("reading the CPU affinity of thread {tid} failed"),
            source,
        }
    })?;
    Ok((0..nix::sched::CpuSet::count())
        .filter(|&c| set.is_set(c).unwrap_or(false))
        .collect())
}

/// Pins the calling thread to `cpu`.
pub fn pin_to_cpu(cpu: usize) -> Result<()> {
    place_thread(0, Some(cpu), &[])
}

/// The CPU HAL threads share by default under realtime: the last one this
/// process may use (LinuxCNC's choice, where isolated CPUs usually are).
pub fn default_cpu() -> Option<usize> {
    allowed_cpus().last().copied()
}

/// Parses a CPU number given as text (LinuxCNC's `RTAPI_CPU_NUMBER`) and
/// checks that the process may use that CPU.
pub fn parse_cpu(what: &str, text: &str, allowed: &[usize]) -> Result<usize> {
    let cpu: usize = text.trim().parse().map_err(|_| HalError::NotACpu {
        what: what.to_string(),
        text: text.to_string(),
    })?;
    if !allowed.contains(&cpu) {
        return Err(HalError::CpuNotAllowed {
            what: what.to_string(),
            cpu,
            allowed: cpu_list(allowed),
        });
    }
    Ok(cpu)
}

/// A CPU list as `0-3,6`.
pub fn cpu_list(cpus: &[usize]) -> String {
    let mut out = String::new();
    let mut i = 0;
    while i < cpus.len() {
        let mut j = i;
        while j + 1 < cpus.len() && cpus[j + 1] == cpus[j] + 1 {
            j += 1;
        }
        if !out.is_empty() {
            out.push(',');
        }
        if j > i {
            let _ = write!(out, "{}-{}", cpus[i], cpus[j]);
        } else {
            let _ = write!(out, "{}", cpus[i]);
        }
        i = j + 1;
    }
    if out.is_empty() {
        out.push_str("none");
    }
    out
}

/// Locks the process's memory as it is touched. Returns a description of
/// the problem if that is not permitted.
pub fn lock_memory() -> Result<()> {
    // MCL_ONFAULT locks pages as they are faulted in, so a large segment is
    // not made resident (and charged) up front.
    const MCL_ONFAULT: i32 = 4;
    // SAFETY: mlockall only changes paging behaviour.
    let rc = unsafe { libc::mlockall(libc::MCL_CURRENT | MCL_ONFAULT) };
    if rc == 0 {
        return Ok(());
    }
    let source = std::io::Error::last_os_error();
    let limit = rlimit(libc::RLIMIT_MEMLOCK).map_or("unknown".to_string(), |l| {
        if l == u64::MAX {
            "unlimited".to_string()
        } else {
            l.to_string()
        }
    });
    Err(HalError::MemoryLock { source, limit })
}

/// A standing request to the kernel's power management (PM QoS) that idle
/// CPUs wake at once: while it is held, cpuidle keeps every CPU in its
/// shallowest idle state (polling, or a halt the hypervisor leaves quickly)
/// instead of a deep one whose exit delays the next timer wake-up. Released
/// when dropped (the kernel drops the request when the file closes).
#[derive(Debug)]
pub struct CpuLatencyRequest {
    _file: std::fs::File,
}

/// The PM QoS device that takes a process's CPU wake-up latency limit.
const CPU_LATENCY_DEVICE: &str = "/dev/cpu_dma_latency";

/// Asks for a CPU wake-up latency of 0 µs for as long as the returned
/// request lives. Needs write access to /dev/cpu_dma_latency (root, or the
/// `hal` group through the package's udev rule). Costs power: idle CPUs
/// stay out of deep sleep.
pub fn request_zero_cpu_latency() -> std::io::Result<CpuLatencyRequest> {
    use std::io::Write;
    // Opened for writing only, never created: a device node in /dev.
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .open(CPU_LATENCY_DEVICE)?;
    // The device takes the limit as a binary s32 in microseconds.
    file.write_all(&0i32.to_ne_bytes())?;
    Ok(CpuLatencyRequest { _file: file })
}

/// What to tell an integrator whose host could not hold the CPU latency
/// request, or `None` where there is nothing to do about it (no such
/// device, as in many containers).
pub fn explain_cpu_latency_failure(err: &std::io::Error) -> Option<String> {
    match err.raw_os_error() {
        Some(libc::ENOENT) | Some(libc::ENODEV) | Some(libc::ENXIO) => None,
        _ => Some(format!(
            "could not keep the CPUs out of deep idle states ({CPU_LATENCY_DEVICE}: {err}); \
             wake-ups may be late by the CPU's idle exit time. The package's udev rule gives \
             the 'hal' group write access to it"
        )),
    }
}

/// Sets the calling thread's timer slack to 1 ns.
pub fn tight_timer_slack() {
    // SAFETY: PR_SET_TIMERSLACK takes an integer argument only.
    unsafe {
        libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong, 0, 0, 0);
    }
}

/// The slice asked for by [`short_slice`]: the kernel's smallest.
const SHORT_SLICE_NS: u64 = 100_000;

/// Asks the fair scheduler (EEVDF, Linux 6.12 and later) for a short time
/// slice for the calling thread: a thread with a shorter slice gets an
/// earlier virtual deadline, so when its timer fires it preempts the
/// ordinary processes running on its CPU instead of waiting for their
/// slices to end. Needs no privilege, leaves the nice value at 0, and is
/// what keeps the wake-up tail short without realtime scheduling. Returns
/// false where the kernel does not take the request (older kernels ignore
/// or refuse it; nothing else changes).
pub fn short_slice() -> bool {
    // `struct sched_attr` as the kernel defines it (SCHED_ATTR_SIZE_VER1).
    #[repr(C)]
    struct SchedAttr {
        size: u32,
        policy: u32,
        flags: u64,
        nice: i32,
        priority: u32,
        runtime: u64,
        deadline: u64,
        period: u64,
        util_min: u32,
        util_max: u32,
    }
    let attr = SchedAttr {
        size: std::mem::size_of::<SchedAttr>() as u32,
        policy: libc::SCHED_OTHER as u32,
        flags: 0,
        nice: 0,
        priority: 0,
        runtime: SHORT_SLICE_NS,
        deadline: 0,
        period: 0,
        util_min: 0,
        util_max: 0,
    };
    // SAFETY: sched_setattr reads `size` bytes from a valid, initialised
    // struct; pid 0 is the calling thread; flags 0.
    let rc = unsafe { libc::syscall(libc::SYS_sched_setattr, 0, &attr as *const SchedAttr, 0) };
    rc == 0
}

/// Touches `bytes` of the calling thread's stack so later use never faults.
#[inline(never)]
pub fn prefault_stack() {
    let mut buf = [0u8; 64 * 1024];
    for i in (0..buf.len()).step_by(4096) {
        // SAFETY: volatile write into our own stack array.
        unsafe { std::ptr::write_volatile(&mut buf[i], 1) };
    }
    std::hint::black_box(&buf);
}

fn rlimit(resource: libc::__rlimit_resource_t) -> Option<u64> {
    let mut r = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes into the struct we pass.
    let rc = unsafe { libc::getrlimit(resource, &mut r) };
    (rc == 0).then_some(r.rlim_cur)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refused_priority_names_the_limit_and_the_remedy() {
        let msg = explain_fifo_failure(libc::EPERM, 90).to_string();
        assert!(msg.contains("rtprio limit is"), "{msg}");
        assert!(msg.contains("CAP_SYS_NICE"), "{msg}");
        assert!(msg.contains("limits.d"), "{msg}");
        let other = explain_fifo_failure(libc::EINVAL, 90).to_string();
        assert!(!other.contains("limits.d"), "{other}");
    }

    /// The kernel's current CPU latency limit, as /dev/cpu_dma_latency
    /// reports it (binary s32, microseconds).
    fn current_cpu_latency_limit() -> std::io::Result<i32> {
        use std::io::Read;
        let mut v = [0u8; 4];
        std::fs::File::open(CPU_LATENCY_DEVICE)?.read_exact(&mut v)?;
        Ok(i32::from_ne_bytes(v))
    }

    #[test]
    fn a_held_cpu_latency_request_sets_the_kernels_limit_to_zero() {
        match request_zero_cpu_latency() {
            Ok(request) => {
                assert_eq!(current_cpu_latency_limit().unwrap(), 0);
                drop(request);
            }
            Err(e) => {
                // No PM QoS device (containers) or no access: what the host
                // would say about it.
                let note = explain_cpu_latency_failure(&e);
                let missing = e.kind() == std::io::ErrorKind::NotFound;
                assert_eq!(note.is_none(), missing, "{e}: {note:?}");
                eprintln!("no CPU latency request here: {e}");
            }
        }
    }

    #[test]
    fn a_refused_cpu_latency_request_names_the_group_and_a_missing_device_is_quiet() {
        let denied = std::io::Error::from_raw_os_error(libc::EACCES);
        let note = explain_cpu_latency_failure(&denied).unwrap();
        assert!(note.contains("/dev/cpu_dma_latency"), "{note}");
        assert!(note.contains("'hal' group"), "{note}");
        let missing = std::io::Error::from_raw_os_error(libc::ENOENT);
        assert_eq!(explain_cpu_latency_failure(&missing), None);
    }

    #[test]
    fn a_short_slice_keeps_the_thread_an_ordinary_one() {
        std::thread::spawn(|| {
            let took = short_slice();
            // SAFETY: sched_getscheduler takes a pid only.
            let policy = unsafe { libc::sched_getscheduler(0) };
            assert_eq!(policy, libc::SCHED_OTHER, "short slice taken: {took}");
            // Where the kernel shows the slice, it is the one asked for.
            let sched = std::fs::read_to_string("/proc/thread-self/sched").unwrap_or_default();
            if let Some(line) = sched.lines().find(|l| l.starts_with("se.slice")) {
                let slice = line.rsplit(' ').next().unwrap_or("");
                assert!(!took || slice == SHORT_SLICE_NS.to_string(), "{line}");
            }
        })
        .join()
        .unwrap();
    }

    #[test]
    fn cpu_numbers_are_checked_against_the_allowed_set() {
        assert_eq!(parse_cpu("RTAPI_CPU_NUMBER", " 1", &[0, 1]).ok(), Some(1));
        let e = parse_cpu("RTAPI_CPU_NUMBER", "x", &[0, 1])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("RTAPI_CPU_NUMBER='x' is not a CPU number"),
            "{e}"
        );
        let e = parse_cpu("RTAPI_CPU_NUMBER", "5", &[0, 1, 2, 6])
            .unwrap_err()
            .to_string();
        assert!(e.contains("may only use CPU 0-2,6"), "{e}");
        assert_eq!(cpu_list(&[]), "none");
        assert_eq!(cpu_list(&[3]), "3");
    }

    #[test]
    fn the_default_cpu_is_one_we_may_use() {
        let cpu = default_cpu().expect("some CPU is allowed");
        pin_to_cpu(cpu).expect("pinning to an allowed CPU works");
    }
}
