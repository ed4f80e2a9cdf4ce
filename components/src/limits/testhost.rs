//! Test support for the limits and filters families: a private HAL host
//! to load modules into, set pins and params, and run functions in a
//! thread for a number of cycles. Used to check the HAL glue (names,
//! defaults, pins read back) on top of the unit tests of the arithmetic.

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, ModuleDef, Result, Value};

/// A host on an instance no other test (or test process) uses, without
/// realtime scheduling and with a small segment.
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(&format!("lim-{tag}"))).expect("host starts")
}

/// `loadrt <def> <args...>`.
pub fn load(host: &Host, def: &'static ModuleDef, args: &[&str]) -> Result<()> {
    host.loadrt(def, args)
}

/// The value of a pin.
pub fn pin(host: &Host, name: &str) -> Value {
    host.instance().pin_value(name).expect(name)
}

/// The value of a param.
pub fn param(host: &Host, name: &str) -> Value {
    host.instance().param_value(name).expect(name)
}

/// `setp` on a pin.
pub fn set_pin(host: &Host, name: &str, v: Value) {
    host.instance().set_pin(name, v).expect(name)
}

/// `setp` on a param.
pub fn set_param(host: &Host, name: &str, v: Value) {
    host.instance().set_param(name, v).expect(name)
}

/// Names of all pins and params starting with `prefix`, sorted.
pub fn items(host: &Host, prefix: &str) -> Vec<String> {
    let inst = host.instance();
    let mut v: Vec<String> = inst
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .chain(inst.params().unwrap().into_iter().map(|p| p.name))
        .filter(|n| n.starts_with(prefix))
        .collect();
    v.sort();
    v
}

/// Puts `functs` in a new 1 ms thread `t`, runs it for at least `n`
/// cycles, stops it and returns the exact number of cycles run.
pub fn run(host: &Host, functs: &[&str], n: i64) -> i64 {
    host.create_thread("t", 1_000_000, true, None).unwrap();
    for f in functs {
        host.addf(f, "t", -1).unwrap();
    }
    let beat = || match pin(host, "t.threadbeat") {
        Value::S64(v) => v,
        Value::S32(v) => i64::from(v),
        Value::U32(v) => i64::from(v),
        v => panic!("threadbeat {v:?}"),
    };
    host.start().unwrap();
    let end = Instant::now() + Duration::from_secs(30);
    while beat() < n && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(2));
    }
    host.stop();
    beat()
}

/// A float value, or a panic naming what it was.
pub fn float(v: Value) -> f64 {
    match v {
        Value::Float(f) => f,
        v => panic!("not a float: {v:?}"),
    }
}
