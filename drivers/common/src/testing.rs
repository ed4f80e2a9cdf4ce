//! For drivers' HAL tests: a host per test, waiting on a condition,
//! pins and params by name, the realtime log's lines, a thread running
//! functions, and [`Flaky`], a bus whose accesses fail on demand (to
//! test a driver's readback faults). Test support only: these helpers
//! panic, with a message saying what was missing, where a test should
//! fail; nothing at run time uses them.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};
use std::time::Duration;

use hal_core::{Host, HostConfig, Value};

use crate::bus::{PortBus, RegWindow, ALL_ONES};

/// A host on an instance of its own for test `tag`.
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(tag))
        .unwrap_or_else(|e| panic!("a host for test {tag}: {e}"))
}

/// Runs `functs` in order in a new thread `thread` of `period_ns`, and
/// starts the threads.
pub fn run(host: &Host, thread: &str, period_ns: i64, functs: &[&str]) {
    host.create_thread(thread, period_ns, true, None)
        .unwrap_or_else(|e| panic!("thread {thread}: {e}"));
    for f in functs {
        host.addf(f, thread, -1)
            .unwrap_or_else(|e| panic!("addf {f}: {e}"));
    }
    host.start().unwrap_or_else(|e| panic!("start: {e}"));
}

/// Waits until `cond` holds, failing with `what` after 20 s.
pub fn wait(what: &str, cond: impl FnMut() -> bool) {
    assert!(
        crate::vmrig::wait_until(Duration::from_secs(20), cond),
        "never happened: {what}"
    );
}

/// The value of the pin, or else the param, `name`.
pub fn value(host: &Host, name: &str) -> Value {
    let inst = host.instance();
    inst.pin_value(name)
        .or_else(|_| inst.param_value(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A float pin or param.
pub fn float(host: &Host, name: &str) -> f64 {
    match value(host, name) {
        Value::Float(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}

/// An s32 pin or param.
pub fn s32(host: &Host, name: &str) -> i32 {
    match value(host, name) {
        Value::S32(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}

/// A bit pin or param.
pub fn bit(host: &Host, name: &str) -> bool {
    match value(host, name) {
        Value::Bit(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}

/// Sets the pin, or else the param, `name`.
pub fn set(host: &Host, name: &str, v: Value) {
    let inst = host.instance();
    if inst.set_pin(name, v).is_err() {
        inst.set_param(name, v)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

/// The realtime log's messages so far, after flushing it.
pub fn log_lines(host: &Host) -> Vec<String> {
    host.flush_rt_log();
    host.rt_log()
        .history()
        .into_iter()
        .map(|(_, t)| t)
        .collect()
}

/// A bus whose reads at the addresses `fails` picks return all ones and
/// count an error while it is failing; everything else goes to `inner`.
pub struct Flaky<B, F> {
    inner: B,
    fails: F,
    failing: AtomicBool,
    errors: AtomicU64,
}

impl<B, F: Fn(u64) -> bool> Flaky<B, F> {
    /// `inner`, working until [`set_failing`](Self::set_failing).
    pub fn new(inner: B, fails: F) -> Flaky<B, F> {
        Flaky {
            inner,
            fails,
            failing: AtomicBool::new(false),
            errors: AtomicU64::new(0),
        }
    }

    /// Starts or stops failing.
    pub fn set_failing(&self, on: bool) {
        self.failing.store(on, Relaxed);
    }

    /// Whether a read at `addr` fails now (and counts it).
    fn fails_at(&self, addr: u64) -> bool {
        let f = self.failing.load(Relaxed) && (self.fails)(addr);
        if f {
            self.errors.fetch_add(1, Relaxed);
        }
        f
    }
}

impl<B: RegWindow, F: Fn(u64) -> bool + Send + Sync> RegWindow for Flaky<B, F> {
    fn len(&self) -> usize {
        self.inner.len()
    }
    fn read32(&self, offset: usize) -> u32 {
        if self.fails_at(offset as u64) {
            return ALL_ONES;
        }
        self.inner.read32(offset)
    }
    fn write32(&self, offset: usize, value: u32) {
        self.inner.write32(offset, value)
    }
    fn errors(&self) -> u64 {
        self.errors.load(Relaxed) + self.inner.errors()
    }
    fn describe(&self) -> String {
        format!("flaky {}", self.inner.describe())
    }
    fn tick(&self, now_ns: u64) {
        self.inner.tick(now_ns)
    }
}

impl<B: PortBus, F: Fn(u64) -> bool + Send + Sync> PortBus for Flaky<B, F> {
    fn inb(&self, port: u16) -> u8 {
        if self.fails_at(port as u64) {
            return 0xFF;
        }
        self.inner.inb(port)
    }
    fn outb(&self, port: u16, value: u8) {
        self.inner.outb(port, value)
    }
    fn inw(&self, port: u16) -> u16 {
        if self.fails_at(port as u64) {
            return 0xFFFF;
        }
        self.inner.inw(port)
    }
    fn outw(&self, port: u16, value: u16) {
        self.inner.outw(port, value)
    }
    fn inl(&self, port: u16) -> u32 {
        if self.fails_at(port as u64) {
            return ALL_ONES;
        }
        self.inner.inl(port)
    }
    fn outl(&self, port: u16, value: u32) {
        self.inner.outl(port, value)
    }
    fn errors(&self) -> u64 {
        self.errors.load(Relaxed) + self.inner.errors()
    }
    fn describe(&self) -> String {
        format!("flaky {}", self.inner.describe())
    }
    fn tick(&self, now_ns: u64) {
        self.inner.tick(now_ns)
    }
}
