//! Helpers for tests that load modules into a private host.

use hal_core::{Host, HostConfig, ModuleDef, Result};

/// A host on an instance no other test uses, without realtime.
pub fn host() -> Host {
    Host::create(HostConfig::for_tests("comp")).expect("host starts")
}

/// Loads `def` with `args` into `host`.
pub fn load(host: &Host, def: &'static ModuleDef, args: &[&str]) -> Result<()> {
    host.loadrt(def, args)
}

/// Names of every pin, sorted.
pub fn pin_names(host: &Host) -> Vec<String> {
    let mut v: Vec<String> = host
        .instance()
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .collect();
    v.sort();
    v
}

/// Names of every param, sorted.
pub fn param_names(host: &Host) -> Vec<String> {
    let mut v: Vec<String> = host
        .instance()
        .params()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .collect();
    v.sort();
    v
}

/// Names of every function, sorted.
pub fn funct_names(host: &Host) -> Vec<String> {
    let mut v: Vec<String> = host
        .instance()
        .functs()
        .unwrap()
        .into_iter()
        .map(|f| f.name)
        .collect();
    v.sort();
    v
}
