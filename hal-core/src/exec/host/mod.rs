//! The HAL host: creates and owns the instance, runs realtime components
//! and threads, and brings everything to a safe state on a fault or exit.
//!
//! This file holds the host's state and its small accessors; the
//! `impl Host` blocks of its jobs live beside it: `lifecycle` (start-up,
//! start/stop, faults, shutdown), `options` (the threads' switches and
//! CPUs), `functs` (threads and their function lists) and `loading`
//! (`loadrt`, `unloadrt`, realtime components).

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering::*};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::funct::FunctCode;
use super::realtime::{self, RealtimeMode};
use super::reaper::Reaper;
use super::thread::{HostShared, ThreadCtl};
use crate::error::{HalError, Result};
use crate::objects::{Component, HostLock, Instance};
use crate::rtlog::{RtLog, RtLogService};

mod functs;
mod lifecycle;
mod loading;
mod options;

pub use loading::RtComponentBuilder;

/// Default size of the shared segment: 32 MiB, sixteen times LinuxCNC's.
pub const DEFAULT_SHM_SIZE: u64 = 32 << 20;

/// How to start a host.
#[derive(Debug, Clone)]
pub struct HostConfig {
    /// Instance name (see [`crate::instance_from_env`]).
    pub instance: String,
    /// Segment size in bytes.
    pub shm_size: u64,
    /// Whether to ask for realtime scheduling.
    pub realtime: RealtimeMode,
    /// The CPU every HAL thread runs on unless it is given its own (see
    /// [`Host::set_thread_cpu`]), as text: LinuxCNC's `RTAPI_CPU_NUMBER`.
    /// [`Host::create`] refuses a number that is not one of the process's
    /// CPUs. `None`: under realtime the last CPU the process may use (as
    /// LinuxCNC), without realtime any CPU.
    pub rt_cpu: Option<String>,
}

impl HostConfig {
    /// A configuration for tests: an instance name no other test or test
    /// process uses (`t-<tag>-<pid>-<n>`), a 4 MiB segment, no realtime
    /// scheduling (tests run side by side). Feature `testing`.
    #[cfg(any(test, feature = "testing"))]
    pub fn for_tests(tag: &str) -> HostConfig {
        static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = NEXT.fetch_add(1, Relaxed);
        HostConfig {
            instance: format!("t-{tag}-{}-{n}", std::process::id()),
            shm_size: 4 << 20,
            realtime: RealtimeMode::Off,
            rt_cpu: None,
        }
    }

    /// A configuration for `instance` with default size; realtime is
    /// attempted unless `HAL_NO_REALTIME` is set; `RTAPI_CPU_NUMBER`
    /// chooses the threads' CPU.
    pub fn new(instance: &str) -> HostConfig {
        HostConfig {
            instance: instance.to_string(),
            shm_size: std::env::var("HAL_SHM_SIZE")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(DEFAULT_SHM_SIZE),
            realtime: if std::env::var_os("HAL_NO_REALTIME").is_some() {
                RealtimeMode::Off
            } else {
                RealtimeMode::Auto
            },
            rt_cpu: std::env::var("RTAPI_CPU_NUMBER").ok(),
        }
    }
}

type Hook = Box<dyn FnMut() + Send>;

struct FunctSlot {
    name: String,
    rec_off: u64,
    code: Arc<FunctCode>,
    reentrant: bool,
    /// Threads whose list holds this function (host bookkeeping; the
    /// segment's copy is for display only).
    threads: Vec<String>,
}

struct HostThread {
    ctl: Arc<ThreadCtl>,
    join: Option<JoinHandle<()>>,
    /// Code ids in execution order.
    functs: Vec<usize>,
    /// Code ids of the init cycle.
    init: Vec<usize>,
    /// Whether `functs` or `init` changed since the executor's list was
    /// built (changes made while threads are stopped are built at start).
    stale: bool,
}

impl HostThread {
    /// Whether function `id` is in this thread's list or init list.
    fn holds(&self, id: usize) -> bool {
        self.functs.contains(&id) || self.init.contains(&id)
    }
}

struct LoadedComp {
    /// The `loadrt` module that made it, if any.
    module: Option<&'static str>,
    comp: Component,
    functs: Vec<usize>,
    safe_state: Option<Hook>,
}

#[derive(Default)]
struct HostState {
    functs: Vec<Option<FunctSlot>>,
    by_name: HashMap<String, usize>,
    threads: Vec<HostThread>,
    comps: Vec<LoadedComp>,
    /// Loaded modules, in load order.
    modules: Vec<&'static str>,
    memory_locked: bool,
    /// Held from the first `start` while the host lives (see
    /// [`realtime::request_zero_cpu_latency`]).
    cpu_latency: Option<realtime::CpuLatencyRequest>,
    /// Per-function timing of threads created from now on.
    timing_default: bool,
}

/// The host of one HAL instance.
pub struct Host {
    inst: Instance,
    shared: Arc<HostShared>,
    state: Arc<Mutex<HostState>>,
    supervisor: Option<JoinHandle<()>>,
    /// Removes user-space components whose process died.
    reaper: Reaper,
    notes: Mutex<Vec<String>>,
    notes_printed: AtomicBool,
    shut_down: AtomicBool,
    rt_log: RtLogService,
    /// CPUs the process may use, found at start.
    allowed_cpus: Vec<usize>,
    /// Where threads without a CPU of their own run (`None`: anywhere).
    default_cpu: Option<usize>,
    _lock: HostLock,
}

impl Host {
    /// The instance this host serves.
    pub fn instance(&self) -> &Instance {
        &self.inst
    }

    /// Whether threads run under SCHED_FIFO.
    pub fn is_realtime(&self) -> bool {
        self.shared.realtime
    }

    /// Notes about the set-up (missing permissions and how to grant them, a
    /// reclaimed segment). Each is also printed once to stderr when it
    /// first matters.
    pub fn notes(&self) -> Vec<String> {
        lock(&self.notes).clone()
    }

    pub(super) fn add_note(&self, note: String) {
        let mut n = lock(&self.notes);
        if !n.contains(&note) {
            if self.notes_printed.load(SeqCst) {
                eprintln!("HAL: note: {note}");
            }
            n.push(note);
        }
    }

    /// The realtime-safe message log ([`crate::rtlog`]): realtime
    /// functions log through it, a thread of the host prints the messages
    /// to stderr. The first call starts that thread.
    pub fn rt_log(&self) -> RtLog {
        self.rt_log.handle()
    }

    /// Prints the messages waiting in the realtime log now, instead of at
    /// the drain thread's next turn.
    pub fn flush_rt_log(&self) {
        self.rt_log.flush();
    }
}

/// Waits until the executor is idle or has passed a boundary.
fn wait_for_boundary(ctl: &ThreadCtl, limit: Duration) -> bool {
    let e0 = ctl.epoch.load(SeqCst);
    if ctl.idle.load(SeqCst) {
        return true;
    }
    let start = Instant::now();
    while ctl.epoch.load(SeqCst) == e0 && !ctl.idle.load(SeqCst) {
        if start.elapsed() > limit {
            return false;
        }
        std::thread::sleep(Duration::from_micros(50));
    }
    true
}

fn thread_index(st: &HostState, name: &str) -> Result<usize> {
    st.threads
        .iter()
        .position(|t| t.ctl.name == name)
        .ok_or_else(|| HalError::NotFound {
            kind: "thread",
            name: name.to_string(),
        })
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Found by the loadrt fuzz target under libFuzzer: every load added
    /// a slot per function to the host's table and no unload freed one
    /// for reuse, so the host grew by about 80 bytes per function per
    /// load, for ever.
    #[test]
    fn function_slots_freed_by_unload_are_reused() {
        let host = Host::create(HostConfig::for_tests("slots")).unwrap();
        for _ in 0..50 {
            let mut b = host.new_rt_component("c").unwrap();
            b.funct("c.a", false, |_| {}).unwrap();
            b.funct("c.b", false, |_| {}).unwrap();
            b.ready().unwrap();
            host.unload("c").unwrap();
        }
        assert_eq!(lock(&host.state).functs.len(), 2);
    }
}
