//! The code of realtime functions, kept in the host's private memory.

use std::cell::UnsafeCell;
use std::sync::Arc;

use crate::handles::{Out, Param, Pin, Ro, Rw};

/// What a realtime function receives each time it runs.
#[derive(Debug, Clone, Copy)]
pub struct FunctCtx {
    period: i64,
    now_ns: u64,
}

impl FunctCtx {
    /// A context for a thread of `period` ns (also for tests of components).
    pub fn new(period: i64) -> FunctCtx {
        FunctCtx { period, now_ns: 0 }
    }

    /// When the thread woke for this cycle, in CLOCK_MONOTONIC ns: the
    /// same for every function of the cycle. Functions needing the time
    /// use this rather than a system call of their own.
    #[inline(always)]
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    pub(crate) fn set_now(&mut self, now_ns: u64) {
        self.now_ns = now_ns;
    }

    /// The period of the calling thread in ns (the configured period, not a
    /// measured interval).
    #[inline(always)]
    pub fn period(&self) -> i64 {
        self.period
    }

    /// The period in seconds, computed as LinuxCNC's `fperiod`: period
    /// times the constant 1e-9 (not divided by 1e9; the two differ in the
    /// last bit for many periods).
    #[inline(always)]
    pub fn fperiod(&self) -> f64 {
        self.period as f64 * 1e-9
    }
}

/// A function body. A non-reentrant function is `FnMut` and may be in at
/// most one thread (the host enforces it from its own bookkeeping, never
/// from the segment); a reentrant one is `Fn + Sync` and may be in several.
pub(crate) enum FunctCode {
    Exclusive(UnsafeCell<ExclusiveFn>),
    Shared(SharedFn),
}

/// Body of a non-reentrant function.
pub(crate) type ExclusiveFn = Box<dyn FnMut(&FunctCtx) + Send>;
/// Body of a reentrant function.
pub(crate) type SharedFn = Box<dyn Fn(&FunctCtx) + Send + Sync>;

// SAFETY: `Shared` is Sync by its bound. `Exclusive` is only called through
// `call`, whose contract (one thread at a time) the host upholds: such a
// function is in at most one thread's list, a thread runs its list
// sequentially, and a list is only replaced after the executor has passed a
// cycle boundary.
unsafe impl Sync for FunctCode {}

impl FunctCode {
    /// Runs the function.
    ///
    /// # Safety
    /// For `Exclusive` code, no other thread may be calling it at the same
    /// time.
    #[inline(always)]
    pub(crate) unsafe fn call(&self, ctx: &FunctCtx) {
        match self {
            // SAFETY: exclusive access is the caller's contract.
            FunctCode::Exclusive(f) => unsafe { (*f.get())(ctx) },
            FunctCode::Shared(f) => f(ctx),
        }
    }
}

/// The timing outputs of one function in an executor's list.
pub(crate) struct TimingOut {
    pub time: Pin<i32, Out>,
    pub tmax: Param<i32, Rw>,
    pub tmax_increased: Param<bool, Ro>,
}

impl TimingOut {
    /// Publishes one execution time.
    #[inline(always)]
    pub(crate) fn record(&self, ns: u64) {
        let t = ns.min(i32::MAX as u64) as i32;
        self.time.set(t);
        let raised = t > self.tmax.get();
        if raised {
            self.tmax.set(t);
        }
        self.tmax_increased.set(raised);
    }
}

/// A thread's function list, replaced whole by the host. The calls sit in a
/// dense array of their own so that a cycle without per-function timing
/// walks only 8 bytes per function.
#[derive(Default)]
pub(crate) struct ExecList {
    /// The code to call, in order; kept alive by `owners`.
    pub calls: Vec<*const FunctCode>,
    /// Timing outputs, parallel to `calls`.
    pub timing: Vec<TimingOut>,
    /// Host code ids, parallel to `calls` (for fault reports).
    pub ids: Vec<usize>,
    pub owners: Vec<Arc<FunctCode>>,
    /// Functions of the init cycle (`initf`), run once instead of the
    /// list on the first cycle after start; kept alive by `owners`.
    pub init_calls: Vec<*const FunctCode>,
    pub init_ids: Vec<usize>,
}

impl ExecList {
    pub(crate) fn push(&mut self, code: Arc<FunctCode>, id: usize, timing: TimingOut) {
        self.calls.push(Arc::as_ptr(&code));
        self.owners.push(code);
        self.ids.push(id);
        self.timing.push(timing);
    }

    pub(crate) fn push_init(&mut self, code: Arc<FunctCode>, id: usize) {
        self.init_calls.push(Arc::as_ptr(&code));
        self.owners.push(code);
        self.init_ids.push(id);
    }
}
