//! The executor: one OS thread per HAL thread, running its function list
//! every period to absolute deadlines on CLOCK_MONOTONIC.
//!
//! What a cycle costs beyond its functions is kept to a minimum: one clock
//! read per function boundary when functions are timed (none when they are
//! not), plain stores for the counters only this executor writes, and one
//! fence to announce the cycle to the host instead of one locked
//! instruction per flag.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{fence, AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex};

use super::clock::{monotonic_ns, rdtsc, sleep_until, TickClock};
use super::funct::{Call, ExecList, FunctCtx};
use super::realtime;
use crate::handles::{Out, Param, Pin, Rw};
use crate::rtlog::RtLog;
use crate::shm::{latency_bucket, Segment, ThreadRec, HIST_BUCKETS};
pub(crate) use crate::shm::{THREAD_CATCH_UP, THREAD_NO_FUNCT_TIMING};

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
    /// The host's realtime message log (printed by its drain thread).
    pub log: RtLog,
    /// Set once a realtime thread has reported a missed deadline: like
    /// LinuxCNC, the host says it once per session.
    pub delay_reported: AtomicBool,
}

/// Where an executor's OS thread runs: the CPU chosen for it (explicitly
/// or by default; `None` for every CPU the process may use) and, once the
/// thread has started, its kernel thread id. Changed under its mutex so
/// that the host and the starting executor never apply two choices in the
/// wrong order.
#[derive(Debug, Default)]
pub(crate) struct Placement {
    pub cpu: Option<usize>,
    pub tid: Option<i32>,
}

/// Control block of one executor, shared with the host.
pub(crate) struct ThreadCtl {
    pub name: String,
    /// The thread's number in creation order from 0, as LinuxCNC numbers
    /// its realtime tasks in messages.
    pub task_id: usize,
    pub period: i64,
    pub priority: i32,
    pub placement: Mutex<Placement>,
    pub rec_off: u64,
    /// [`THREAD_NO_FUNCT_TIMING`] and [`THREAD_CATCH_UP`] bits; 0 is the
    /// default (timing on, missed deadlines skipped). Read once a cycle.
    pub options: AtomicU64,
    pub list: AtomicPtr<ExecList>,
    /// Incremented at every cycle boundary and whenever the executor parks;
    /// only the executor writes it.
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

    /// Records the calling OS thread as this executor's and moves it to its
    /// chosen CPU.
    fn attach_os_thread(&self, allowed: &[usize]) {
        let mut p = self.placement.lock().unwrap_or_else(|e| e.into_inner());
        let tid = realtime::current_tid();
        p.tid = Some(tid);
        // A refused choice was reported when it was made.
        let _ = realtime::place_thread(tid, p.cpu, allowed);
    }

    /// Marks the executor as holding nothing (parked or gone). The
    /// record's `running` flag is not the executor's to write: the host
    /// sets it under its state lock at start, stop, thread creation and
    /// fault, so a query never sees a started thread as stopped while it
    /// parks on its way round.
    fn park(&self, rec: &ThreadRec) {
        self.idle.store(true, SeqCst);
        rec.seen_epoch.store(u64::MAX, SeqCst);
        self.epoch.fetch_add(1, SeqCst);
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

    /// Called on a realtime thread whose cycle ended after its next
    /// deadline. Under SCHED_FIFO this means the host cannot keep its
    /// periods (LinuxCNC's "Unexpected realtime delay"), said once per
    /// host in LinuxCNC's words; without realtime, late cycles are
    /// expected and only counted. Realtime-safe: one swap and a log push.
    fn report_delay(&self, ctl: &ThreadCtl) {
        if self.realtime && !self.delay_reported.swap(true, Relaxed) {
            self.log.err(format_args!(
                "Unexpected realtime delay on task {} with period {}\n\
                 This Message will only display once per session.\n\
                 Run the Latency Test and resolve before continuing.\n",
                ctl.task_id, ctl.period
            ));
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
pub(crate) fn run(ctl: Arc<ThreadCtl>, sh: Arc<HostShared>, allowed: Vec<usize>) {
    if sh.realtime {
        // Failures were reported when the host probed its permissions.
        let _ = realtime::set_fifo(ctl.priority);
    } else if std::env::var_os("HAL_NO_SHORT_SLICE").is_none() {
        // Without realtime, a short fair-scheduler slice is what keeps the
        // wake-up tail short (see `short_slice`).
        let _ = realtime::short_slice();
    }
    ctl.attach_os_thread(&allowed);
    drop(allowed);
    realtime::tight_timer_slack();
    realtime::prefault_stack();
    let Ok(rec) = sh.seg.rec::<ThreadRec>(ctl.rec_off) else {
        return;
    };
    let grace = &sh.seg.header().grace_epoch;
    let mut ctx = FunctCtx::new(ctl.period);
    let period = ctl.period.max(1) as u64;

    'park: loop {
        ctl.park(rec);
        sh.wait_for_start(&ctl);
        if ctl.exit.load(Acquire) {
            break;
        }
        // First deadline: the next multiple of the period after start.
        let start = sh.start_ns.load(Acquire);
        let mut now = monotonic_ns();
        let mut next = start + period * ((now.saturating_sub(start)) / period + 1);
        loop {
            // A cycle already late (catching up) runs at once.
            if now < next {
                sleep_until(next);
            }
            if ctl.exit.load(Acquire) {
                break 'park;
            }
            if !sh.running.load(Acquire) {
                continue 'park;
            }
            let woke = monotonic_ns();
            ctx.set_cycle(next, woke);
            record_latency(rec, woke.saturating_sub(next));

            // Announce that we may now hold references: to value cells as
            // of the grace epoch we saw, and to our list. The fence orders
            // these stores before every later load (the list pointer, pin
            // slots, `running`): the host and the segment's writers store
            // first and then look at these flags, so one of the two sides
            // always sees the other.
            ctl.idle.store(false, Relaxed);
            let seen = grace.load(Relaxed);
            rec.seen_epoch.store(seen, Relaxed);
            fence(SeqCst);
            if !sh.running.load(Relaxed) {
                continue 'park;
            }
            if !ctl.faster.is_empty() {
                ctl.wait_for_faster(&sh, next);
            }
            let guard = sh
                .serial
                .as_ref()
                .map(|m| m.lock().unwrap_or_else(|e| e.into_inner()));
            // SAFETY: the host only frees a list after replacing it and
            // seeing this thread pass a boundary (epoch bump) or idle.
            let list = unsafe { &*ctl.list.load(Acquire) };
            let options = ctl.options.load(Relaxed);
            let faulted = run_cycle(&ctl, &sh, list, &ctx, options & THREAD_NO_FUNCT_TIMING == 0);
            // Only this executor writes its counters: no locked increment.
            rec.cycles
                .store(rec.cycles.load(Relaxed).wrapping_add(1), Relaxed);
            drop(guard);
            ctl.done_deadline.store(next, Release);
            rec.seen_epoch.store(u64::MAX, Release);
            ctl.epoch
                .store(ctl.epoch.load(Relaxed).wrapping_add(1), Release);
            ctl.idle.store(true, Release);
            if faulted {
                continue 'park;
            }

            next += period;
            now = monotonic_ns();
            if now > next {
                let late = if options & THREAD_CATCH_UP != 0 {
                    // The next cycle runs at once, late; it counts once.
                    1
                } else {
                    // Deadlines already missed are skipped, each counted.
                    let missed = (now - next) / period + 1;
                    next += missed * period;
                    missed
                };
                rec.overruns
                    .store(rec.overruns.load(Relaxed).wrapping_add(late), Relaxed);
                sh.report_delay(&ctl);
            }
        }
    }
    ctl.park(rec);
}

/// Runs one cycle's functions (or the init cycle's) and publishes the
/// thread's time. Returns whether a function panicked.
fn run_cycle(
    ctl: &ThreadCtl,
    sh: &HostShared,
    list: &ExecList,
    ctx: &FunctCtx,
    timed: bool,
) -> bool {
    let clock = sh.clock;
    let init = !list.init_calls.is_empty() && !ctl.init_done.load(Acquire);
    // One unwind guard for the whole list: a panic ends the cycle anyway,
    // and `current` says which function it came from.
    let mut current = 0usize;
    let start = clock.now();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if init {
            ctl.init_done.store(true, Release);
            run_untimed(&list.init_calls, ctx, &mut current);
            clock.now()
        } else if !timed {
            run_listed(list, ctx, &mut current);
            clock.now()
        } else if clock.uses_tsc() {
            run_timed(list, ctx, &clock, start, rdtsc, &mut current)
        } else {
            run_timed(list, ctx, &clock, start, monotonic_ns, &mut current)
        }
    }));
    let (end, faulted) = match outcome {
        Ok(end) => (end, false),
        Err(_) => {
            let ids = if init { &list.init_ids } else { &list.ids };
            sh.report_fault(ids.get(current).copied().unwrap_or(NO_FAULT - 1));
            (clock.now(), true)
        }
    };
    let t = clock.to_ns(end.wrapping_sub(start)).min(i32::MAX as u64) as i32;
    ctl.time.set(t);
    if t > ctl.tmax.get() {
        ctl.tmax.set(t);
    }
    ctl.beat.set(ctl.beat.get().wrapping_add(1));
    faulted
}

/// Calls every function of `calls` in order.
#[inline(always)]
fn run_untimed(calls: &[Call], ctx: &FunctCtx, current: &mut usize) {
    for (i, call) in calls.iter().enumerate() {
        *current = i;
        // SAFETY: the list's owners keep the code alive; a non-reentrant
        // function is in this list only, and this thread runs its list
        // sequentially.
        unsafe { call.run(ctx) };
    }
}

/// Calls every function of the list without timing them, asking for
/// each function's closure while the one before runs.
#[inline(always)]
fn run_listed(list: &ExecList, ctx: &FunctCtx, current: &mut usize) {
    let entries = &list.entries;
    for (i, e) in entries.iter().enumerate() {
        *current = i;
        if let Some(next) = entries.get(i + 1) {
            next.call.prefetch();
        }
        // SAFETY: as in `run_untimed`.
        unsafe { e.call.run(ctx) };
    }
}

/// Calls every function of the list, reading the clock once per function
/// boundary (the end of one function is the start of the next) and
/// publishing each function's time. Returns the last reading.
#[inline(always)]
fn run_timed(
    list: &ExecList,
    ctx: &FunctCtx,
    clock: &TickClock,
    start: u64,
    ticks: impl Fn() -> u64,
    current: &mut usize,
) -> u64 {
    let mut prev = start;
    let entries = &list.entries;
    for (i, e) in entries.iter().enumerate() {
        *current = i;
        if let Some(next) = entries.get(i + 1) {
            next.call.prefetch();
        }
        // SAFETY: as in `run_untimed`.
        unsafe { e.call.run(ctx) };
        let now = ticks();
        e.timing
            .record(&list.cells, clock.to_ns(now.wrapping_sub(prev)));
        prev = now;
    }
    prev
}

/// Counts one wake-up latency. Only this executor writes the statistics,
/// so plain loads and stores do (readers see each word whole).
fn record_latency(rec: &ThreadRec, ns: u64) {
    let b = latency_bucket(ns).min(HIST_BUCKETS - 1);
    let bucket = &rec.hist[b];
    bucket.store(bucket.load(Relaxed).wrapping_add(1), Relaxed);
    if ns < rec.lat_min_ns.load(Relaxed) {
        rec.lat_min_ns.store(ns, Relaxed);
    }
    if ns > rec.lat_max_ns.load(Relaxed) {
        rec.lat_max_ns.store(ns, Relaxed);
    }
}
