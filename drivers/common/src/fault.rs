//! Safe state and fault reporting.
//!
//! * [`SafeState`]: what a driver does to make its hardware harmless
//!   (outputs off, DACs to 0 V, amplifier enables off, the watchdog
//!   allowed to bite). [`install`] makes it the component's hal-core
//!   safe-state hook, which the host calls after a fault in any realtime
//!   function, at unload and at exit, in reverse load order.
//! * [`FaultLatch`]: a realtime function that finds its hardware gone or
//!   misbehaving trips the latch with a [`Fault`] (a code and a
//!   `&'static str` reason). Atomics only; the first trip wins and is
//!   said exactly once through the host's realtime log
//!   ([`hal_core::RtLog`], or LinuxCNC's `rtapi_print_msg`: a
//!   [`LogSink`]) as `<prefix>: <reason>`; optional HAL pins show it; an
//!   explicit [`reset`](FaultLatch::reset) clears it. The latch is generic
//!   over the host its pins live in ([`FaultLatch::named`]); `new` makes
//!   one in ours.
//!
//! ```no_run
//! use std::sync::Arc;
//! use hal_core::{Host, Out, Pin};
//! use hal_driver::fault::{self, Fault, FaultLatch, SafeState};
//!
//! static WATCHDOG_BIT: Fault = Fault::new(1, "watchdog has bit, outputs are off");
//!
//! struct Board { /* bus, pins */ latch: FaultLatch }
//! impl SafeState for Board {
//!     fn go_safe(&self) { /* write the outputs' off state */ }
//! }
//!
//! # fn load(host: &Host) -> hal_core::Result<()> {
//! let mut b = host.new_rt_component("myboard")?;
//! let pin: Pin<bool, Out> = b.component().pin("myboard.0.fault")?;
//! let latch = FaultLatch::new("myboard.0").with_log(host.rt_log()).with_pin(pin);
//! let board = Arc::new(Board { latch });
//! let rt = board.clone();
//! b.funct("myboard.0.read", false, move |_ctx| {
//!     let bit = false; // read the watchdog status register here
//!     if bit && rt.latch.trip(&WATCHDOG_BIT) {
//!         rt.go_safe(); // first time only; the log says why
//!     }
//! })?;
//! fault::install(&mut b, board);
//! b.ready()
//! # }
//! ```

use std::sync::atomic::{AtomicPtr, AtomicU64, Ordering::*};
use std::sync::Arc;

use hal_core::{HalHost, HostPin, Ours, Out, RtComponentBuilder};

use crate::log::LogSink;

/// What a driver does to put its hardware in a safe state. Called from
/// non-realtime threads (the host's supervisor, unload, exit) while no
/// function of the component runs, and by the driver itself after a trip.
pub trait SafeState: Send + Sync + 'static {
    /// Outputs off, DACs to 0 V, amplifier enables off, watchdog allowed
    /// to bite. Must not fail and must be safe to call repeatedly.
    fn go_safe(&self);
}

impl<T: SafeState + ?Sized> SafeState for Arc<T> {
    fn go_safe(&self) {
        (**self).go_safe()
    }
}

impl<T: SafeState> SafeState for Vec<T> {
    /// Every element, in order.
    fn go_safe(&self) {
        for s in self {
            s.go_safe();
        }
    }
}

/// Makes `state` the safe-state hook of the component being built.
pub fn install(builder: &mut RtComponentBuilder<'_>, state: impl SafeState) {
    builder.on_safe_state(move || state.go_safe());
}

/// A fault a driver can report: declared once as a `static`, so a trip
/// stores one pointer.
#[derive(Debug, PartialEq, Eq)]
pub struct Fault {
    /// Non-zero code, shown on the code pin.
    pub code: u32,
    /// What happened and what the driver did, said once.
    pub reason: &'static str,
}

impl Fault {
    /// A fault with `code` (non-zero) and `reason`.
    pub const fn new(code: u32, reason: &'static str) -> Fault {
        Fault { code, reason }
    }
}

/// A latch a realtime function trips when its hardware fails; its pins
/// live in host `H`.
pub struct FaultLatch<H: HalHost = Ours> {
    prefix: String,
    tripped: AtomicPtr<Fault>,
    log: Option<LogSink>,
    pin: Option<H::Pin<bool, Out>>,
    code_pin: Option<H::Pin<u32, Out>>,
}

impl<H: HalHost> std::fmt::Debug for FaultLatch<H> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaultLatch")
            .field("prefix", &self.prefix)
            .field("fault", &self.fault())
            .finish()
    }
}

impl FaultLatch {
    /// A clear latch in our host whose messages start with `prefix` (the
    /// board's HAL name, `hm2_5i25.0`).
    pub fn new(prefix: impl Into<String>) -> FaultLatch {
        FaultLatch::named(prefix)
    }
}

impl<H: HalHost> FaultLatch<H> {
    /// A clear latch in host `H` whose messages start with `prefix`
    /// (`FaultLatch::<H>::named("motenc.0")` in a driver generic over
    /// its host).
    pub fn named(prefix: impl Into<String>) -> Self {
        FaultLatch {
            prefix: prefix.into(),
            tripped: AtomicPtr::new(std::ptr::null_mut()),
            log: None,
            pin: None,
            code_pin: None,
        }
    }

    /// Says the first trip through `log` (normally `host.rt_log()`, or
    /// the driver's [`Exporter::log`](crate::Exporter::log)), at level
    /// `Err`.
    pub fn with_log(mut self, log: impl Into<LogSink>) -> Self {
        self.log = Some(log.into());
        self
    }

    /// Shows "tripped" on `pin`.
    pub fn with_pin(mut self, pin: H::Pin<bool, Out>) -> Self {
        self.pin = Some(pin);
        self
    }

    /// Shows the fault's code on `pin` (0 when clear).
    pub fn with_code_pin(mut self, pin: H::Pin<u32, Out>) -> Self {
        self.code_pin = Some(pin);
        self
    }

    /// Trips the latch with `fault`; realtime-safe. Returns true for the
    /// call that tripped it (say why and go safe then); false when it was
    /// already tripped, whatever the fault (the first one stays).
    pub fn trip(&self, fault: &'static Fault) -> bool {
        // Already tripped: a plain load, no locked instruction.
        if self.is_tripped() {
            return false;
        }
        let p = fault as *const Fault as *mut Fault;
        if self
            .tripped
            .compare_exchange(std::ptr::null_mut(), p, AcqRel, Acquire)
            .is_err()
        {
            return false;
        }
        // The code goes out before the flag: whoever sees `fault` TRUE
        // (a panel, halcmd, a test polling from another thread) must
        // also see why.
        if let Some(pin) = &self.code_pin {
            pin.set(fault.code);
        }
        std::sync::atomic::fence(Release);
        if let Some(pin) = &self.pin {
            pin.set(true);
        }
        if let Some(log) = &self.log {
            log.err(format_args!("{}: {}", self.prefix, fault.reason));
        }
        true
    }

    /// [`trip`](Self::trip), and on the first trip puts `state` in its
    /// safe state at once: what a realtime function does when it finds
    /// its hardware failing. Returns what `trip` returns.
    pub fn trip_into(&self, fault: &'static Fault, state: &(impl SafeState + ?Sized)) -> bool {
        let first = self.trip(fault);
        if first {
            state.go_safe();
        }
        first
    }

    /// The fault that tripped the latch, if it is tripped.
    pub fn fault(&self) -> Option<&'static Fault> {
        let p = self.tripped.load(Acquire);
        // SAFETY: the pointer is null or was made from a `&'static Fault`
        // in `trip`; such a reference is valid and immutable forever.
        unsafe { p.cast_const().as_ref() }
    }

    /// Whether the latch is tripped.
    pub fn is_tripped(&self) -> bool {
        !self.tripped.load(Acquire).is_null()
    }

    /// The tripping fault's code, 0 when clear.
    pub fn code(&self) -> u32 {
        self.fault().map_or(0, |f| f.code)
    }

    /// Clears the latch (the operator acknowledged, the hardware was
    /// re-armed), returning the fault it held. The next trip is said
    /// again.
    pub fn reset(&self) -> Option<&'static Fault> {
        let old = self.fault();
        self.tripped.store(std::ptr::null_mut(), Release);
        if let Some(pin) = &self.pin {
            pin.set(false);
        }
        if let Some(pin) = &self.code_pin {
            pin.set(0);
        }
        old
    }
}

/// Watches a bus's count of failed accesses
/// ([`RegWindow::errors`](crate::bus::RegWindow::errors),
/// [`PortBus::errors`](crate::bus::PortBus::errors)): whether any access
/// failed since the last look. Atomics only, realtime-safe.
#[derive(Debug)]
pub struct ErrorWatch {
    seen: AtomicU64,
}

impl ErrorWatch {
    /// Starts watching a bus whose count is `errors_now`.
    pub fn new(errors_now: u64) -> ErrorWatch {
        ErrorWatch {
            seen: AtomicU64::new(errors_now),
        }
    }

    /// Whether the count moved since the last call (or since `new`),
    /// given the bus's count now.
    #[inline]
    pub fn failed_since(&self, errors_now: u64) -> bool {
        self.seen.swap(errors_now, Relaxed) != errors_now
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::{MsgLevel, RtLog};

    static LOST: Fault = Fault::new(3, "board lost, outputs are off");
    static OTHER: Fault = Fault::new(4, "something else");

    #[test]
    fn first_trip_wins_and_is_said_once() {
        let log = RtLog::new(8);
        let latch = FaultLatch::new("drv.0").with_log(log.clone());
        assert!(!latch.is_tripped() && latch.fault().is_none() && latch.code() == 0);
        assert!(latch.trip(&LOST));
        assert!(!latch.trip(&LOST));
        assert!(!latch.trip(&OTHER));
        assert_eq!(latch.code(), 3);
        assert_eq!(latch.fault(), Some(&LOST));
        let mut said = Vec::new();
        log.drain(|l, t| said.push((l, t.to_string())));
        assert_eq!(
            said,
            vec![(
                MsgLevel::Err,
                "drv.0: board lost, outputs are off".to_string()
            )]
        );
        assert_eq!(latch.reset(), Some(&LOST));
        assert!(!latch.is_tripped());
        assert!(latch.trip(&OTHER));
        assert_eq!(latch.code(), 4);
        log.drain(|_, t| said.push((MsgLevel::Err, t.to_string())));
        assert_eq!(said.len(), 2, "said again after a reset");
    }

    #[test]
    fn racing_trips_have_one_winner() {
        let latch = FaultLatch::new("drv.0");
        let wins = std::thread::scope(|s| {
            let hs: Vec<_> = (0..4)
                .map(|i| {
                    let latch = &latch;
                    s.spawn(move || latch.trip(if i % 2 == 0 { &LOST } else { &OTHER }))
                })
                .collect();
            hs.into_iter()
                .map(|h| h.join().unwrap())
                .filter(|&w| w)
                .count()
        });
        assert_eq!(wins, 1);
        assert!(latch.is_tripped());
    }

    #[test]
    fn trip_into_goes_safe_once_and_errors_are_watched() {
        let latch = FaultLatch::new("drv.0");
        let safe = Counter(Default::default());
        assert!(latch.trip_into(&LOST, &safe));
        assert!(!latch.trip_into(&OTHER, &safe));
        assert_eq!(safe.0.load(Relaxed), 1);
        let w = ErrorWatch::new(3);
        assert!(!w.failed_since(3));
        assert!(w.failed_since(4));
        assert!(!w.failed_since(4));
    }

    struct Counter(std::sync::atomic::AtomicU32);
    impl SafeState for Counter {
        fn go_safe(&self) {
            self.0.fetch_add(1, Relaxed);
        }
    }

    #[test]
    fn collections_go_safe_element_by_element() {
        let parts: Vec<Arc<Counter>> = (0..3)
            .map(|_| Arc::new(Counter(Default::default())))
            .collect();
        parts.go_safe();
        parts.go_safe();
        assert!(parts.iter().all(|c| c.0.load(Relaxed) == 2));
    }
}
