//! Helpers of the Servo-To-Go HAL tests: hosts, simulated boards, threads and
//! waiting on conditions.
#![allow(dead_code)]

use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Value};
use hal_driver::sim::SimBoard;
use hal_stg::sim::StgModel;

/// A host of its own for test `tag`.
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(&format!("stg-{tag}"))).unwrap()
}

/// The simulated board the driver published.
pub fn board(host: &Host) -> Arc<SimBoard<StgModel>> {
    hal_driver::sim::find(host.instance().name(), "stg").expect("no simulated stg")
}

/// Runs `functs` in a 1 ms thread `servo`, in order.
pub fn run(host: &Host, functs: &[&str]) {
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    for f in functs {
        host.addf(f, "servo", -1).unwrap();
    }
    host.start().unwrap();
}

/// Waits until `cond` holds, failing with `what` after 20 s.
pub fn wait(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(20);
    while !cond() {
        assert!(Instant::now() < end, "never happened: {what}");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// A pin's or param's value.
pub fn get(host: &Host, name: &str) -> Value {
    let inst = host.instance();
    inst.pin_value(name)
        .or_else(|_| inst.param_value(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A float pin or param.
pub fn float(host: &Host, name: &str) -> f64 {
    match get(host, name) {
        Value::Float(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}

/// An s32 pin.
pub fn s32(host: &Host, name: &str) -> i32 {
    match get(host, name) {
        Value::S32(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}

/// A bit pin or param.
pub fn bit(host: &Host, name: &str) -> bool {
    match get(host, name) {
        Value::Bit(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}

/// Sets a pin, or a param of that name.
pub fn set(host: &Host, name: &str, v: Value) {
    let inst = host.instance();
    if inst.set_pin(name, v).is_err() {
        inst.set_param(name, v)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

/// The realtime log's messages so far (after flushing it).
pub fn log_lines(host: &Host) -> Vec<String> {
    host.flush_rt_log();
    host.rt_log()
        .history()
        .into_iter()
        .map(|(_, t)| t)
        .collect()
}
