//! What the component tests share: a HAL instance of their own, pin
//! access by name, the simulated drive on simulated time.
#![allow(dead_code)]
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use hal_core::{Component, ComponentKind, Host, HostConfig, Instance, PinDir, Value};
use hal_driver::sim::SimClock;
use hal_serial::crc;
use hal_serial::line::{LineSettings, SimLine};
use hal_serial::sim::{Protocol, VfdSim};
use hal_serial::vfd::Cycle;

/// A component on the simulated drive, in an instance of its own, on
/// simulated time.
pub struct Rig<V: Cycle> {
    _host: Host,
    /// The instance.
    pub inst: Instance,
    _comp: Component,
    /// The drive.
    pub sim: Arc<Mutex<VfdSim>>,
    /// The component.
    pub vfd: V,
    clock: Arc<SimClock>,
    prefix: String,
}

impl<V: Cycle> Rig<V> {
    /// Makes component `prefix` with `build` on a line to `sim`.
    pub fn new(
        tag: &str,
        prefix: &str,
        sim: Arc<Mutex<VfdSim>>,
        build: impl FnOnce(&Component, SimLine) -> V,
    ) -> Rig<V> {
        let host = host(tag);
        let inst = host.instance().clone();
        let comp = inst.new_component(prefix, ComponentKind::User).unwrap();
        let line = line(&sim);
        let clock = line.clock().clone();
        let vfd = build(&comp, line);
        comp.ready().unwrap();
        Rig {
            _host: host,
            inst,
            _comp: comp,
            sim,
            vfd,
            clock,
            prefix: prefix.to_string(),
        }
    }

    /// One cycle, then the period passes.
    pub fn cycle(&mut self) {
        self.vfd.cycle();
        self.clock.advance(self.vfd.period().as_nanos() as u64);
    }

    /// `n` cycles.
    pub fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    /// The line's clock.
    pub fn now(&self) -> Duration {
        Duration::from_nanos(self.clock.peek())
    }

    fn pin(&self, pin: &str) -> String {
        format!("{}.{pin}", self.prefix)
    }

    /// Sets one of the component's pins.
    pub fn set(&self, pin: &str, v: Value) {
        set(&self.inst, &self.pin(pin), v);
    }

    /// Reads one of the component's float pins.
    pub fn float(&self, pin: &str) -> f64 {
        float(&self.inst, &self.pin(pin))
    }

    /// Reads one of the component's bit pins.
    pub fn bit(&self, pin: &str) -> bool {
        bit(&self.inst, &self.pin(pin))
    }

    /// Reads one of the component's pins.
    pub fn get(&self, pin: &str) -> Value {
        get(&self.inst, &self.pin(pin))
    }
}

/// A host of its own for one test.
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(tag)).expect("host")
}

/// A simulated drive at address 1.
pub fn drive(protocol: Protocol, settings: LineSettings) -> Arc<Mutex<VfdSim>> {
    Arc::new(Mutex::new(VfdSim::new(protocol, 1, settings)))
}

/// A line to it.
pub fn line(sim: &Arc<Mutex<VfdSim>>) -> SimLine {
    SimLine::new(sim.clone())
}

/// The drive, locked.
pub fn lock(sim: &Mutex<VfdSim>) -> MutexGuard<'_, VfdSim> {
    sim.lock().unwrap()
}

/// Takes the requests logged so far.
pub fn take_requests(sim: &Mutex<VfdSim>) -> Vec<Vec<u8>> {
    let mut s = lock(sim);
    let r = s.requests().to_vec();
    s.clear_requests();
    r
}

/// A frame with its CRC.
pub fn frame(body: &[u8]) -> Vec<u8> {
    let mut f = body.to_vec();
    crc::append(&mut f);
    f
}

/// Reads a pin.
pub fn get(inst: &Instance, pin: &str) -> Value {
    inst.pin_value(pin)
        .unwrap_or_else(|e| panic!("pin {pin}: {e}"))
}

/// Reads a float pin.
pub fn float(inst: &Instance, pin: &str) -> f64 {
    match get(inst, pin) {
        Value::Float(v) => v,
        other => panic!("{pin} is {other:?}"),
    }
}

/// Reads a bit pin.
pub fn bit(inst: &Instance, pin: &str) -> bool {
    match get(inst, pin) {
        Value::Bit(v) => v,
        other => panic!("{pin} is {other:?}"),
    }
}

/// Sets a pin.
pub fn set(inst: &Instance, pin: &str, v: Value) {
    inst.set_pin(pin, v)
        .unwrap_or_else(|e| panic!("pin {pin}: {e}"))
}

/// Every pin of component `owner`: (name without the prefix, type, direction).
pub fn pins_of(inst: &Instance, owner: &str) -> Vec<(String, String, PinDir)> {
    let mut v: Vec<_> = inst
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == owner)
        .map(|p| {
            (
                p.name[owner.len() + 1..].to_string(),
                format!("{:?}", p.hal_type).to_lowercase(),
                p.dir,
            )
        })
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

/// Whether `a` is within `tol` of `b`.
pub fn near(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}
