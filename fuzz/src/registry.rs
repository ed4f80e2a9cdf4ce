//! The modules the fuzz targets may load: every module of the host's
//! registry, with each hardware driver replaced by an entry that can only
//! reach its simulated backend.
//!
//! A fuzzer that loads `hal_parport cfg=0x378` as root on a machine with
//! a parallel port would write random bytes to it (or, with a random
//! address, to any I/O port); `hal_stg` as root probes I/O ports; the PCI
//! drivers map the BARs of whatever board sysfs lists. So no driver module
//! reaches the fuzzers as it is: [`fuzz_registry`] keeps the software
//! modules (those of `hal_components`, `hal_ladder`, `motion` and the launcher's
//! `tpmod`/`homemod`) and the driver modules of [`NO_DEVICE`], and swaps
//! every other module for its entry in [`SIM_ONLY`], which parses the
//! fuzzed parameters with the driver's own code and then loads it with a
//! simulated backend only. The modules of [`NOT_FUZZED`] (none today)
//! would have no simulated-only form and be left out of the fuzzers'
//! registry altogether. A registry module in none of these stops the fuzz run with
//! a message saying what to add, so a new driver cannot reach the fuzzers
//! with its real backend.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamKind};
use hal_core::{Host, Registry, Result};
use hal_driver::params::{Backend as DriverBackend, BackendTokens};
use hal_driver::pci::Sysfs;
use hal_parport::cfg::{self, Backend, PortAddr};
use hal_parport::clock::MonotonicClock;
use hal_parport::select::SysPaths;

/// Where the simulated-only entries look for devices: a path that does
/// not exist, so a real backend the driver picks finds nothing.
const NOWHERE: &str = "/nonexistent/hal-fuzz";

/// Driver modules that reach no device whatever their parameters, loaded
/// as they are: `hostmot2` (the driver core: settings only), `hm2_test`
/// (a register image held in memory), and `setsserial` and `hm2_modbus`
/// (they reach only the boards already loaded in their HAL, which the
/// fuzz registry's drivers make simulated ones; they read, never write,
/// a regular file).
pub const NO_DEVICE: &[&ModuleDef] = &[
    &hostmot2::hal::HOSTMOT2_MODULE,
    &hostmot2::hal::HM2_TEST_MODULE,
    &hostmot2::SETSSERIAL_MODULE,
    &hostmot2::modbus::hal::HM2_MODBUS_MODULE,
];

/// Driver modules the fuzzers never load, each with the reason: a
/// driver no parameter can keep off its device or network would go here
/// (`hm2_eth` did until it had `sim=`).
pub const NOT_FUZZED: &[(&ModuleDef, &str)] = &[];

/// Driver modules in their simulated-only form, by `loadrt` name.
pub const SIM_ONLY: &[&ModuleDef] = &[
    &PARPORT_SIM_ONLY,
    &SPEAKER_SIM_ONLY,
    &HM2_PCI_SIM_ONLY,
    &HM2_7I43_SIM_ONLY,
    &HM2_7I90_SIM_ONLY,
    &HM2_SPI_SIM_ONLY,
    &HM2_RPSPI_SIM_ONLY,
    &HM2_ETH_SIM_ONLY,
    &MOTENC_SIM_ONLY,
    &STG_SIM_ONLY,
    &PPMC_SIM_ONLY,
    &GPIO_SIM_ONLY,
    &PCA9685_SIM_ONLY,
    &MCP23017_SIM_ONLY,
    &ADS1115_SIM_ONLY,
    CANSERVO_SIM_ONLY,
    &LCEC_SIM_ONLY,
];

/// The modules that drive no hardware: components, motion, and the
/// launcher's planner and homing modules.
fn software_modules() -> Vec<&'static str> {
    hal_components::modules()
        .into_iter()
        .chain(hal_ladder::modules())
        .chain(motion::modules())
        .chain(motion::tp_home::modules())
        .map(|d| d.name)
        .collect()
}

/// The host's registry, safe to fuzz: software modules and [`NO_DEVICE`]
/// drivers as they are, the other drivers from [`SIM_ONLY`], without the
/// modules of [`NOT_FUZZED`]. Panics if a registry module is in none of
/// them.
pub fn fuzz_registry() -> Registry {
    let software = software_modules();
    let host = hal_host::registry();
    let mut safe = Registry::new();
    for name in host.names() {
        if NOT_FUZZED.iter().any(|(d, _)| d.name == name) {
            continue;
        }
        if software.contains(&name) || NO_DEVICE.iter().any(|d| d.name == name) {
            safe.add(&[host.find(name).expect("listed by names()")]);
        } else if let Some(def) = SIM_ONLY.iter().find(|d| d.name == name) {
            safe.add(&[def]);
        } else {
            panic!(
                "module '{name}' is neither a software module nor in hal_fuzz::registry::SIM_ONLY, \
                 NO_DEVICE or NOT_FUZZED: give it a simulated-only entry there (fuzz/README.md) \
                 before fuzzing loads it"
            );
        }
    }
    safe
}

/// `args` as they were, but for `backend`: a simulator token of `tokens`
/// stays, anything else (a real backend, a word the driver would refuse,
/// none at all) becomes `sim`. The other parameters are written back as
/// the words they were parsed from.
fn simulated_args(def: &ModuleDef, args: &ModuleArgs, tokens: BackendTokens) -> Result<ModuleArgs> {
    let backend = match args.str("backend").and_then(|t| tokens.parse(t)) {
        Some(b @ DriverBackend::Sim(_)) => b.token(),
        _ => "sim",
    };
    let join = |items: Vec<String>| (!items.is_empty()).then(|| items.join(","));
    let mut words = vec![format!("backend={backend}")];
    for decl in def.params.iter().filter(|d| d.name != "backend") {
        let value = match decl.kind {
            ParamKind::Int | ParamKind::Long => args.int(decl.name).map(|v| v.to_string()),
            ParamKind::Str => args.str(decl.name).map(str::to_string),
            ParamKind::IntArray(_) | ParamKind::LongArray(_) => join(
                args.int_array(decl.name)
                    .iter()
                    .map(i64::to_string)
                    .collect(),
            ),
            ParamKind::StrArray(_) => join(args.str_array(decl.name).to_vec()),
        };
        if let Some(v) = value {
            words.push(format!("{}={v}", decl.name));
        }
    }
    ModuleArgs::parse(def.name, def.params, &words)
}

/// Declares a simulated-only entry `$entry` for the driver module `$def`
/// whose `backend` parameter takes `$tokens`: its load runs the driver's
/// own load with [`simulated_args`].
macro_rules! backend_forced_to_sim {
    ($entry:ident, $load:ident, $def:path, $tokens:path) => {
        #[doc = concat!("`", stringify!($def), "` with its `backend` forced to a simulator.")]
        static $entry: ModuleDef = ModuleDef {
            name: $def.name,
            params: $def.params,
            help: $def.help,
            load: $load,
        };

        fn $load(host: &Host, args: &ModuleArgs) -> Result<()> {
            let def: &ModuleDef = &$def;
            (def.load)(host, &simulated_args(def, args, $tokens)?)
        }
    };
}

/// `hal_ppmc` with simulated buses only: a bus without `sim=` is refused
/// before any port I/O.
static PPMC_SIM_ONLY: ModuleDef = ModuleDef {
    name: hal_ppmc::MODULE.name,
    params: hal_ppmc::MODULE.params,
    help: hal_ppmc::MODULE.help,
    load: hal_ppmc::hal::load_sim_only,
};

backend_forced_to_sim!(
    STG_SIM_ONLY,
    stg_sim_only,
    hal_stg::MODULE,
    hal_stg::open::BACKENDS
);
backend_forced_to_sim!(
    GPIO_SIM_ONLY,
    gpio_sim_only,
    hal_gpio::MODULE,
    hal_gpio::hal::BACKENDS
);
backend_forced_to_sim!(
    PCA9685_SIM_ONLY,
    pca9685_sim_only,
    hal_i2c::hal::pca9685::MODULE,
    hal_i2c::hal::BACKENDS
);
backend_forced_to_sim!(
    MCP23017_SIM_ONLY,
    mcp23017_sim_only,
    hal_i2c::hal::mcp23017::MODULE,
    hal_i2c::hal::BACKENDS
);
backend_forced_to_sim!(
    ADS1115_SIM_ONLY,
    ads1115_sim_only,
    hal_i2c::hal::ads1115::MODULE,
    hal_i2c::hal::BACKENDS
);

backend_forced_to_sim!(
    LCEC_SIM_ONLY,
    lcec_sim_only,
    hal_ethercat::MODULE,
    hal_ethercat::hal::BACKENDS
);

/// `hal_speaker` with its `backend` checked by the driver, then always
/// the simulated speaker: no port 0x61 access.
static SPEAKER_SIM_ONLY: ModuleDef = ModuleDef {
    name: hal_parport::speaker::MODULE.name,
    params: hal_parport::speaker::MODULE.params,
    help: hal_parport::speaker::MODULE.help,
    load: speaker_sim_only,
};

fn speaker_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    use hal_parport::speaker::{backend, load_on, open, Backend};
    backend(args)?;
    load_on(host, open(host, Backend::Sim)?)
}

/// `canservo` as its crate offers it for fuzzing: every drive simulated
/// whatever `backend=` says, the parameters parsed by the driver's code.
static CANSERVO_SIM_ONLY: &ModuleDef = &hal_canservo::hal::SIM_ONLY_MODULE;

/// `hm2_pci` with a PCI bus that has no boards: `sim=` boards load, a
/// search of the bus finds nothing (the driver's own error).
static HM2_PCI_SIM_ONLY: ModuleDef = ModuleDef {
    name: hostmot2::hal::HM2_PCI_MODULE.name,
    params: hostmot2::hal::HM2_PCI_MODULE.params,
    help: hostmot2::hal::HM2_PCI_MODULE.help,
    load: hm2_pci_sim_only,
};

fn hm2_pci_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    hostmot2::hal::load_pci(host, args, &Sysfs::at(NOWHERE), &[])
}

/// `hm2_7i43` with no parallel port: `sim=` boards (behind simulated
/// ports) load, a board without one is refused before any port I/O.
static HM2_7I43_SIM_ONLY: ModuleDef = ModuleDef {
    name: hostmot2::epp::hal::HM2_7I43_MODULE.name,
    params: hostmot2::epp::hal::HM2_7I43_MODULE.params,
    help: hostmot2::epp::hal::HM2_7I43_MODULE.help,
    load: hm2_7i43_sim_only,
};

fn hm2_7i43_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    use hostmot2::epp::hal::{load_without_ports, HalHm2_7i43, SEVEN_I43};
    load_without_ports::<HalHm2_7i43>(host, args, &SEVEN_I43)
}

/// `hm2_7i90` as [`HM2_7I43_SIM_ONLY`].
static HM2_7I90_SIM_ONLY: ModuleDef = ModuleDef {
    name: hostmot2::epp::hal::HM2_7I90_MODULE.name,
    params: hostmot2::epp::hal::HM2_7I90_MODULE.params,
    help: hostmot2::epp::hal::HM2_7I90_MODULE.help,
    load: hm2_7i90_sim_only,
};

fn hm2_7i90_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    use hostmot2::epp::hal::{load_without_ports, HalHm2_7i90, SEVEN_I90};
    load_without_ports::<HalHm2_7i90>(host, args, &SEVEN_I90)
}

/// `hm2_spi` with no spidev device: `sim=` boards (behind simulated SPI
/// links) load, a board without one is refused before any device opens.
static HM2_SPI_SIM_ONLY: ModuleDef = ModuleDef {
    name: hostmot2::spi::hal::HM2_SPI_MODULE.name,
    params: hostmot2::spi::hal::HM2_SPI_MODULE.params,
    help: hostmot2::spi::hal::HM2_SPI_MODULE.help,
    load: hm2_spi_sim_only,
};

fn hm2_spi_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    use hostmot2::spi::hal::{load_without_devices, HalHm2Spi};
    load_without_devices::<HalHm2Spi>(host, args)
}

/// `hm2_rpspi` as [`HM2_SPI_SIM_ONLY`].
static HM2_RPSPI_SIM_ONLY: ModuleDef = ModuleDef {
    name: hostmot2::spi::hal::HM2_RPSPI_MODULE.name,
    params: hostmot2::spi::hal::HM2_RPSPI_MODULE.params,
    help: hostmot2::spi::hal::HM2_RPSPI_MODULE.help,
    load: hm2_rpspi_sim_only,
};

fn hm2_rpspi_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    use hostmot2::spi::hal::{load_without_devices, HalHm2Rpspi};
    load_without_devices::<HalHm2Rpspi>(host, args)
}

/// `hm2_eth` with `sim=` boards only: a board without a `sim` item is
/// refused before any socket is made, so no fuzzed `board_ip` is ever
/// sent a packet.
static HM2_ETH_SIM_ONLY: ModuleDef = ModuleDef {
    name: hostmot2::eth::hal::HM2_ETH_MODULE.name,
    params: hostmot2::eth::hal::HM2_ETH_MODULE.params,
    help: hostmot2::eth::hal::HM2_ETH_MODULE.help,
    load: hostmot2::eth::hal::load_without_network,
};

/// `hal_motenc` with a PCI bus that has no boards: `backend=sim` boards
/// load, `backend=pci` finds nothing (the driver's own error).
static MOTENC_SIM_ONLY: ModuleDef = ModuleDef {
    name: hal_motenc::MODULE.name,
    params: hal_motenc::MODULE.params,
    help: hal_motenc::MODULE.help,
    load: motenc_sim_only,
};

fn motenc_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    hal_motenc::hal::load_from(host, args, &Sysfs::at(NOWHERE), &[])
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
        dev: format!("{NOWHERE}/dev").into(),
        proc_parport: format!("{NOWHERE}/proc").into(),
    };
    hal_parport::hal::load_cfg(host, &cfg, &nowhere, Arc::new(MonotonicClock))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registry_module_is_fuzzable_and_drivers_are_simulated() {
        let r = fuzz_registry();
        let mut host = hal_host::registry().names();
        host.retain(|n| !NOT_FUZZED.iter().any(|(d, _)| d.name == *n));
        assert_eq!(r.names(), host);
        assert!(std::ptr::eq(r.find("hm2_eth").unwrap(), &HM2_ETH_SIM_ONLY));
        let pp = r.find("hal_parport").unwrap();
        assert!(std::ptr::eq(pp, &PARPORT_SIM_ONLY));
    }

    #[test]
    fn driver_modules_are_classified_as_the_readme_says() {
        let r = fuzz_registry();
        for def in SIM_ONLY {
            assert!(
                std::ptr::eq(r.find(def.name).unwrap(), *def),
                "{}",
                def.name
            );
        }
        for def in NO_DEVICE {
            assert!(
                std::ptr::eq(r.find(def.name).unwrap(), *def),
                "{}",
                def.name
            );
        }
    }

    #[test]
    fn real_backends_of_the_drivers_come_up_simulated() {
        use hal_driver::sim::{find, SimBoard};
        let host = Host::create(hal_core::HostConfig::for_tests("fuzz-drv")).unwrap();
        let inst = host.instance().name().to_string();
        let empty = || host.loaded_modules().is_empty();

        // hal_stg: `ioperm` would probe I/O ports as root.
        host.loadrt(&STG_SIM_ONLY, &["backend=ioperm", "num_chan=2", "dio=OOII"])
            .unwrap();
        assert!(find::<SimBoard<hal_stg::sim::StgModel>>(&inst, "stg").is_some());
        assert!(host.instance().pin("stg.1.counts").unwrap().is_some());
        assert!(host.instance().pin("stg.2.counts").unwrap().is_none());
        host.unloadrt("all").unwrap();

        // hal_ppmc: without sim= it would scan the EPP port at 0x378.
        let e = host
            .loadrt(&PPMC_SIM_ONLY, &["port_addr=0x378"])
            .unwrap_err();
        assert!(e.to_string().contains("simulated buses only"), "{e}");
        assert!(empty());
        host.loadrt(&PPMC_SIM_ONLY, &["sim=usc"]).unwrap();
        assert!(host
            .instance()
            .pin("ppmc.0.stepgen.03.velocity")
            .unwrap()
            .is_some());
        host.unloadrt("all").unwrap();

        // hal_gpio: `cdev` would request lines of /dev/gpiochip*.
        host.loadrt(&GPIO_SIM_ONLY, &["backend=cdev", "outputs=A"])
            .unwrap();
        assert!(find::<hal_gpio::sim::SimChips>(&inst, hal_gpio::hal::SIM_KEY).is_some());
        host.unloadrt("all").unwrap();

        // The I2C chips: `dev` would open /dev/i2c-3.
        host.loadrt(&PCA9685_SIM_ONLY, &["backend=dev", "bus=3", "address=0x41"])
            .unwrap();
        assert!(hal_i2c::hal::sim_bus(&inst, 3).is_some());
        host.unloadrt("all").unwrap();
        assert!(empty());

        // canservo: `socketcan` would open the CAN interface `nocan7`.
        host.loadrt(
            CANSERVO_SIM_ONLY,
            &["iface=nocan7", "backend=socketcan", "nodes=2"],
        )
        .unwrap();
        assert!(host.instance().pin("canservo.0.enable").unwrap().is_some());
        host.unloadrt("all").unwrap();
        assert!(empty());

        // hal_motenc and hm2_pci: the PCI bus they search has no boards.
        assert!(host.loadrt(&MOTENC_SIM_ONLY, &["backend=pci"]).is_err());
        assert!(empty());
        host.loadrt(&MOTENC_SIM_ONLY, &["backend=sim"]).unwrap();
        assert!(find::<SimBoard<hal_motenc::sim::MotencModel>>(&inst, "motenc.0").is_some());
        host.unloadrt("all").unwrap();
        host.loadrt(&hostmot2::hal::HOSTMOT2_MODULE, &[] as &[&str])
            .unwrap();
        assert!(host.loadrt(&HM2_PCI_SIM_ONLY, &[] as &[&str]).is_err());
        host.loadrt(&HM2_PCI_SIM_ONLY, &["sim=5i25"]).unwrap();
        // hm2_7i43 and hm2_7i90: no port I/O, even at the default 0x378.
        for m in [&HM2_7I43_SIM_ONLY, &HM2_7I90_SIM_ONLY] {
            let e = host.loadrt(m, &["ioaddr=0x378"]).unwrap_err();
            assert!(e.to_string().contains("real ports are not reached"), "{e}");
        }
        host.loadrt(&HM2_7I43_SIM_ONLY, &["sim=7i43"]).unwrap();
        // hm2_spi and hm2_rpspi: no spidev device is opened.
        for m in [&HM2_SPI_SIM_ONLY, &HM2_RPSPI_SIM_ONLY] {
            let e = host.loadrt(m, &[] as &[&str]).unwrap_err();
            assert!(
                e.to_string().contains("real devices are not reached"),
                "{e}"
            );
        }
        host.loadrt(&HM2_RPSPI_SIM_ONLY, &["sim=7c80"]).unwrap();
        // hm2_eth: a board_ip without sim= would be sent LBP16 requests.
        let e = host
            .loadrt(&HM2_ETH_SIM_ONLY, &["board_ip=192.0.2.1"])
            .unwrap_err();
        assert!(e.to_string().contains("the network is not reached"), "{e}");
        host.loadrt(&HM2_ETH_SIM_ONLY, &["board_ip=192.0.2.1", "sim=7i93"])
            .unwrap();
        assert!(host
            .instance()
            .pin("hm2_7i93.0.stepgen.07.position-fb")
            .unwrap()
            .is_some());
        host.unloadrt("all").unwrap();
        crate::snapshot::delete_threads(&host);
        assert!(empty());
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
