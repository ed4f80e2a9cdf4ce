//! Helpers shared by the hal_parport integration tests.
#![allow(dead_code)]
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Value};
use hal_parport::sim::SimPort;

/// A host on an instance no other test uses, without realtime, with room
/// for eight ports.
pub fn host(tag: &str) -> Host {
    let mut cfg = HostConfig::for_tests(&format!("pp-{tag}"));
    cfg.shm_size = 8 << 20;
    Host::create(cfg).expect("host starts")
}

/// `loadrt hal_parport cfg=<cfg>`.
pub fn loadrt(host: &Host, cfg: &str) -> hal_core::Result<()> {
    host.loadrt(&hal_parport::MODULE, &[format!("cfg={cfg}")])
}

/// The simulated port `n` of the loaded module.
pub fn sim(host: &Host, n: usize) -> Arc<SimPort> {
    hal_parport::sim::find(host.instance().name(), n).expect("simulated port registered")
}

/// A bit pin's value.
pub fn bit(host: &Host, pin: &str) -> bool {
    match host
        .instance()
        .pin_value(pin)
        .unwrap_or_else(|e| panic!("{pin}: {e}"))
    {
        Value::Bit(b) => b,
        v => panic!("{pin} is {v:?}"),
    }
}

/// Sets an unconnected input pin.
pub fn set(host: &Host, pin: &str, v: bool) {
    host.instance()
        .set_pin(pin, Value::Bit(v))
        .unwrap_or_else(|e| panic!("{pin}: {e}"));
}

/// Sets a bit or u32 parameter.
pub fn setp(host: &Host, param: &str, v: Value) {
    host.instance()
        .set_param(param, v)
        .unwrap_or_else(|e| panic!("{param}: {e}"));
}

/// A parameter's value.
pub fn param(host: &Host, param: &str) -> Value {
    host.instance()
        .param_value(param)
        .unwrap_or_else(|e| panic!("{param}: {e}"))
}

/// Creates thread `t` with `period_ns`, adds `functs` in order and starts.
pub fn run(host: &Host, period_ns: i64, functs: &[&str]) {
    host.create_thread("t", period_ns, false, None).unwrap();
    for f in functs {
        host.addf(f, "t", -1).unwrap();
    }
    host.start().unwrap();
}

/// Waits until `sim`'s status register has been read `n` more times:
/// with read before write in the thread, two more reads mean a whole
/// cycle ran after the caller's change.
pub fn cycles(sim: &SimPort, n: u64) {
    // `read` reads the status register first and sets the HAL pins last,
    // so the n-th counted read may still be running: wait for one more,
    // which starts only after the n-th cycle has finished.
    let start = sim.reads(hal_parport::regs::STATUS);
    let end = Instant::now() + Duration::from_secs(10);
    while sim.reads(hal_parport::regs::STATUS) < start + n + 1 {
        assert!(Instant::now() < end, "thread did not run");
        std::thread::sleep(Duration::from_micros(200));
    }
}
