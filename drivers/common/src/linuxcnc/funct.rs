//! A driver's functions as LinuxCNC calls them.
//!
//! Each closure is boxed into a slot with the module's [`ModuleCtl`], and
//! exported with a trampoline monomorphised for the closure's type
//! ([`call_mut`], [`call_ref`]): LinuxCNC's thread calls the trampoline
//! with the slot, the trampoline calls the closure directly. Around the
//! call the trampoline counts itself in and out of the module (two
//! uncontended atomic adds), so an unload can wait until no call runs
//! before freeing anything, and it catches a panic: `rtapi_app` must
//! never unwind or abort because of a driver. After a panic the module
//! says so once, puts its outputs in their safe state, and its functions
//! do nothing until it is unloaded (our host halts its threads instead).

use std::ffi::{c_long, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr::NonNull;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering::SeqCst};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use hal_core::{FunctCtx, MsgLevel};

use super::api::FunctCall;
use super::print;
use crate::fault::SafeState;

/// How long an unload waits for running functions to return.
pub(crate) const QUIESCE_LIMIT: Duration = Duration::from_secs(2);
/// How long after `hal_exit` a call LinuxCNC's thread had already
/// fetched may take to begin.
pub(crate) const GRACE: Duration = Duration::from_millis(5);

/// What every function of one loaded module shares: whether it may run,
/// how many calls are running, and the safe state a panic invokes.
pub(crate) struct ModuleCtl {
    module: &'static str,
    /// Set at unload: calls return at once.
    stopping: AtomicBool,
    /// Set by a panic: calls return at once.
    faulted: AtomicBool,
    /// Calls between their check-in and check-out.
    running: AtomicU32,
    /// The module's safe state, set when the load finished.
    safe: OnceLock<Vec<Box<dyn SafeState>>>,
}

impl ModuleCtl {
    pub(crate) fn new(module: &'static str) -> ModuleCtl {
        ModuleCtl {
            module,
            stopping: AtomicBool::new(false),
            faulted: AtomicBool::new(false),
            running: AtomicU32::new(0),
            safe: OnceLock::new(),
        }
    }

    /// Gives the module's safe state to a panic (and the unload).
    pub(crate) fn arm(&self, safe: Vec<Box<dyn SafeState>>) {
        let _ = self.safe.set(safe);
    }

    /// Checks a call in; `None` (checked out again) when the module is
    /// stopping or faulted.
    #[inline(always)]
    fn enter(&self) -> Option<Running<'_>> {
        // Check in first, then look at the flags: an unload that set
        // `stopping` and then saw no call running cannot miss this one.
        self.running.fetch_add(1, SeqCst);
        let run = Running(self);
        if self.stopping.load(SeqCst) || self.faulted.load(SeqCst) {
            return None;
        }
        Some(run)
    }

    /// Stops new calls and waits up to [`QUIESCE_LIMIT`] until none runs;
    /// whether none does.
    pub(crate) fn stop_and_wait(&self) -> bool {
        self.stopping.store(true, SeqCst);
        let end = Instant::now() + QUIESCE_LIMIT;
        while self.running.load(SeqCst) != 0 {
            if Instant::now() > end {
                return false;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        true
    }

    /// Runs the safe state; a panic in it is caught and said.
    pub(crate) fn go_safe(&self) {
        for s in self.safe.get().into_iter().flatten() {
            if catch_unwind(AssertUnwindSafe(|| s.go_safe())).is_err() {
                print::say(
                    MsgLevel::Err,
                    format_args!("{}: the safe state panicked", self.module),
                );
            }
        }
    }

    /// After a panic in function `funct`: the first one is said, goes
    /// safe, and stops the module's functions.
    #[cold]
    fn fault(&self, funct: &str) {
        if self.faulted.swap(true, SeqCst) {
            return;
        }
        print::say(
            MsgLevel::Err,
            format_args!(
                "{}: function '{funct}' panicked: outputs are in their safe state and the \
                 module's functions do nothing until it is unloaded",
                self.module
            ),
        );
        self.go_safe();
    }
}

/// A call checked in; checks out when dropped.
struct Running<'a>(&'a ModuleCtl);

impl Drop for Running<'_> {
    #[inline(always)]
    fn drop(&mut self) {
        self.0.running.fetch_sub(1, SeqCst);
    }
}

/// A closure and what its trampoline needs, at a stable address.
struct Slot<F> {
    ctl: Arc<ModuleCtl>,
    name: Box<str>,
    f: std::cell::UnsafeCell<F>,
}

/// A boxed [`Slot`] of some closure type with the trampoline of that
/// type (paired here, so a slot is never called through another type's
/// trampoline); the slot is freed on drop.
pub(crate) struct OwnedFunct {
    slot: NonNull<c_void>,
    call: FunctCall,
    free: unsafe fn(NonNull<c_void>),
}

/// Frees a slot of closure type `F`.
///
/// # Safety
/// `p` comes from `Box::<Slot<F>>::into_raw` and is freed only once.
unsafe fn free<F>(p: NonNull<c_void>) {
    // SAFETY: the caller's contract.
    drop(unsafe { Box::from_raw(p.cast::<Slot<F>>().as_ptr()) })
}

impl OwnedFunct {
    fn boxed<F>(ctl: Arc<ModuleCtl>, name: &str, f: F, call: FunctCall) -> OwnedFunct {
        let slot = Box::new(Slot {
            ctl,
            name: name.into(),
            f: std::cell::UnsafeCell::new(f),
        });
        OwnedFunct {
            slot: NonNull::from(Box::leak(slot)).cast(),
            call,
            free: free::<F>,
        }
    }

    /// A non-reentrant function: LinuxCNC adds it to one thread at most,
    /// so calls never overlap and the closure may be `FnMut`.
    pub(crate) fn exclusive<F: FnMut(&FunctCtx) + Send + 'static>(
        ctl: Arc<ModuleCtl>,
        name: &str,
        f: F,
    ) -> OwnedFunct {
        OwnedFunct::boxed(ctl, name, f, call_mut::<F>)
    }

    /// A reentrant function: calls may overlap, so the closure is `Fn +
    /// Sync`.
    pub(crate) fn shared<F: Fn(&FunctCtx) + Send + Sync + 'static>(
        ctl: Arc<ModuleCtl>,
        name: &str,
        f: F,
    ) -> OwnedFunct {
        OwnedFunct::boxed(ctl, name, f, call_ref::<F>)
    }

    /// The trampoline LinuxCNC calls.
    pub(crate) fn call(&self) -> FunctCall {
        self.call
    }

    /// The argument LinuxCNC passes back to the trampoline.
    pub(crate) fn arg(&self) -> *mut c_void {
        self.slot.as_ptr()
    }
}

impl Drop for OwnedFunct {
    fn drop(&mut self) {
        // SAFETY: `free` is the freeing function of the slot's type and
        // the slot is freed here only.
        unsafe { (self.free)(self.slot) }
    }
}

/// Runs `body` for the slot at `arg` as one checked-in call.
#[inline(always)]
fn run<F>(arg: *mut c_void, period: c_long, body: impl FnOnce(&Slot<F>, &FunctCtx)) {
    // SAFETY: LinuxCNC passes back the argument exported with this
    // trampoline: a live Slot<F> (the session frees it only after no call
    // runs and LinuxCNC has removed the function).
    let slot = unsafe { &*arg.cast::<Slot<F>>() };
    let Some(_running) = slot.ctl.enter() else {
        return;
    };
    // `long` is 64 bits on the platforms LinuxCNC's uspace runs on.
    #[allow(clippy::useless_conversion)]
    let ctx = FunctCtx::at(i64::from(period), hal_core::clock::monotonic_ns());
    if catch_unwind(AssertUnwindSafe(|| body(slot, &ctx))).is_err() {
        slot.ctl.fault(&slot.name);
    }
}

/// The trampoline of a non-reentrant function of closure type `F`.
unsafe extern "C" fn call_mut<F: FnMut(&FunctCtx) + Send + 'static>(
    arg: *mut c_void,
    period: c_long,
) {
    run::<F>(arg, period, |slot, ctx| {
        // SAFETY: LinuxCNC runs a non-reentrant function in one thread
        // at most, one call at a time, so this is the only reference.
        let f = unsafe { &mut *slot.f.get() };
        f(ctx)
    })
}

/// The trampoline of a reentrant function of closure type `F`.
unsafe extern "C" fn call_ref<F: Fn(&FunctCtx) + Send + Sync + 'static>(
    arg: *mut c_void,
    period: c_long,
) {
    run::<F>(arg, period, |slot, ctx| {
        // SAFETY: `F: Fn + Sync` needs only a shared reference.
        let f = unsafe { &*slot.f.get() };
        f(ctx)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

    struct Count(Arc<AtomicU64>);
    impl SafeState for Count {
        fn go_safe(&self) {
            self.0.fetch_add(1, Relaxed);
        }
    }

    #[test]
    fn trampolines_call_count_and_contain_a_panic() {
        let ctl = Arc::new(ModuleCtl::new("drv"));
        let safe = Arc::new(AtomicU64::new(0));
        ctl.arm(vec![Box::new(Count(safe.clone()))]);
        let calls = Arc::new(AtomicU64::new(0));
        let c = calls.clone();
        let mut n = 0u64;
        let f = OwnedFunct::exclusive(ctl.clone(), "drv.read", move |ctx: &FunctCtx| {
            n += 1;
            c.store(n * 1000 + ctx.period() as u64, Relaxed);
        });
        // SAFETY: the slot with its own trampoline, alive for the test.
        unsafe { (f.call())(f.arg(), 7) };
        assert_eq!(calls.load(Relaxed), 1007);

        let boom = OwnedFunct::shared(ctl.clone(), "drv.write", |_: &FunctCtx| panic!("bug"));
        // SAFETY: as above.
        unsafe { (boom.call())(boom.arg(), 1) };
        assert_eq!(safe.load(Relaxed), 1, "a panic goes safe");
        // SAFETY: as above; a faulted module's functions do nothing.
        unsafe { (boom.call())(boom.arg(), 1) };
        // SAFETY: as above.
        unsafe { (f.call())(f.arg(), 7) };
        assert_eq!(safe.load(Relaxed), 1, "said and made safe once");
        assert_eq!(calls.load(Relaxed), 1007, "the module's functions stopped");
        assert_eq!(ctl.running.load(SeqCst), 0);
        assert!(ctl.stop_and_wait());
    }
}
