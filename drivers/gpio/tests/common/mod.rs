//! Helpers shared by the hal_gpio integration tests.
#![allow(dead_code)]
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::time::Duration;

use hal_core::{Host, HostConfig, Value};

/// A host on an instance no other test uses.
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(&format!("gpio-{tag}"))).expect("host starts")
}

/// A bit pin's value.
pub fn bit(h: &Host, pin: &str) -> bool {
    match h
        .instance()
        .pin_value(pin)
        .unwrap_or_else(|e| panic!("{pin}: {e}"))
    {
        Value::Bit(b) => b,
        v => panic!("{pin} is {v:?}"),
    }
}

/// Sets an unconnected bit input pin.
pub fn set(h: &Host, pin: &str, v: bool) {
    h.instance()
        .set_pin(pin, Value::Bit(v))
        .unwrap_or_else(|e| panic!("{pin}: {e}"));
}

/// Waits (up to a minute: the VM rig is slow) until `cond` holds.
pub fn wait_for(what: &str, cond: impl FnMut() -> bool) {
    assert!(
        hal_driver::vmrig::wait_until(Duration::from_secs(60), cond),
        "timed out waiting for {what}"
    );
}

/// Runs `functs` in a thread `t` of `period_ns`.
pub fn run(h: &Host, period_ns: i64, functs: &[&str]) {
    h.create_thread("t", period_ns, false, None).unwrap();
    for f in functs {
        h.addf(f, "t", -1).unwrap();
    }
    h.start().unwrap();
}
