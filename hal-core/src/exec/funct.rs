//! The code of realtime functions, kept in the host's private memory, and
//! the dense lists executors walk.

use std::ptr::NonNull;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use crate::handles::{Cells, Out, Param, Pin, Ro, Rw};
use crate::shm::Segment;
use crate::types::PinValue;

/// What a realtime function receives each time it runs.
#[derive(Debug, Clone, Copy)]
pub struct FunctCtx {
    period: i64,
    now_ns: u64,
    deadline_ns: u64,
}

impl FunctCtx {
    /// A context for a thread of `period` ns (also for tests of components).
    pub fn new(period: i64) -> FunctCtx {
        FunctCtx {
            period,
            now_ns: 0,
            deadline_ns: 0,
        }
    }

    /// A context for one call from a foreign host's thread (LinuxCNC's):
    /// its period, and the time the call is made, which serves as the
    /// cycle's deadline too.
    pub fn at(period: i64, now_ns: u64) -> FunctCtx {
        FunctCtx {
            period,
            now_ns,
            deadline_ns: now_ns,
        }
    }

    /// When the thread woke for this cycle, in CLOCK_MONOTONIC ns: the
    /// same for every function of the cycle. Functions needing the time
    /// use this rather than a system call of their own.
    #[inline(always)]
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// The deadline this cycle serves, in CLOCK_MONOTONIC ns: a multiple
    /// of the period after the threads were started. It advances by one
    /// period per cycle, or by more when deadlines were missed and skipped
    /// (see [`MissedDeadline`](crate::MissedDeadline)).
    #[inline(always)]
    pub fn deadline_ns(&self) -> u64 {
        self.deadline_ns
    }

    pub(crate) fn set_cycle(&mut self, deadline_ns: u64, now_ns: u64) {
        self.deadline_ns = deadline_ns;
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

/// Calls a function body through a pointer to its closure.
type CallFn = unsafe fn(NonNull<()>, &FunctCtx);

/// A function body: a boxed closure and the monomorphic code that calls it,
/// so that an executor reaches the body in one indirect call from its list
/// (no enum, no trait-object double hop).
///
/// A non-reentrant function is `FnMut` and may be in at most one thread
/// (the host enforces it from its own bookkeeping, never from the segment);
/// a reentrant one is `Fn + Sync` and may be in several.
pub(crate) struct FunctCode {
    data: NonNull<()>,
    call: CallFn,
    drop: unsafe fn(NonNull<()>),
}

// SAFETY: the closure is `Send` (both constructors require it), and a
// shared closure is `Sync`. An exclusive one is only called through
// `Call::run`, whose contract (one thread at a time) the host upholds: such
// a function is in at most one thread's list, a thread runs its list
// sequentially, and a list is only replaced after the executor has passed a
// cycle boundary.
unsafe impl Send for FunctCode {}
// SAFETY: as above.
unsafe impl Sync for FunctCode {}

/// Calls an exclusive body.
///
/// # Safety
/// `data` comes from `Box::<F>::into_raw`, is alive, and no other thread
/// calls it at the same time.
unsafe fn call_mut<F: FnMut(&FunctCtx)>(data: NonNull<()>, ctx: &FunctCtx) {
    // SAFETY: the caller's contract.
    unsafe { (*data.cast::<F>().as_ptr())(ctx) }
}

/// Calls a shared body.
///
/// # Safety
/// `data` comes from `Box::<F>::into_raw` and is alive.
unsafe fn call_ref<F: Fn(&FunctCtx)>(data: NonNull<()>, ctx: &FunctCtx) {
    // SAFETY: the caller's contract; `F: Fn` needs only a shared reference.
    unsafe { (*data.cast::<F>().as_ptr())(ctx) }
}

/// Frees a body.
///
/// # Safety
/// `data` comes from `Box::<F>::into_raw` and is freed only once.
unsafe fn drop_box<F>(data: NonNull<()>) {
    // SAFETY: the caller's contract.
    drop(unsafe { Box::from_raw(data.cast::<F>().as_ptr()) })
}

impl FunctCode {
    /// A non-reentrant body.
    pub(crate) fn exclusive<F: FnMut(&FunctCtx) + Send + 'static>(f: F) -> FunctCode {
        FunctCode {
            data: NonNull::from(Box::leak(Box::new(f))).cast(),
            call: call_mut::<F>,
            drop: drop_box::<F>,
        }
    }

    /// A reentrant body.
    pub(crate) fn shared<F: Fn(&FunctCtx) + Send + Sync + 'static>(f: F) -> FunctCode {
        FunctCode {
            data: NonNull::from(Box::leak(Box::new(f))).cast(),
            call: call_ref::<F>,
            drop: drop_box::<F>,
        }
    }

    fn entry(&self) -> Call {
        Call {
            data: self.data,
            call: self.call,
        }
    }
}

impl Drop for FunctCode {
    fn drop(&mut self) {
        // SAFETY: `data` came from Box::into_raw in a constructor with the
        // same `F` as `drop`, and this is the only place that frees it.
        unsafe { (self.drop)(self.data) }
    }
}

/// One entry of an executor's list: 16 bytes, four to a cache line.
#[derive(Clone, Copy)]
pub(crate) struct Call {
    data: NonNull<()>,
    call: CallFn,
}

impl Call {
    /// Asks the CPU to start loading the first two cache lines of the
    /// function's closure (its captured pins and state), so that when the
    /// executor reads the clock after the function before it (which waits
    /// for that function's loads), this one's first cache miss is already
    /// under way.
    #[inline(always)]
    pub(crate) fn prefetch(&self) {
        let p = self.data.as_ptr() as *const u8;
        prefetch_line(p);
        prefetch_line(p.wrapping_add(64));
    }

    /// Runs the function.
    ///
    /// # Safety
    /// The [`FunctCode`] this entry came from is alive, and for exclusive
    /// code no other thread is calling it at the same time.
    #[inline(always)]
    pub(crate) unsafe fn run(&self, ctx: &FunctCtx) {
        // SAFETY: the caller's contract.
        unsafe { (self.call)(self.data, ctx) }
    }
}

/// The timing outputs of one function in an executor's list: its `.time`
/// pin's slot and the value words of its `.tmax` and `.tmax-increased`
/// params, 24 bytes (the list's [`Cells`] resolves the slot), so that
/// timing a function reads little beyond the segment's own words.
pub(crate) struct TimingOut {
    time_slot: NonNull<AtomicU64>,
    tmax: NonNull<AtomicU64>,
    tmax_increased: NonNull<AtomicU64>,
}

impl TimingOut {
    /// The outputs of a function, from its record's pin and params.
    pub(crate) fn new(
        time: &Pin<i32, Out>,
        tmax: &Param<i32, Rw>,
        tmax_increased: &Param<bool, Ro>,
    ) -> TimingOut {
        TimingOut {
            time_slot: NonNull::from(time.slot()),
            tmax: NonNull::from(tmax.word()),
            tmax_increased: NonNull::from(tmax_increased.word()),
        }
    }

    /// Publishes one execution time.
    #[inline(always)]
    pub(crate) fn record(&self, cells: &Cells, ns: u64) {
        let t = ns.min(i32::MAX as u64) as i32;
        // SAFETY: the three words are in the mapping, which the list that
        // holds this (its `_seg`) keeps alive.
        let (slot, tmax, increased) = unsafe {
            (
                self.time_slot.as_ref(),
                self.tmax.as_ref(),
                self.tmax_increased.as_ref(),
            )
        };
        cells.cell(slot).store(t.to_bits(), Relaxed);
        let raised = t > i32::from_bits(tmax.load(Relaxed));
        if raised {
            tmax.store(t.to_bits(), Relaxed);
        }
        increased.store(raised.to_bits(), Relaxed);
    }
}

/// Asks the CPU to load the cache line holding `p`.
#[inline(always)]
fn prefetch_line(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: prefetching never faults and has no effect on program
        // state, whatever the address.
        unsafe { _mm_prefetch(p as *const i8, _MM_HINT_T0) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// One function of an executor's list: its code and, beside it, the words
/// its timing goes to, so that one pass over the list reads 40 bytes per
/// function in order and nothing else of it.
pub(crate) struct Entry {
    pub call: Call,
    pub timing: TimingOut,
}

/// A thread's function list, replaced whole by the host.
pub(crate) struct ExecList {
    /// The functions, in order; their code is kept alive by `owners`.
    pub entries: Vec<Entry>,
    /// Resolves the `.time` pins' slots.
    pub cells: Cells,
    /// Host code ids, parallel to `calls` (for fault reports).
    pub ids: Vec<usize>,
    owners: Vec<Arc<FunctCode>>,
    /// Functions of the init cycle (`initf`), run once instead of the
    /// list on the first cycle after start; kept alive by `owners`.
    pub init_calls: Vec<Call>,
    pub init_ids: Vec<usize>,
    /// Keeps the mapping the timing outputs point into alive.
    _seg: Arc<Segment>,
}

impl ExecList {
    pub(crate) fn new(seg: &Arc<Segment>) -> ExecList {
        ExecList {
            entries: Vec::new(),
            cells: Cells::new(seg),
            ids: Vec::new(),
            owners: Vec::new(),
            init_calls: Vec::new(),
            init_ids: Vec::new(),
            _seg: seg.clone(),
        }
    }

    pub(crate) fn push(&mut self, code: Arc<FunctCode>, id: usize, timing: TimingOut) {
        self.entries.push(Entry {
            call: code.entry(),
            timing,
        });
        self.owners.push(code);
        self.ids.push(id);
    }

    pub(crate) fn push_init(&mut self, code: Arc<FunctCode>, id: usize) {
        self.init_calls.push(code.entry());
        self.owners.push(code);
        self.init_ids.push(id);
    }
}
