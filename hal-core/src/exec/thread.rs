//! The executor: one OS thread per HAL thread, running its function list
//! every period to absolute deadlines on CLOCK_MONOTONIC.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex};

use super::clock::{monotonic_ns, sleep_until, TickClock};
use super::funct::{ExecList, FunctCtx};
use super::realtime;
use crate::handles::{Out, Param, Pin, Rw};
use crate::shm::{latency_bucket, Segment, ThreadRec, HIST_BUCKETS};

/// Supervisor request: a function faulted.
pub(crate) const SUPERVISOR_FAULT: u8 = 1;
/// Supervisor request: the host is shutting down.
pub(crate) const SUPERVISOR_EXIT: u8 = 2;

/// No function has faulted.
pub(crate) const NO_FAULT: usize = usize::MAX;

/// State the host shares with every executor.
pub(crate) struct HostShared {
    pub seg: Arc<Segment>,
    /// Threads run their lists only while this is set (`start`/`stop`).
    pub running: AtomicBool,
    /// Executors park here while stopped.
    pub gate: (Mutex<()>, Condvar),
    /// Without realtime scheduling, held for a whole cycle so that two HAL
    /// threads never run at once.
    pub serial: Option<Mutex<()>>,
    /// Per-function timing on or off.
    pub timing: AtomicBool,
    /// Code id of the function that panicked, or NO_FAULT.
    pub fault: AtomicUsize,
    /// Wakes the supervisor: [`SUPERVISOR_FAULT`] or [`SUPERVISOR_EXIT`].
    pub fault_signal: (Mutex<u8>, Condvar),
    pub clock: TickClock,
    pub realtime: bool,
    /// CLOCK_MONOTONIC time of the last `start`: every thread's deadlines
    /// are multiples of its period after it, so threads whose periods
    /// divide each other are due at the same instants.
    pub start_ns: AtomicU64,
}

/// Control block of one executor, shared with the host.
pub(crate) struct ThreadCtl {
    pub name: String,
    pub period: i64,
    pub priority: i32,
    pub cpu: Option<usize>,
    pub rec_off: u64,
    pub list: AtomicPtr<ExecList>,
    /// Incremented at every cycle boundary and whenever the executor parks.
    pub epoch: AtomicU64,
    /// True while the executor holds no reference to its list.
    pub idle: AtomicBool,
    pub exit: AtomicBool,
    /// Set once the init cycle (`initf` functions) has run.
    pub init_done: AtomicBool,
    pub time: Pin<i32, Out>,
    pub tmax: Param<i32, Rw>,
    pub beat: Pin<i64, Out>,
    /// Deadline of the last cycle this executor finished.
    pub done_deadline: AtomicU64,

    /// Threads created before this one, so at least as fast.
    pub faster: Vec<Arc<ThreadCtl>>,
}

impl ThreadCtl {
    /// Waits until every faster thread has finished its cycle for its
    /// latest deadline at or before `deadline`, as long as threads run.
    /// With SCHED_FIFO on one CPU, priorities already give this order;
    /// without realtime this is what keeps a faster thread first when both
    /// are due, as LinuxCNC's priorities do. Like a higher priority, a
    /// faster thread that never finishes holds the slower one back.
    fn wait_for_faster(&self, sh: &HostShared, deadline: u64) {
        let start = sh.start_ns.load(Acquire);
        for f in &self.faster {
            let p = f.period.max(1) as u64;
            let due = start + p * (deadline.saturating_sub(start) / p);
            while sh.running.load(Acquire)
                && !f.exit.load(Acquire)
                && f.done_deadline.load(Acquire) < due
            {
                std::thread::yield_now();
            }
        }
    }
}

impl HostShared {
    fn wait_for_start(&self, ctl: &ThreadCtl) {
        let (lock, cv) = &self.gate;
        let mut g = lock.lock().unwrap_or_else(|e| e.into_inner());
        while !self.running.load(Acquire) && !ctl.exit.load(Acquire) {
            g = cv.wait(g).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// Called on the realtime thread when a function panicked: halts every
    /// thread and wakes the supervisor, which does the rest.
    fn report_fault(&self, code_id: usize) {
        let _ = self
            .fault
            .compare_exchange(NO_FAULT, code_id, AcqRel, Acquire);
        self.running.store(false, SeqCst);
        let (lock, cv) = &self.fault_signal;
        let mut req = lock.lock().unwrap_or_else(|e| e.into_inner());
        if *req != SUPERVISOR_EXIT {
            *req = SUPERVISOR_FAULT;
        }
        drop(req);
        cv.notify_all();
    }
}

/// The body of an executor thread.
pub(crate) fn run(ctl: Arc<ThreadCtl>, sh: Arc<HostShared>) {
    if sh.realtime {
        // Failures were reported when the host probed its permissions.
        let _ = realtime::set_fifo(ctl.priority);
    }
    if let Some(cpu) = ctl.cpu {
        let _ = realtime::pin_to_cpu(cpu);
    }
    realtime::tight_timer_slack();
    realtime::prefault_stack();
    let Ok(rec) = sh.seg.rec::<ThreadRec>(ctl.rec_off) else {
        return;
    };
    let grace = &sh.seg.header().grace_epoch;
    let mut ctx = FunctCtx::new(ctl.period);
    let period = ctl.period.max(1) as u64;
    let clock = sh.clock;

    'park: loop {
        ctl.idle.store(true, SeqCst);
        rec.seen_epoch.store(u64::MAX, SeqCst);
        rec.running.store(0, Relaxed);
        ctl.epoch.fetch_add(1, SeqCst);
        sh.wait_for_start(&ctl);
        if ctl.exit.load(Acquire) {
            break;
        }
        rec.running.store(1, Relaxed);
        // First deadline: the next multiple of the period after start.
        let start = sh.start_ns.load(Acquire);
        let now = monotonic_ns();
        let mut next = start + period * ((now.saturating_sub(start)) / period + 1);
        loop {
            sleep_until(next);
            if ctl.exit.load(Acquire) {
                break 'park;
            }
            if !sh.running.load(Acquire) {
                continue 'park;
            }
            let woke = monotonic_ns();
            ctx.set_now(woke);
            record_latency(rec, woke.saturating_sub(next));

            // Announce that we may now hold references: first to the grace
            // epoch (for retired value cells), then to our list.
            ctl.idle.store(false, SeqCst);
            // Re-check after announcing: `stop` clears `running` and then
            // looks at `idle`, so one of us sees the other.
            if !sh.running.load(SeqCst) {
                continue 'park;
            }
            rec.seen_epoch.store(grace.load(SeqCst), SeqCst);
            if !ctl.faster.is_empty() {
                ctl.wait_for_faster(&sh, next);
            }
            let guard = sh
                .serial
                .as_ref()
                .map(|m| m.lock().unwrap_or_else(|e| e.into_inner()));
            // SAFETY: the host only frees a list after replacing it and
            // seeing this thread pass a boundary (epoch bump) or idle.
            let list = unsafe { &*ctl.list.load(SeqCst) };
            let timing = sh.timing.load(Relaxed);
            let start = clock.now();
            let mut prev = start;
            // One unwind guard for the whole list: a panic ends the cycle
            // anyway, and `current` says which function it came from.
            let mut current = 0usize;
            let init = !list.init_calls.is_empty() && !ctl.init_done.load(Acquire);
            let (calls, ids) = if init {
                ctl.init_done.store(true, Release);
                (&list.init_calls, &list.init_ids)
            } else {
                (&list.calls, &list.ids)
            };
            let outcome = catch_unwind(AssertUnwindSafe(|| {
                for (i, &code) in calls.iter().enumerate() {
                    current = i;
                    // SAFETY: `code` is kept alive by `list.owners`; a
                    // non-reentrant function is in this list only, and this
                    // thread runs its list sequentially.
                    unsafe { (*code).call(&ctx) };
                    if timing && !init {
                        let now = clock.now();
                        list.timing[i].record(clock.to_ns(now.wrapping_sub(prev)));
                        prev = now;
                    }
                }
            }));
            let faulted = outcome.is_err();
            if faulted {
                sh.report_fault(ids.get(current).copied().unwrap_or(NO_FAULT - 1));
            }
            let end = if timing { prev } else { clock.now() };
            let t = clock.to_ns(end.wrapping_sub(start)).min(i32::MAX as u64) as i32;
            ctl.time.set(t);
            if t > ctl.tmax.get() {
                ctl.tmax.set(t);
            }
            ctl.beat.set(ctl.beat.get().wrapping_add(1));
            rec.cycles.fetch_add(1, Relaxed);
            drop(guard);
            ctl.done_deadline.store(next, Release);
            ctl.idle.store(true, SeqCst);
            rec.seen_epoch.store(u64::MAX, SeqCst);
            ctl.epoch.fetch_add(1, SeqCst);
            if faulted {
                continue 'park;
            }

            next += period;
            let now = monotonic_ns();
            if now > next {
                // Deadlines already missed are skipped, each counted once.
                let missed = (now - next) / period + 1;
                rec.overruns.fetch_add(missed, Relaxed);
                next += missed * period;
            }
        }
    }
    ctl.idle.store(true, SeqCst);
    rec.seen_epoch.store(u64::MAX, SeqCst);
    rec.running.store(0, Relaxed);
    ctl.epoch.fetch_add(1, SeqCst);
}

fn record_latency(rec: &ThreadRec, ns: u64) {
    let b = latency_bucket(ns).min(HIST_BUCKETS - 1);
    rec.hist[b].fetch_add(1, Relaxed);
    if ns < rec.lat_min_ns.load(Relaxed) {
        rec.lat_min_ns.store(ns, Relaxed);
    }
    if ns > rec.lat_max_ns.load(Relaxed) {
        rec.lat_max_ns.store(ns, Relaxed);
    }
}
