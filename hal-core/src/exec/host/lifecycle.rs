//! Start-up and shutdown of the host: creating the instance, starting and
//! stopping the threads, faults and the supervisor that answers them, and
//! the orderly end (safe state, unload, segment removed).

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

use crate::error::{HalError, Result};
use crate::exec::clock::TickClock;
use crate::exec::realtime::{self, RealtimeMode, TOP_PRIORITY};
use crate::exec::reaper::Reaper;
use crate::exec::thread::{HostShared, NO_FAULT, SUPERVISOR_EXIT};
use crate::objects::{validate_instance_name, HostLock, Instance};
use crate::paths;
use crate::rtlog::RtLogService;
use crate::shm::{Segment, ThreadRec};

use super::{lock, wait_for_boundary, Host, HostConfig, HostState};

impl Host {
    /// Starts a host: takes the instance's lock (failing if another host
    /// holds it), reclaims a segment left by a dead host, creates a fresh one.
    pub fn create(config: HostConfig) -> Result<Host> {
        validate_instance_name(&config.instance)?;
        let allowed_cpus = realtime::allowed_cpus();
        let rt_cpu = match &config.rt_cpu {
            Some(text) => Some(
                realtime::parse_cpu("RTAPI_CPU_NUMBER", text, &allowed_cpus).map_err(|e| {
                    HalError::BadSetting {
                        what: "the realtime CPU".into(),
                        source: Box::new(e),
                    }
                })?,
            ),
            None => None,
        };
        let lock = HostLock::acquire(&config.instance)?;
        let mut notes = Vec::new();
        let seg_path = paths::segment(&config.instance);
        if std::fs::symlink_metadata(&seg_path).is_ok() {
            // We hold the lock, so whoever made this is gone (a host that
            // died), or it was planted: either way it is removed (a link
            // itself, never what it names), not used.
            std::fs::remove_file(&seg_path)
                .map_err(|e| HalError::io("removing stale segment", &seg_path, e))?;
            notes.push(format!(
                "reclaimed segment {} (left by a host that died, or planted there)",
                seg_path.display()
            ));
        }
        let seg = Arc::new(Segment::create(&config.instance, config.shm_size)?);
        let (realtime, cpu_note) = match config.realtime {
            RealtimeMode::Off => (false, None),
            RealtimeMode::Auto => match realtime::probe_fifo(TOP_PRIORITY) {
                Ok(()) => (true, None),
                Err(why) => (false, Some(why.to_string())),
            },
        };
        if let Some(why) = cpu_note {
            notes.push(format!(
                "realtime scheduling unavailable, threads run without it \
                 (serialised, no preemption): {why}"
            ));
        }
        let rt_log = RtLogService::new();
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
            log: rt_log.ring(),
            delay_reported: AtomicBool::new(false),
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
            rt_log,
            allowed_cpus,
            default_cpu,
            _lock: lock,
        })
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
            self.publish_stale(&mut st)?;
            let mut notes = Vec::new();
            if !st.memory_locked {
                st.memory_locked = true;
                if let Err(why) = realtime::lock_memory() {
                    notes.push(why.to_string());
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
            // Threads start on a common grid a little ahead, so that all
            // are awake before the first deadline and due together
            // afterwards. Set while the state is locked: a change to a
            // thread's list sees either stopped threads (and leaves its
            // list to this start) or running ones.
            self.shared
                .start_ns
                .store(crate::exec::clock::monotonic_ns() + 200_000, SeqCst);
            self.shared.running.store(true, SeqCst);
            // Marked here rather than by each thread when it wakes, so that a
            // query right after `start` sees every thread running, as
            // LinuxCNC's `start` leaves them.
            self.mark_threads_running(&st, true);
            drop(st);
            for why in notes {
                self.add_note(why);
            }
        }
        if self.shared.realtime {
            // A realtime thread may report a missed deadline: make sure
            // something prints it.
            self.rt_log.handle();
        }
        self.wake_executors();
        Ok(())
    }

    /// Stops all threads (halcmd `stop`). Threads freeze between cycles;
    /// outputs keep their values: this is not a safe state. Returns once no
    /// function is running.
    pub fn stop(&self) {
        self.shared.running.store(false, SeqCst);
        let st = lock(&self.state);
        self.mark_threads_running(&st, false);
        for t in &st.threads {
            wait_for_boundary(&t.ctl, Duration::from_secs(10));
        }
    }

    /// Sets the `running` flag that queries read in every thread's record.
    fn mark_threads_running(&self, st: &HostState, running: bool) {
        for t in &st.threads {
            if let Ok(rec) = self.inst.seg.rec::<ThreadRec>(t.ctl.rec_off) {
                rec.running.store(u64::from(running), SeqCst);
            }
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

    pub(super) fn funct_name(&self, id: usize) -> String {
        lock(&self.state)
            .functs
            .get(id)
            .and_then(|s| s.as_ref().map(|s| s.name.clone()))
            .unwrap_or_else(|| format!("#{id}"))
    }

    pub(super) fn wake_executors(&self) {
        let (m, cv) = &self.shared.gate;
        let _g = lock(m);
        cv.notify_all();
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
        st.free_functs.clear();
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
            // The executors never write their record's flag; a halted
            // thread is shown stopped from here on.
            if let Ok(rec) = shared.seg.rec::<ThreadRec>(t.ctl.rec_off) {
                rec.running.store(0, SeqCst);
            }
        }
        for c in st.comps.iter_mut().rev() {
            if let Some(h) = c.safe_state.as_mut() {
                h();
            }
        }
    }
}
