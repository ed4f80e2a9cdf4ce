//! Edges, timers and latches (reference section 8): edge, flipflop,
//! oneshot, timedelay, toggle, toggle2nist, debounce, dbounce, updown,
//! charge_pump, estop_latch, sample_hold.
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
pub mod oneshot;
pub mod sample_hold;
pub mod timedelay;
pub mod toggle;
pub mod updown;

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
    ]
}

/// Helpers for tests that load modules into a private host.
#[cfg(test)]
pub(crate) mod testhost {

    use hal_core::{Host, HostConfig, ModuleDef, Result};

    /// A host on an instance no other test uses, without realtime.
    pub fn host() -> Host {
        Host::create(HostConfig::for_tests("comp")).expect("host starts")
    }

    /// Loads `def` with `args` into `host`.
    pub fn load(host: &Host, def: &'static ModuleDef, args: &[&str]) -> Result<()> {
        let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        host.loadrt(def, &args)
    }

    /// Names of every pin, sorted.
    pub fn pin_names(host: &Host) -> Vec<String> {
        let mut v: Vec<String> = host
            .instance()
            .pins()
            .unwrap()
            .into_iter()
            .map(|p| p.name)
            .collect();
        v.sort();
        v
    }

    /// Names of every param, sorted.
    pub fn param_names(host: &Host) -> Vec<String> {
        let mut v: Vec<String> = host
            .instance()
            .params()
            .unwrap()
            .into_iter()
            .map(|p| p.name)
            .collect();
        v.sort();
        v
    }

    /// Names of every function, sorted.
    pub fn funct_names(host: &Host) -> Vec<String> {
        let mut v: Vec<String> = host
            .instance()
            .functs()
            .unwrap()
            .into_iter()
            .map(|f| f.name)
            .collect();
        v.sort();
        v
    }
}
