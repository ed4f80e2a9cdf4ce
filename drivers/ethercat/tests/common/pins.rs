//! Reading and setting pins of a test's host by name.
#![allow(dead_code, reason = "each test binary uses some of these")]

use hal_core::{Host, Value};

/// The value of pin `name`.
pub fn pin(host: &Host, name: &str) -> Value {
    host.instance().pin_value(name).unwrap()
}

/// Sets pin `name` (not connected to a signal) to `v`.
pub fn set(host: &Host, name: &str, v: Value) {
    host.instance().set_pin(name, v).unwrap();
}

/// Bit pin `name`; fails the test on another type.
pub fn bit(host: &Host, name: &str) -> bool {
    match pin(host, name) {
        Value::Bit(b) => b,
        v => panic!("{name} is {v:?}"),
    }
}

/// Float pin `name`; fails the test on another type.
pub fn float(host: &Host, name: &str) -> f64 {
    match pin(host, name) {
        Value::Float(f) => f,
        v => panic!("{name} is {v:?}"),
    }
}

/// s32 pin `name`; fails the test on another type.
pub fn s32(host: &Host, name: &str) -> i32 {
    match pin(host, name) {
        Value::S32(v) => v,
        v => panic!("{name} is {v:?}"),
    }
}
