//! Signal generators: `pwmgen` (software PWM/PDM) and `siggen` (test
//! waveforms).

pub mod pwmgen;
pub mod siggen;

use hal_core::ModuleDef;

/// The modules of this family.
pub fn modules() -> Vec<&'static ModuleDef> {
    vec![&pwmgen::MODULE, &siggen::MODULE]
}

/// A HAL host on a private instance, for the family's tests.
#[cfg(test)]
pub(crate) fn test_host(tag: &str) -> hal_core::Host {
    hal_core::Host::create(hal_core::HostConfig::for_tests(&format!("gen-{tag}")))
        .expect("test host starts")
}

/// The names of every pin in the host, sorted.
#[cfg(test)]
pub(crate) fn pin_names(host: &hal_core::Host) -> Vec<String> {
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
