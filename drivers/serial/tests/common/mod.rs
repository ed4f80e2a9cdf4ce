//! What the component tests share: a HAL instance of their own, pin
//! access by name, the simulated drive on simulated time.
#![allow(dead_code)]

use std::sync::{Arc, Mutex, MutexGuard};

use hal_core::{Host, HostConfig, Instance, PinDir, Value};
use hal_serial::crc;
use hal_serial::line::{LineSettings, SimLine};
use hal_serial::sim::{Protocol, VfdSim};

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
