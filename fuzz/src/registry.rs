//! The modules the fuzz targets may load: every module of the host's
//! registry, with each hardware driver replaced by an entry that can only
//! reach its simulated backend.
//!
//! A fuzzer that loads `hal_parport cfg=0x378` as root on a machine with
//! a parallel port would write random bytes to it (or, with a random
//! address, to any I/O port). So no driver module reaches the fuzzers as
//! it is: [`fuzz_registry`] keeps the software modules (those of
//! `hal_components` and `motion`) and swaps every other module for its
//! entry in [`SIM_ONLY`], which parses the fuzzed parameters with the
//! driver's own code and then loads it with every port turned into a
//! simulated one. A registry module in neither list stops the fuzz run
//! with a message saying what to add, so a new driver cannot reach the
//! fuzzers with its real backend.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Registry, Result};
use hal_parport::cfg::{self, Backend, PortAddr};
use hal_parport::clock::MonotonicClock;
use hal_parport::select::SysPaths;

/// Driver modules in their simulated-only form, by `loadrt` name.
pub const SIM_ONLY: &[&ModuleDef] = &[&PARPORT_SIM_ONLY];

/// The host's registry, safe to fuzz: software modules as they are,
/// drivers from [`SIM_ONLY`]. Panics if a registry module is in neither.
pub fn fuzz_registry() -> Registry {
    let software: Vec<&'static str> = hal_components::modules()
        .into_iter()
        .chain(motion::modules())
        .map(|d| d.name)
        .collect();
    let host = hal_tools::hostd::registry();
    let mut safe = Registry::new();
    for name in host.names() {
        if software.contains(&name) {
            safe.add(&[host.find(name).expect("listed by names()")]);
        } else if let Some(def) = SIM_ONLY.iter().find(|d| d.name == name) {
            safe.add(&[def]);
        } else {
            panic!(
                "module '{name}' is neither a software module nor in hal_fuzz::registry::SIM_ONLY: \
                 give it a simulated-only entry there (fuzz/README.md) before fuzzing loads it"
            );
        }
    }
    safe
}

/// `hal_parport`, with every port on the simulator.
static PARPORT_SIM_ONLY: ModuleDef = ModuleDef {
    name: hal_parport::MODULE.name,
    params: hal_parport::MODULE.params,
    help: hal_parport::MODULE.help,
    load: parport_sim_only,
};

/// Parses `cfg` as the driver does; a string that parses is loaded with
/// every port's backend made `sim` (`simloop` stays), one that does not
/// goes to the driver unchanged to fail there, before any port is
/// touched.
fn parport_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    let given = args.str("cfg").unwrap_or(cfg::DEFAULT_CFG);
    let cfg = match cfg::parse(given) {
        Ok(specs) => specs
            .iter()
            .map(|s| {
                let addr = match s.addr {
                    PortAddr::Number(n) => format!("{n:x}"),
                    PortAddr::Address(a) => format!("{a:#x}"),
                };
                let backend = match s.backend {
                    Some(Backend::SimLoop) => Backend::SimLoop,
                    _ => Backend::Sim,
                };
                format!("{addr} {} {}", s.mode.name(), backend.name())
            })
            .collect::<Vec<_>>()
            .join(" "),
        Err(_) => given.to_string(),
    };
    let nowhere = SysPaths {
        dev: "/nonexistent/hal-fuzz/dev".into(),
        proc_parport: "/nonexistent/hal-fuzz/proc".into(),
    };
    hal_parport::hal::load_cfg(host, &cfg, &nowhere, Arc::new(MonotonicClock))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registry_module_is_fuzzable_and_drivers_are_simulated() {
        let r = fuzz_registry();
        assert_eq!(r.names(), hal_tools::hostd::registry().names());
        let pp = r.find("hal_parport").unwrap();
        assert!(std::ptr::eq(pp, &PARPORT_SIM_ONLY));
    }

    #[test]
    fn parport_ports_are_always_simulated() {
        let host = Host::create(hal_core::HostConfig::for_tests("fuzz-pp")).unwrap();
        // A raw I/O address and a ppdev number both come up simulated.
        host.loadrt(&PARPORT_SIM_ONLY, &["cfg=0x378 out raw 1 in ppdev"])
            .unwrap();
        let inst = host.instance();
        assert!(inst.pin("parport.0.pin-02-out").unwrap().is_some());
        assert!(inst.pin("parport.1.pin-02-in").unwrap().is_some());
        assert!(hal_parport::sim::find(inst.name(), 0).is_some());
        assert!(hal_parport::sim::find(inst.name(), 1).is_some());
        host.unloadrt("all").unwrap();
        // A bad string fails in the driver's own parser.
        let e = host
            .loadrt(&PARPORT_SIM_ONLY, &["cfg=0x378 sim sim"])
            .unwrap_err();
        assert!(e.to_string().contains("bad port address 'sim'"), "{e}");
    }
}
