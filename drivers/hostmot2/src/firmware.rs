//! Reading a board's firmware description, HAL-free: identification,
//! IDROM, pin and module descriptors, which modules and instances to use,
//! and which pin goes where (hardware.md 5.7 steps 5 to 11, in LinuxCNC's
//! order). This is what the fuzz target feeds random register images to.

use crate::config::{self, Config};
use crate::error::{Hm2Error, Result};
use crate::idrom::{self, IdromHeader};
use crate::llio::Llio;
use crate::log::MessageLog;
use crate::md::{self, ModuleDescriptor};
use crate::modules::sserial::discovery::{self, SserialFirmware};
use crate::pins::{self, InstancesUsed, IoPin};
use crate::regs::gtag;
use crate::transport::Transport;

/// hostmot2's debugging switches (its module parameters).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Debug {
    /// Log the IDROM header.
    pub idrom: bool,
    /// Log every module descriptor.
    pub module_descriptors: bool,
    /// Log every pin descriptor.
    pub pin_descriptors: bool,
    /// Log what each module uses.
    pub modules: bool,
    /// Name Smart Serial cards by unit number (`use_serial_numbers`).
    pub use_serial_numbers: bool,
    /// Set every Smart Serial channel to this baud rate (`sserial_baudrate`).
    pub sserial_baudrate: Option<u32>,
}

/// A module the driver will use: its descriptor and instances in use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModuleUse {
    /// The descriptor.
    pub md: ModuleDescriptor,
    /// Instances in use (at least 1).
    pub instances: u32,
}

/// Everything the driver learned from a board before touching HAL.
#[derive(Debug, Clone, PartialEq)]
pub struct Firmware {
    /// The IDROM header.
    pub idrom: IdromHeader,
    /// Every module descriptor, in order.
    pub mds: Vec<ModuleDescriptor>,
    /// Every I/O pin with its owner.
    pub pins: Vec<IoPin>,
    /// The IOPort module (one instance per connector).
    pub ioport: ModuleUse,
    /// The watchdog, if the firmware has one.
    pub watchdog: Option<ModuleUse>,
    /// Encoders in use.
    pub encoder: Option<ModuleUse>,
    /// Step generators in use.
    pub stepgen: Option<ModuleUse>,
    /// PWM generators in use.
    pub pwmgen: Option<ModuleUse>,
    /// LEDs in use.
    pub led: Option<ModuleUse>,
    /// The Smart Serial ports in use and the cards found on them.
    pub sserial: Option<SserialFirmware>,
    /// The PktUARTs (for hm2_modbus).
    pub pktuart: crate::pktuart::PktUartFirmware,
}

/// Reads and checks everything, logging what LinuxCNC logs. On an error
/// the log holds the messages that came before it.
pub fn load(
    llio: &Llio,
    config: &Config,
    debug: Debug,
    t: &mut dyn Transport,
    log: &mut MessageLog,
) -> Result<Firmware> {
    llio.validate()?;
    idrom::check_identity(t)?;
    let idrom = idrom::read_header(t, llio)?;
    if debug.idrom {
        for l in idrom::describe(&idrom) {
            log.dbg(l);
        }
    }
    let descs = pins::read_all(t, &idrom, llio.connectors.len() as u32)?;
    if debug.pin_descriptors {
        for (i, d) in descs.iter().enumerate() {
            log.dbg(format!(
                "pin {i}: Primary Tag 0x{:02X}, Secondary Tag 0x{:02X}, Secondary Unit 0x{:02X}, Secondary Pin 0x{:02X}",
                d.primary_tag, d.sec_tag, d.sec_unit, d.sec_pin
            ));
        }
    }
    let mds = md::read_all(t, &idrom)?;
    if debug.module_descriptors {
        for m in &mds {
            for l in m.describe() {
                log.dbg(l);
            }
        }
    }
    let plan = plan_modules(&mds, &idrom, llio, config, log)?;
    let ioport_instances = plan.ioport.map_or(0, |m| m.instances);
    let sserial = match (plan.sserial, plan.ioport) {
        (Some(s), Some(io)) => Some(discovery::discover(
            t,
            &discovery::Setup {
                md: s.md,
                ports: s.instances,
                ioport: io.md,
                port_width: idrom.port_width,
                pins: &descs,
                config,
                baudrate: debug.sserial_baudrate,
            },
            log,
        )?),
        _ => None,
    };
    let mut pktuart = crate::pktuart::PktUartFirmware::discover(&mds, &llio.name)?;
    let n = crate::config::instances(
        "num_pktuarts",
        config.num_pktuarts,
        pktuart.instances.len() as u32,
    )?;
    pktuart.instances.truncate(n as usize);
    for p in &pktuart.instances {
        log.info(format!("created PktUART Interface function {}.", p.name));
    }
    let used = InstancesUsed {
        pktuarts: pktuart.instances.len() as u32,
        encoders: plan.encoder.map_or(0, |m| m.instances),
        stepgens: plan.stepgen.map_or(0, |m| m.instances),
        pwmgens: plan.pwmgen.map_or(0, |m| m.instances),
        sserial: sserial.as_ref().map_or([0; 4], |s| s.masks()),
    };
    let pins = pins::allocate(
        &descs,
        idrom.port_width,
        ioport_instances,
        &used,
        config.stepgen_width as u32,
        log,
    );
    let Some(ioport) = plan.ioport else {
        return Err(Hm2Error::NoIoPort {
            pins: idrom.io_width,
        });
    };
    for l in pins::usage_lines(&pins, &llio.connectors, idrom.port_width) {
        log.info(l);
    }
    if debug.modules {
        for m in [
            Some(ioport),
            plan.watchdog,
            plan.encoder,
            plan.stepgen,
            plan.pwmgen,
            plan.led,
        ]
        .into_iter()
        .flatten()
        {
            log.dbg(format!(
                "{}: using {} of {} instances (version {}, base 0x{:04X}, clock {} Hz)",
                m.md.name(),
                m.instances,
                m.md.instances,
                m.md.version,
                m.md.base_address,
                m.md.clock_hz
            ));
        }
    }
    Ok(Firmware {
        idrom,
        mds,
        pins,
        ioport,
        watchdog: plan.watchdog,
        encoder: plan.encoder,
        stepgen: plan.stepgen,
        pwmgen: plan.pwmgen,
        led: plan.led,
        sserial,
        pktuart,
    })
}

#[derive(Default)]
struct Plan {
    ioport: Option<ModuleUse>,
    watchdog: Option<ModuleUse>,
    encoder: Option<ModuleUse>,
    stepgen: Option<ModuleUse>,
    pwmgen: Option<ModuleUse>,
    led: Option<ModuleUse>,
    sserial: Option<ModuleUse>,
}

/// Remembers which modules were seen, to refuse duplicates even when a
/// module ends up with no instance in use.
#[derive(Default)]
struct Seen(Vec<u8>);

impl Seen {
    fn first(&mut self, tag: u8) -> Result<()> {
        if self.0.contains(&tag) {
            return Err(Hm2Error::DuplicateMd {
                name: gtag::name(tag).unwrap_or("unknown"),
            });
        }
        self.0.push(tag);
        Ok(())
    }
}

fn used(md: &ModuleDescriptor, instances: u32) -> Option<ModuleUse> {
    (instances > 0).then_some(ModuleUse { md: *md, instances })
}

/// Parses the descriptors as LinuxCNC does: IOPort first, then the rest
/// in descriptor order.
fn plan_modules(
    mds: &[ModuleDescriptor],
    idrom: &IdromHeader,
    llio: &Llio,
    config: &Config,
    log: &mut MessageLog,
) -> Result<Plan> {
    let mut plan = Plan::default();
    let mut seen = Seen::default();
    for m in mds.iter().filter(|m| m.gtag == gtag::IOPORT) {
        md::check_ioport(m)?;
        md::check_window(m)?;
        seen.first(gtag::IOPORT)?;
        if idrom.io_ports != m.instances as u32 {
            return Err(Hm2Error::IoPortInstances {
                idrom: idrom.io_ports,
                md: m.instances,
            });
        }
        plan.ioport = used(m, m.instances as u32);
    }
    for m in mds.iter().filter(|m| m.gtag != gtag::IOPORT) {
        match m.gtag {
            gtag::WATCHDOG => {
                md::check_watchdog(m)?;
                md::check_window(m)?;
                seen.first(m.gtag)?;
                if m.instances != 1 {
                    log.warn(format!(
                        "Watchdog MD has {} instances, expected 1; using the first",
                        m.instances
                    ));
                }
                plan.watchdog = used(m, m.instances.min(1) as u32);
            }
            gtag::ENCODER => {
                if let Some(w) = md::check_encoder(m)? {
                    log.warn(w);
                }
                md::check_window(m)?;
                seen.first(m.gtag)?;
                let n = config::instances("num_encoders", config.num_encoders, m.instances as u32)?;
                plan.encoder = used(m, n);
            }
            gtag::STEPGEN => {
                if let Some(w) = md::check_stepgen(m)? {
                    log.warn(w);
                }
                md::check_window(m)?;
                seen.first(m.gtag)?;
                let n = config::instances("num_stepgens", config.num_stepgens, m.instances as u32)?;
                plan.stepgen = used(m, n);
            }
            gtag::PWMGEN => {
                md::check_pwmgen(m)?;
                md::check_window(m)?;
                seen.first(m.gtag)?;
                let n = config::instances("num_pwmgens", config.num_pwmgens, m.instances as u32)?;
                plan.pwmgen = used(m, n);
            }
            gtag::LED => {
                md::check_led(m)?;
                md::check_window(m)?;
                seen.first(m.gtag)?;
                let have = llio.num_leds;
                let n = match config.num_leds {
                    -1 => have,
                    n if n as u32 > have => {
                        log.warn(format!(
                            "There are only {have} LEDs on this board, not {n}; using {have}"
                        ));
                        have
                    }
                    n => n as u32,
                };
                plan.led = used(m, n);
            }
            gtag::SSERIAL => {
                md::check_sserial(m)?;
                seen.first(m.gtag)?;
                let n = config::instances("num_sserials", config.num_sserials, m.instances as u32)?;
                plan.sserial = used(m, n);
            }
            // Paired, checked and counted by PktUartFirmware::discover.
            gtag::PKTUART_TX | gtag::PKTUART_RX => {}
            tag => {
                if gtag::name(tag).is_none() {
                    log.warn(format!("Firmware contains unknown function (gtag-{tag})"));
                }
                log.warn(format!(
                    "MD {}: {}x {} v{}: ignored",
                    m.index,
                    m.instances,
                    m.name(),
                    m.version
                ));
            }
        }
    }
    Ok(plan)
}
