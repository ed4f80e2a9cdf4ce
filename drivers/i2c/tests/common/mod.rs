//! Helpers shared by the hal-i2c integration tests.
#![allow(dead_code)]
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::time::Duration;

use hal_core::{Host, HostConfig, Value};

/// A host on an instance no other test uses.
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(&format!("i2c-{tag}"))).expect("host starts")
}

/// Sets an unconnected input pin.
pub fn set(h: &Host, pin: &str, v: Value) {
    h.instance()
        .set_pin(pin, v)
        .unwrap_or_else(|e| panic!("{pin}: {e}"));
}

/// A pin's value.
pub fn value(h: &Host, pin: &str) -> Value {
    h.instance()
        .pin_value(pin)
        .unwrap_or_else(|e| panic!("{pin}: {e}"))
}

/// Waits (up to a minute: the VM rig is slow) until `cond` holds.
pub fn wait_for(what: &str, cond: impl FnMut() -> bool) {
    assert!(
        hal_driver::vmrig::wait_until(Duration::from_secs(60), cond),
        "timed out waiting for {what}"
    );
}

/// Runs `functs` in a 1 ms thread `servo`.
pub fn run(h: &Host, functs: &[&str]) {
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    for f in functs {
        h.addf(f, "servo", -1).unwrap();
    }
    h.start().unwrap();
}
