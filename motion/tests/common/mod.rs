//! What the motion integration tests share: a private host, module
//! loading, looped-back motors, and reading pins while threads run.
#![allow(
    dead_code,
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test; not every test uses every helper"
)]

use std::time::{Duration, Instant};

use hal_core::{HalType, Host, HostConfig, Result, Value};

/// A host of its own for the test `tag` (unique across the test files).
pub fn host(tag: &str) -> Host {
    Host::create(HostConfig::for_tests(&format!("mot-{tag}"))).expect("host starts")
}

/// `loadrt module args...` with the motion crate's modules.
pub fn loadrt(h: &Host, module: &str, args: &[&str]) -> Result<()> {
    let def = motion::modules()
        .into_iter()
        .find(|d| d.name == module)
        .expect("module exists");
    h.loadrt(def, args)
}

/// Feeds each of the first `n` joints' motor command back as its motor
/// feedback (a perfect motor).
pub fn loop_back_motors(h: &Host, n: usize) {
    let inst = h.instance();
    for j in 0..n {
        let sig = format!("j{j}-pos");
        inst.newsig(&sig, HalType::Float).unwrap();
        inst.link(&format!("joint.{j}.motor-pos-cmd"), &sig)
            .unwrap();
        inst.link(&format!("joint.{j}.motor-pos-fb"), &sig).unwrap();
    }
}

/// Adds motmod's two functions to its servo thread and starts the threads.
pub fn start_motion(h: &Host) {
    h.addf("motion-command-handler", "servo-thread", -1)
        .unwrap();
    h.addf("motion-controller", "servo-thread", -1).unwrap();
    h.start().unwrap();
}

/// Polls `f` until it holds; fails the test after 10 s.
pub fn wait_for(what: &str, mut f: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(10);
    while !f() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// A float pin's value.
pub fn float(h: &Host, pin: &str) -> f64 {
    match h.instance().pin_value(pin).unwrap() {
        Value::Float(v) => v,
        v => panic!("{pin}: {v:?}"),
    }
}

/// A bit pin's value.
pub fn bit(h: &Host, pin: &str) -> bool {
    match h.instance().pin_value(pin).unwrap() {
        Value::Bit(v) => v,
        v => panic!("{pin}: {v:?}"),
    }
}
