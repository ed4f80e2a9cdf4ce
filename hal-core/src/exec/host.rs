//! The HAL host: creates and owns the instance, runs realtime components
//! and threads, and brings everything to a safe state on a fault or exit.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::clock::TickClock;
use super::funct::{ExecList, FunctCode, FunctCtx, TimingOut};
use super::realtime::{self, RealtimeMode, TOP_PRIORITY};
use super::reaper::Reaper;
use super::thread::{self, HostShared, Placement, ThreadCtl, NO_FAULT, SUPERVISOR_EXIT};
use super::MissedDeadline;
use crate::error::{HalError, Result};
use crate::handles::{Param, Pin};
use crate::module::{ModuleArgs, ModuleDef};
use crate::objects::funct::{
    add_entry_tx, delete_thread_tx, new_funct_tx, new_thread_tx, position_to_index,
    remove_entry_tx, NewThread,
};
use crate::objects::{validate_instance_name, Component, ComponentKind, HostLock, Instance};
use crate::paths;
use crate::rtlog::{RtLog, RtLogService};
use crate::shm::{FunctRec, Segment, ThreadRec, THREAD_CATCH_UP, THREAD_NO_FUNCT_TIMING};

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
    /// Starts a host: takes the instance's lock (failing if another host
    /// holds it), reclaims a segment left by a dead host, creates a fresh one.
    pub fn create(config: HostConfig) -> Result<Host> {
        validate_instance_name(&config.instance)?;
        let allowed_cpus = realtime::allowed_cpus();
        let rt_cpu = match &config.rt_cpu {
            Some(text) => Some(
                realtime::parse_cpu("RTAPI_CPU_NUMBER", text, &allowed_cpus).map_err(|reason| {
                    HalError::BadValue {
                        what: "the realtime CPU".into(),
                        reason,
                    }
                })?,
            ),
            None => None,
        };
        let lock = HostLock::acquire(&config.instance)?;
        let mut notes = Vec::new();
        let seg_path = paths::segment(&config.instance);
        if std::fs::symlink_metadata(&seg_path).is_ok() {
            // We hold the lock, so whoever made this is gone.
            std::fs::remove_file(&seg_path)
                .map_err(|e| HalError::io("removing stale segment", &seg_path, e))?;
            notes.push(format!(
                "reclaimed segment {} left by a host that died",
                seg_path.display()
            ));
        }
        let seg = Arc::new(Segment::create(&config.instance, config.shm_size)?);
        let (realtime, cpu_note) = match config.realtime {
            RealtimeMode::Off => (false, None),
            RealtimeMode::Auto => match realtime::probe_fifo(TOP_PRIORITY) {
                Ok(()) => (true, None),
                Err(why) => (false, Some(why)),
            },
        };
        if let Some(why) = cpu_note {
            notes.push(format!(
                "realtime scheduling unavailable, threads run without it \
                 (serialised, no preemption): {why}"
            ));
        }
        let shared = Arc::new(HostShared {
            seg: seg.clone(),
            running: AtomicBool::new(false),
            gate: (Mutex::new(()), Condvar::new()),
            serial: (!realtime).then(|| Mutex::new(())),
            fault: AtomicUsize::new(NO_FAULT),
            fault_signal: (Mutex::new(0), Condvar::new()),
            clock: TickClock::calibrate(),
            realtime,
            start_ns: AtomicU64::new(0),
        });
        let state = Arc::new(Mutex::new(HostState {
            timing_default: true,
            ..HostState::default()
        }));
        let default_cpu = rt_cpu.or_else(|| {
            if realtime {
                allowed_cpus.last().copied()
            } else {
                None
            }
        });
        let reaper = Reaper::start(Instance { seg: seg.clone() })?;
        let supervisor = {
            let shared = shared.clone();
            let state = state.clone();
            std::thread::Builder::new()
                .name("hal-supervisor".into())
                .spawn(move || supervise(shared, state))
                .map_err(|e| HalError::io("starting supervisor thread", "", e))?
        };
        Ok(Host {
            inst: Instance { seg },
            shared,
            state,
            supervisor: Some(supervisor),
            reaper,
            notes: Mutex::new(notes),
            notes_printed: AtomicBool::new(false),
            shut_down: AtomicBool::new(false),
            rt_log: RtLogService::new(),
            allowed_cpus,
            default_cpu,
            _lock: lock,
        })
    }

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

    fn add_note(&self, note: String) {
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

    /// Turns per-function timing (`<funct>.time`, `.tmax`) on or off for
    /// every thread, and for threads created later; a thread's own `time`
    /// is always measured.
    pub fn set_function_timing(&self, on: bool) {
        let mut st = lock(&self.state);
        st.timing_default = on;
        for t in &st.threads {
            // A thread's record only goes away with the thread.
            let _ = self.set_option(&t.ctl, THREAD_NO_FUNCT_TIMING, !on);
        }
    }

    /// Turns per-function timing on or off for one thread (halcmd
    /// `setthread THREAD timing=on|off`). Off, the thread's functions'
    /// `.time`, `.tmax` and `.tmax-increased` keep their last values and
    /// the thread reads the clock twice per cycle instead of once per
    /// function.
    pub fn set_thread_timing(&self, thread: &str, on: bool) -> Result<()> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        self.set_option(&st.threads[ti].ctl, THREAD_NO_FUNCT_TIMING, !on)
    }

    /// Chooses what a thread does with missed deadlines (halcmd
    /// `setthread THREAD missed=skip|catch-up`); see [`MissedDeadline`].
    pub fn set_missed_deadline(&self, thread: &str, policy: MissedDeadline) -> Result<()> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let catch_up = policy == MissedDeadline::CatchUp;
        self.set_option(&st.threads[ti].ctl, THREAD_CATCH_UP, catch_up)
    }

    fn set_option(&self, ctl: &ThreadCtl, bit: u64, set: bool) -> Result<()> {
        if set {
            ctl.options.fetch_or(bit, Relaxed);
        } else {
            ctl.options.fetch_and(!bit, Relaxed);
        }
        self.publish_options(ctl)
    }

    /// Copies a thread's switch bits into its segment record, where other
    /// processes read them.
    fn publish_options(&self, ctl: &ThreadCtl) -> Result<()> {
        self.inst.tx(|tx| {
            let rec: &ThreadRec = tx.rec(ctl.rec_off)?;
            tx.set(&rec.options, ctl.options.load(Relaxed))
        })
    }

    /// A thread's integrator switches: whether its functions are timed,
    /// and what it does with missed deadlines.
    pub fn thread_options(&self, thread: &str) -> Result<(bool, MissedDeadline)> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let bits = st.threads[ti].ctl.options.load(Relaxed);
        let policy = if bits & THREAD_CATCH_UP != 0 {
            MissedDeadline::CatchUp
        } else {
            MissedDeadline::Skip
        };
        Ok((bits & THREAD_NO_FUNCT_TIMING == 0, policy))
    }

    /// Puts a thread on `cpu`, or back on the default placement for `None`
    /// (halcmd `setthread THREAD cpu=N|default`); takes effect at once,
    /// running or not. Two threads on different CPUs under realtime can
    /// run at the same time: HAL files that rely on the faster thread
    /// preempting the slower one must keep them on one CPU.
    pub fn set_thread_cpu(&self, thread: &str, cpu: Option<usize>) -> Result<()> {
        if let Some(c) = cpu {
            if !self.allowed_cpus.contains(&c) {
                return Err(HalError::BadValue {
                    what: format!("CPU of thread '{thread}'"),
                    reason: format!(
                        "CPU {c} is not one this process may use ({})",
                        realtime::cpu_list(&self.allowed_cpus)
                    ),
                });
            }
        }
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let ctl = &st.threads[ti].ctl;
        self.inst.tx(|tx| {
            let rec: &ThreadRec = tx.rec(ctl.rec_off)?;
            tx.set(&rec.cpu, cpu.map_or(0, |c| c as u64 + 1))
        })?;
        let mut p = lock(&ctl.placement);
        p.cpu = cpu.or(self.default_cpu);
        match p.tid {
            Some(tid) => realtime::place_thread(tid, p.cpu, &self.allowed_cpus).map_err(|reason| {
                HalError::BadValue {
                    what: format!("CPU of thread '{thread}'"),
                    reason,
                }
            }),
            None => Ok(()),
        }
    }

    /// The CPUs a thread's OS thread may run on, as the kernel reports
    /// them (`sched_getaffinity`); `None` before its OS thread has started.
    pub fn thread_affinity(&self, thread: &str) -> Result<Option<Vec<usize>>> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let tid = lock(&st.threads[ti].ctl.placement).tid;
        tid.map(|tid| {
            realtime::thread_affinity(tid).map_err(|source| HalError::BadValue {
                what: format!("thread '{thread}'"),
                reason: source,
            })
        })
        .transpose()
    }

    /// Starts building a realtime component in this host.
    pub fn new_rt_component(&self, name: &str) -> Result<RtComponentBuilder<'_>> {
        let comp = self.inst.new_component(name, ComponentKind::Realtime)?;
        Ok(RtComponentBuilder {
            host: self,
            comp: Some(comp),
            functs: Vec::new(),
            safe_state: None,
        })
    }

    fn export_funct(
        &self,
        comp: &Component,
        name: &str,
        uses_fp: bool,
        code: FunctCode,
        reentrant: bool,
    ) -> Result<usize> {
        let mut st = lock(&self.state);
        // A slot freed by an unload is taken again, so that a host that
        // loads and unloads for months does not grow its table; never the
        // slot of a function whose fault still stands (`fault` names it).
        let faulted = self.shared.fault.load(Acquire);
        let code_id = (0..st.functs.len())
            .find(|&i| st.functs[i].is_none() && i != faulted)
            .unwrap_or(st.functs.len());
        let rec_off = self
            .inst
            .tx(|tx| new_funct_tx(tx, comp.offset(), name, code_id as u64, uses_fp, reentrant))?;
        let slot = Some(FunctSlot {
            name: name.to_string(),
            rec_off,
            code: Arc::new(code),
            reentrant,
            threads: Vec::new(),
        });
        if code_id == st.functs.len() {
            st.functs.push(slot);
        } else {
            st.functs[code_id] = slot;
        }
        st.by_name.insert(name.to_string(), code_id);
        Ok(code_id)
    }

    /// Removes functions of a component that never became ready, taking
    /// them out of any thread first.
    fn drop_functs(&self, ids: &[usize]) {
        let mut st = lock(&self.state);
        for id in ids {
            for ti in 0..st.threads.len() {
                while st.threads[ti].holds(*id) {
                    if self.remove_from_thread(&mut st, ti, *id).is_err() {
                        break;
                    }
                }
            }
        }
        for &id in ids {
            if let Some(slot) = st.functs.get_mut(id).and_then(Option::take) {
                st.by_name.remove(&slot.name);
            }
        }
    }

    /// Creates a thread (as `loadrt threads` does) with LinuxCNC's rules:
    /// the first thread fixes the base period, later ones are rounded to a
    /// multiple of it and must not be faster than any earlier one. Returns
    /// the period in use. `cpu` pins this thread to a CPU explicitly.
    pub fn create_thread(
        &self,
        name: &str,
        period_ns: i64,
        uses_fp: bool,
        cpu: Option<usize>,
    ) -> Result<i64> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "create_thread")?;
        let mut st = lock(&self.state);
        let (off, period) = self.inst.tx(|tx| {
            new_thread_tx(
                tx,
                &NewThread {
                    name,
                    period: period_ns,
                    uses_fp,
                    cpu,
                },
            )
        })?;
        let seg = &self.inst.seg;
        let built = (|| -> Result<(i32, Arc<ThreadCtl>)> {
            let rec: &ThreadRec = seg.rec(off)?;
            let priority = rec.priority.load(Relaxed) as i32;
            let ctl = Arc::new(ThreadCtl {
                name: name.to_string(),
                period,
                priority,
                placement: Mutex::new(Placement {
                    cpu: cpu.or(self.default_cpu),
                    tid: None,
                }),
                rec_off: off,
                options: AtomicU64::new(if st.timing_default {
                    0
                } else {
                    THREAD_NO_FUNCT_TIMING
                }),
                list: AtomicPtr::new(Box::into_raw(Box::new(ExecList::new(seg)))),
                epoch: AtomicU64::new(0),
                idle: AtomicBool::new(true),
                exit: AtomicBool::new(false),
                init_done: AtomicBool::new(false),
                time: Pin::new(seg, rec.time_pin.load(Relaxed))?,
                tmax: Param::new(seg, rec.tmax_param.load(Relaxed))?,
                beat: Pin::new(seg, rec.beat_pin.load(Relaxed))?,
                done_deadline: AtomicU64::new(0),

                faster: st.threads.iter().map(|t| t.ctl.clone()).collect(),
            });
            Ok((priority, ctl))
        })();
        let built = built.and_then(|b| self.publish_options(&b.1).map(|()| b));
        let (_, ctl) = match built {
            Ok(b) => b,
            Err(e) => {
                let _ = self.inst.tx(|tx| delete_thread_tx(tx, off));
                return Err(e);
            }
        };
        let join = {
            let ctl = ctl.clone();
            let shared = self.shared.clone();
            let allowed = self.allowed_cpus.clone();
            std::thread::Builder::new()
                .name(format!("hal-{name}"))
                .spawn(move || thread::run(ctl, shared, allowed))
        };
        let join = match join {
            Ok(j) => j,
            Err(e) => {
                let _ = self.inst.tx(|tx| delete_thread_tx(tx, off));
                // SAFETY: the list was never shared with a running executor.
                drop(unsafe { Box::from_raw(ctl.list.load(SeqCst)) });
                return Err(HalError::io("starting thread", "", e));
            }
        };
        st.threads.push(HostThread {
            ctl,
            join: Some(join),
            functs: Vec::new(),
            init: Vec::new(),
        });
        drop(st);
        // Set-up notes matter once threads exist; say them once.
        if !self.notes_printed.swap(true, SeqCst) {
            for note in lock(&self.notes).iter() {
                eprintln!("HAL: note: {note}");
            }
        }
        Ok(period)
    }

    /// Deletes a thread; its functions stay loaded.
    pub fn delete_thread(&self, name: &str) -> Result<()> {
        let mut st = lock(&self.state);
        let idx = thread_index(&st, name)?;
        let mut t = st.threads.remove(idx);
        t.ctl.exit.store(true, SeqCst);
        self.wake_executors();
        if let Some(j) = t.join.take() {
            let _ = j.join();
        }
        for id in &t.functs {
            if let Some(Some(slot)) = st.functs.get_mut(*id) {
                slot.threads.retain(|n| n != name);
            }
        }
        // SAFETY: the executor has exited; nobody else reads the list.
        drop(unsafe { Box::from_raw(t.ctl.list.swap(std::ptr::null_mut(), SeqCst)) });
        self.inst.tx(|tx| delete_thread_tx(tx, t.ctl.rec_off))
    }

    /// Adds a function to a thread (halcmd `addf`). `position` as halcmd:
    /// -1 appends, 1 puts it first, -2 before the last, and so on.
    pub fn addf(&self, funct: &str, thread: &str, position: i32) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "add_funct_to_thread")?;
        let mut st = lock(&self.state);
        let id = *st.by_name.get(funct).ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        let ti = thread_index(&st, thread)?;
        let slot = st.functs[id].as_ref().ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        if !slot.reentrant && !slot.threads.is_empty() {
            return Err(HalError::FunctInUse {
                funct: funct.to_string(),
                thread: slot.threads[0].clone(),
            });
        }
        let len = st.threads[ti].functs.len();
        let index = position_to_index(position, len).ok_or_else(|| HalError::BadPosition {
            thread: thread.to_string(),
            position,
            len,
        })?;
        let (rec_off, thread_off) = (slot.rec_off, st.threads[ti].ctl.rec_off);
        let mut functs = st.threads[ti].functs.clone();
        functs.insert(index, id);
        // Everything that can fail happens before anything changes.
        let list = self.build_list(&st, &functs, &st.threads[ti].init)?;
        self.inst
            .tx(|tx| add_entry_tx(tx, thread_off, rec_off, index))?;
        self.swap_list(&st.threads[ti].ctl, list);
        st.threads[ti].functs = functs;
        if let Some(slot) = st.functs[id].as_mut() {
            slot.threads.push(thread.to_string());
        }
        Ok(())
    }

    /// Registers a function for the init cycle of a thread (halcmd
    /// `initf`): it runs once, on the thread's first cycle after `start`,
    /// instead of the function list. Refused once that cycle has run.
    pub fn initf(&self, funct: &str, thread: &str) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "add_funct_to_thread")?;
        let mut st = lock(&self.state);
        let id = *st.by_name.get(funct).ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        let ti = thread_index(&st, thread)?;
        if st.threads[ti].ctl.init_done.load(SeqCst) {
            return Err(HalError::BadValue {
                what: format!("initf {funct} {thread}"),
                reason: format!("thread '{thread}' has already run its init cycle"),
            });
        }
        let slot = st.functs[id].as_ref().ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        if !slot.reentrant && slot.threads.iter().any(|t| t != thread) {
            return Err(HalError::FunctInUse {
                funct: funct.to_string(),
                thread: slot.threads[0].clone(),
            });
        }
        let (rec_off, thread_off) = (slot.rec_off, st.threads[ti].ctl.rec_off);
        let mut init = st.threads[ti].init.clone();
        init.push(id);
        let list = self.build_list(&st, &st.threads[ti].functs, &init)?;
        self.inst
            .tx(|tx| crate::objects::funct::add_init_entry_tx(tx, thread_off, rec_off))?;
        self.swap_list(&st.threads[ti].ctl, list);
        st.threads[ti].init = init;
        if let Some(slot) = st.functs[id].as_mut() {
            slot.threads.push(thread.to_string());
        }
        Ok(())
    }

    /// Removes a function from a thread (halcmd `delf`); with no thread,
    /// from every thread it is in.
    pub fn delf(&self, funct: &str, thread: Option<&str>) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "del_funct_from_thread")?;
        let mut st = lock(&self.state);
        let id = *st.by_name.get(funct).ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        let targets: Vec<usize> = match thread {
            Some(t) => {
                let ti = thread_index(&st, t)?;
                if !st.threads[ti].holds(id) {
                    return Err(HalError::FunctNotInThread {
                        funct: funct.to_string(),
                        thread: t.to_string(),
                    });
                }
                vec![ti]
            }
            None => (0..st.threads.len())
                .filter(|&i| st.threads[i].holds(id))
                .collect(),
        };
        for ti in targets {
            self.remove_from_thread(&mut st, ti, id)?;
        }
        Ok(())
    }

    fn remove_from_thread(&self, st: &mut HostState, ti: usize, id: usize) -> Result<()> {
        let Some(slot) = st.functs.get(id).and_then(Option::as_ref) else {
            return Ok(());
        };
        let (rec_off, thread_off) = (slot.rec_off, st.threads[ti].ctl.rec_off);
        // One entry per call, an init entry before a cyclic one, as
        // remove_entry_tx takes it off the thread's lists.
        let mut functs = st.threads[ti].functs.clone();
        let mut init = st.threads[ti].init.clone();
        if let Some(pos) = init.iter().position(|&f| f == id) {
            init.remove(pos);
        } else if let Some(pos) = functs.iter().position(|&f| f == id) {
            functs.remove(pos);
        }
        let list = self.build_list(st, &functs, &init)?;
        self.inst
            .tx(|tx| remove_entry_tx(tx, thread_off, rec_off).map(|_| ()))?;
        self.swap_list(&st.threads[ti].ctl, list);
        st.threads[ti].functs = functs;
        st.threads[ti].init = init;
        let tname = st.threads[ti].ctl.name.clone();
        if let Some(Some(slot)) = st.functs.get_mut(id) {
            if let Some(p) = slot.threads.iter().position(|n| *n == tname) {
                slot.threads.remove(p);
            }
        }
        Ok(())
    }

    /// Builds an executor list for the code ids `functs`.
    fn build_list(&self, st: &HostState, functs: &[usize], init: &[usize]) -> Result<ExecList> {
        let seg = &self.inst.seg;
        let mut list = ExecList::new(seg);
        for &id in init {
            if let Some(slot) = st.functs.get(id).and_then(Option::as_ref) {
                list.push_init(slot.code.clone(), id);
            }
        }
        for &id in functs {
            let Some(slot) = st.functs.get(id).and_then(Option::as_ref) else {
                continue;
            };
            let rec: &FunctRec = seg.rec(slot.rec_off)?;
            let timing = TimingOut::new(
                &Pin::new(seg, rec.time_pin.load(Relaxed))?,
                &Param::new(seg, rec.tmax_param.load(Relaxed))?,
                &Param::new(seg, rec.tmax_inc_param.load(Relaxed))?,
            );
            list.push(slot.code.clone(), id, timing);
        }
        Ok(list)
    }

    /// Swaps a thread's list and frees the old one once the executor has
    /// passed a cycle boundary. Never gives up: freeing (or forgetting) a
    /// list the executor may still run would let a non-reentrant function
    /// run on two threads.
    fn swap_list(&self, ctl: &ThreadCtl, list: ExecList) {
        let new = Box::into_raw(Box::new(list));
        let old = ctl.list.swap(new, SeqCst);
        let mut warned = false;
        while !wait_for_boundary(ctl, Duration::from_secs(10)) {
            if !warned {
                warned = true;
                self.add_note(format!(
                    "thread '{}' has not reached a cycle boundary for 10 s; still waiting",
                    ctl.name
                ));
            }
        }
        // SAFETY: the executor is idle or has finished a cycle since the
        // swap, so it no longer references `old`.
        drop(unsafe { Box::from_raw(old) });
    }

    /// Starts all threads (halcmd `start`). Refused after a fault until
    /// [`Host::clear_fault`].
    pub fn start(&self) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::RUN, "start_threads")?;
        let fault = self.shared.fault.load(Acquire);
        if fault != NO_FAULT {
            return Err(HalError::Faulted {
                instance: self.inst.name().to_string(),
                funct: self.funct_name(fault),
            });
        }
        {
            let mut st = lock(&self.state);
            let mut notes = Vec::new();
            if !st.memory_locked {
                st.memory_locked = true;
                if let Err(why) = realtime::lock_memory() {
                    notes.push(why);
                }
                if std::env::var_os("HAL_NO_CPU_LATENCY").is_none() {
                    match realtime::request_zero_cpu_latency() {
                        Ok(request) => st.cpu_latency = Some(request),
                        // Without realtime scheduling the request is a
                        // bonus; its absence is not worth a note.
                        Err(e) if self.shared.realtime => {
                            notes.extend(realtime::explain_cpu_latency_failure(&e))
                        }
                        Err(_) => {}
                    }
                }
            }
            drop(st);
            for why in notes {
                self.add_note(why);
            }
        }
        // Threads start on a common grid a little ahead, so that all are
        // awake before the first deadline and due together afterwards.
        self.shared
            .start_ns
            .store(super::clock::monotonic_ns() + 200_000, SeqCst);
        self.shared.running.store(true, SeqCst);
        self.wake_executors();
        Ok(())
    }

    /// Stops all threads (halcmd `stop`). Threads freeze between cycles;
    /// outputs keep their values: this is not a safe state. Returns once no
    /// function is running.
    pub fn stop(&self) {
        self.shared.running.store(false, SeqCst);
        let st = lock(&self.state);
        for t in &st.threads {
            wait_for_boundary(&t.ctl, Duration::from_secs(10));
        }
    }

    /// Whether threads are started.
    pub fn is_running(&self) -> bool {
        self.shared.running.load(Acquire)
    }

    /// The function that panicked, if any.
    pub fn fault(&self) -> Option<String> {
        match self.shared.fault.load(Acquire) {
            NO_FAULT => None,
            id => Some(self.funct_name(id)),
        }
    }

    /// Forgets a fault so that threads may be started again.
    pub fn clear_fault(&self) {
        self.shared.fault.store(NO_FAULT, SeqCst);
    }

    fn funct_name(&self, id: usize) -> String {
        lock(&self.state)
            .functs
            .get(id)
            .and_then(|s| s.as_ref().map(|s| s.name.clone()))
            .unwrap_or_else(|| format!("#{id}"))
    }

    fn wake_executors(&self) {
        let (m, cv) = &self.shared.gate;
        let _g = lock(m);
        cv.notify_all();
    }

    /// Unloads a realtime component: takes its functions out of every
    /// thread (waiting for each thread to pass a boundary), calls its
    /// safe-state hook, then frees it.
    pub fn unload(&self, comp: &str) -> Result<()> {
        let mut st = lock(&self.state);
        let ci = st
            .comps
            .iter()
            .position(|c| c.comp.name() == comp)
            .ok_or_else(|| HalError::NotFound {
                kind: "component",
                name: comp.to_string(),
            })?;
        self.unload_at(&mut st, ci)
    }

    fn unload_at(&self, st: &mut HostState, ci: usize) -> Result<()> {
        let ids = st.comps[ci].functs.clone();
        for id in &ids {
            for ti in 0..st.threads.len() {
                while st.threads[ti].holds(*id) {
                    self.remove_from_thread(st, ti, *id)?;
                }
            }
        }
        let mut lc = st.comps.remove(ci);
        if let Some(hook) = lc.safe_state.as_mut() {
            hook();
        }
        for id in &ids {
            if let Some(slot) = st.functs.get_mut(*id).and_then(Option::take) {
                st.by_name.remove(&slot.name);
            }
        }
        drop(lc);
        Ok(())
    }

    /// Loads a module (halcmd `loadrt`): parses `args` against its table
    /// and runs its `load`. On any error, every component and thread the
    /// load created is removed again.
    pub fn loadrt<S: AsRef<str>>(&self, def: &'static ModuleDef, args: &[S]) -> Result<()> {
        self.inst.check_unlocked(crate::lock_bits::LOAD, "loadrt")?;
        if lock(&self.state).modules.contains(&def.name) {
            return Err(HalError::ModuleLoaded {
                name: def.name.to_string(),
            });
        }
        let parsed = ModuleArgs::parse(def.name, def.params, args)?;
        let (comps_before, threads_before) = {
            let st = lock(&self.state);
            (st.comps.len(), st.threads.len())
        };
        let result = (def.load)(self, &parsed).and_then(|()| {
            // What `save` prints after `loadrt `: the name, a space, the
            // arguments (LinuxCNC keeps the space when there are none).
            let saved = format!("{} {}", def.name, parsed.raw());
            let mut st = lock(&self.state);
            for c in &mut st.comps[comps_before..] {
                c.module = Some(def.name);
                c.comp.set_loadrt_args(&saved)?;
            }
            st.modules.push(def.name);
            Ok(())
        });
        if result.is_err() {
            let mut st = lock(&self.state);
            while st.comps.len() > comps_before {
                let last = st.comps.len() - 1;
                let _ = self.unload_at(&mut st, last);
            }
            let extra: Vec<String> = st.threads[threads_before.min(st.threads.len())..]
                .iter()
                .map(|t| t.ctl.name.clone())
                .collect();
            drop(st);
            for t in extra.iter().rev() {
                let _ = self.delete_thread(t);
            }
        }
        result
    }

    /// Unloads a module (halcmd `unloadrt`), or every module for `all`,
    /// newest first.
    pub fn unloadrt(&self, name: &str) -> Result<()> {
        let mut st = lock(&self.state);
        let targets: Vec<&'static str> = if name == "all" {
            st.modules.iter().rev().copied().collect()
        } else {
            match st.modules.iter().find(|m| **m == name) {
                Some(m) => vec![*m],
                None => {
                    return Err(HalError::NotFound {
                        kind: "module",
                        name: name.to_string(),
                    })
                }
            }
        };
        for m in targets {
            while let Some(ci) = st.comps.iter().rposition(|c| c.module == Some(m)) {
                self.unload_at(&mut st, ci)?;
            }
            st.modules.retain(|x| *x != m);
        }
        Ok(())
    }

    /// Names of the loaded modules, in load order.
    pub fn loaded_modules(&self) -> Vec<&'static str> {
        lock(&self.state).modules.clone()
    }

    /// Names of the loaded realtime components, in load order.
    pub fn loaded_components(&self) -> Vec<String> {
        lock(&self.state)
            .comps
            .iter()
            .map(|c| c.comp.name().to_string())
            .collect()
    }

    /// Stops threads, calls every safe-state hook in reverse load order,
    /// unloads everything and removes the segment. Called by `Drop` too.
    pub fn shutdown(&self) {
        if self.shut_down.swap(true, SeqCst) {
            return;
        }
        self.reaper.stop();
        self.shared.running.store(false, SeqCst);
        let mut st = lock(&self.state);
        for t in &st.threads {
            t.ctl.exit.store(true, SeqCst);
        }
        self.wake_executors();
        for t in &mut st.threads {
            if let Some(j) = t.join.take() {
                let _ = j.join();
            }
        }
        for c in st.comps.iter_mut().rev() {
            if let Some(h) = c.safe_state.as_mut() {
                h();
            }
        }
        while let Some(c) = st.comps.pop() {
            drop(c);
        }
        for t in st.threads.drain(..) {
            let p = t.ctl.list.swap(std::ptr::null_mut(), SeqCst);
            if !p.is_null() {
                // SAFETY: every executor has exited, so nobody else reads
                // the list, and the swap took the only pointer to it.
                drop(unsafe { Box::from_raw(p) });
            }
        }
        st.functs.clear();
        // No thread runs any more: idle CPUs may sleep deeply again.
        st.cpu_latency = None;
        drop(st);
        // What the safe-state hooks and the last cycles said.
        self.rt_log.stop();
        {
            let (m, cv) = &self.shared.fault_signal;
            *lock(m) = SUPERVISOR_EXIT;
            cv.notify_all();
        }
        self.inst.seg.unlink();
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        self.shutdown();
        if let Some(s) = self.supervisor.take() {
            let _ = s.join();
        }
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

/// Waits for a fault; then brings every component to its safe state.
fn supervise(shared: Arc<HostShared>, state: Arc<Mutex<HostState>>) {
    loop {
        {
            let (m, cv) = &shared.fault_signal;
            let mut req = lock(m);
            while *req == 0 {
                req = cv.wait(req).unwrap_or_else(|e| e.into_inner());
            }
            if *req == SUPERVISOR_EXIT {
                return;
            }
            *req = 0;
        }
        let fault = shared.fault.load(Acquire);
        if fault == NO_FAULT {
            continue;
        }
        let mut st = lock(&state);
        let name = st
            .functs
            .get(fault)
            .and_then(|s| s.as_ref().map(|s| s.name.clone()))
            .unwrap_or_default();
        eprintln!(
            "HAL: function '{name}' panicked; all threads of instance '{}' halted, components put in their safe state",
            shared.seg.instance()
        );
        if let Some(rec) = st.functs.get(fault).and_then(|s| s.as_ref()) {
            shared.seg.header().fault_funct.store(rec.rec_off, SeqCst);
        }
        // Cycles still in progress would overwrite the safe outputs.
        for t in &st.threads {
            wait_for_boundary(&t.ctl, Duration::from_secs(10));
        }
        for c in st.comps.iter_mut().rev() {
            if let Some(h) = c.safe_state.as_mut() {
                h();
            }
        }
    }
}

/// Builds a realtime component inside the host. Dropped without
/// [`ready`](Self::ready), it removes everything it created.
pub struct RtComponentBuilder<'h> {
    host: &'h Host,
    comp: Option<Component>,
    functs: Vec<usize>,
    safe_state: Option<Hook>,
}

impl RtComponentBuilder<'_> {
    /// The component, to create pins, params and regions on.
    pub fn component(&self) -> &Component {
        self.comp.as_ref().expect("component present until ready")
    }

    /// Exports a non-reentrant function: it may be added to one thread.
    ///
    /// Functions of one component may run in different threads, which
    /// preempt each other. State they share must therefore be `Sync`
    /// (atomics, pins): plain shared state does not compile.
    ///
    /// ```compile_fail
    /// # use hal_core::*;
    /// # fn build(host: &Host) -> Result<()> {
    /// let mut b = host.new_rt_component("sg")?;
    /// let freq = std::sync::Arc::new(std::cell::Cell::new(0.0));
    /// let f2 = freq.clone();
    /// b.funct("sg.update-freq", true, move |_| f2.set(1.0))?; // Cell is not Sync
    /// b.funct("sg.make-pulses", true, move |_| { let _ = freq.get(); })?;
    /// # Ok(()) }
    /// ```
    ///
    /// ```no_run
    /// # use hal_core::*;
    /// # use std::sync::{Arc, atomic::{AtomicU64, Ordering::Relaxed}};
    /// # fn build(host: &Host) -> Result<()> {
    /// let mut b = host.new_rt_component("sg")?;
    /// let freq = Arc::new(AtomicU64::new(0));
    /// let f2 = freq.clone();
    /// b.funct("sg.update-freq", true, move |_| f2.store(1.0f64.to_bits(), Relaxed))?;
    /// b.funct("sg.make-pulses", true, move |_| { let _ = f64::from_bits(freq.load(Relaxed)); })?;
    /// b.ready()
    /// # }
    /// ```
    pub fn funct(
        &mut self,
        name: &str,
        uses_fp: bool,
        f: impl FnMut(&FunctCtx) + Send + 'static,
    ) -> Result<()> {
        let code = FunctCode::exclusive(f);
        let id = self
            .host
            .export_funct(self.component(), name, uses_fp, code, false)?;
        self.functs.push(id);
        Ok(())
    }

    /// Exports a reentrant function: it may be added to several threads.
    pub fn funct_reentrant(
        &mut self,
        name: &str,
        uses_fp: bool,
        f: impl Fn(&FunctCtx) + Send + Sync + 'static,
    ) -> Result<()> {
        let code = FunctCode::shared(f);
        let id = self
            .host
            .export_funct(self.component(), name, uses_fp, code, true)?;
        self.functs.push(id);
        Ok(())
    }

    /// Sets the hook that puts the component's outputs in a safe state
    /// (outputs off, amplifiers disabled); called after a fault, at unload
    /// and at host exit, in reverse load order.
    pub fn on_safe_state(&mut self, f: impl FnMut() + Send + 'static) {
        self.safe_state = Some(Box::new(f));
    }

    /// Marks the component ready and hands it to the host.
    pub fn ready(mut self) -> Result<()> {
        let comp = self.comp.take().expect("component present until ready");
        if let Err(e) = comp.ready() {
            self.comp = Some(comp);
            return Err(e);
        }
        let mut st = lock(&self.host.state);
        st.comps.push(LoadedComp {
            module: None,
            comp,
            functs: std::mem::take(&mut self.functs),
            safe_state: self.safe_state.take(),
        });
        Ok(())
    }
}

impl Drop for RtComponentBuilder<'_> {
    fn drop(&mut self) {
        if self.comp.is_some() {
            self.host.drop_functs(&self.functs);
            self.comp = None;
        }
    }
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
