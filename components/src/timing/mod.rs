//! Edges, timers and latches (reference section 8): edge, flipflop,
//! oneshot, timedelay, toggle, toggle2nist, debounce, dbounce, updown,
//! charge_pump, estop_latch, sample_hold; and ton, tof and tp (the IEC
//! timers), time, reset, safety_latch, watchdog, multiclick.
//!
//! Each component keeps its per-call logic in a plain struct whose `step`
//! works on a struct of pin and param values, so the logic can be tested
//! (and reused) without a HAL. The HAL glue reads the pins, calls `step`
//! and writes back what changed; components read their own outputs back,
//! so the values passed in are always the current pin values.

pub mod charge_pump;
pub mod debounce;
pub mod edge;
pub mod estop_latch;
pub mod flipflop;
pub mod iec_timers;
pub mod multiclick;
pub mod oneshot;
pub mod reset;
pub mod safety_latch;
pub mod sample_hold;
pub mod time;
pub mod timedelay;
pub mod toggle;
pub mod updown;
pub mod watchdog;

use hal_core::handles::Writable;
use hal_core::PinValue;

/// Writes `new` to an output or I/O pin if it differs from `old`, the
/// value read at the start of the call. A function that leaves a value
/// unchanged thus never writes it, as the C code only writes in the
/// branches that change it.
#[inline(always)]
pub(crate) fn write_changed<T: PinValue + PartialEq, D: Writable>(
    pin: &hal_core::Pin<T, D>,
    old: T,
    new: T,
) {
    if old != new {
        pin.set(new);
    }
}

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &edge::MODULE,
        &flipflop::MODULE,
        &oneshot::MODULE,
        &timedelay::MODULE,
        &toggle::TOGGLE,
        &toggle::TOGGLE2NIST,
        &debounce::DEBOUNCE,
        &debounce::DBOUNCE,
        &updown::MODULE,
        &charge_pump::MODULE,
        &estop_latch::MODULE,
        &sample_hold::MODULE,
        &iec_timers::TON,
        &iec_timers::TOF,
        &iec_timers::TP,
        &time::MODULE,
        &reset::MODULE,
        &safety_latch::MODULE,
        &watchdog::MODULE,
        &multiclick::MODULE,
    ]
}
