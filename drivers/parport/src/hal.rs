//! The HAL binding: `loadrt hal_parport cfg="..."`.
//!
//! One realtime component `hal_parport` with, per port p (hardware.md 2.4):
//!
//! * `parport.p.pin-NN-in` / `-in-not` (bit OUT) for every input pin;
//! * `parport.p.pin-NN-out` (bit IN), params `-out-invert` and
//!   `-out-reset` (bit RW) for every output pin;
//! * params `parport.p.reset-time`, `.debug1`, `.debug2` (u32 RW) when the
//!   data pins are outputs (`debug1`/`debug2` are unused, as in LinuxCNC);
//! * functions `parport.p.read`, `.write`, `.reset`;
//!
//! and the functions `parport.read-all` and `parport.write-all`. No
//! function uses floating point. Output pins are canonical digital
//! outputs ([`canonical::DigOut`]) under parport's historic names.
//!
//! The safe-state hook (after a fault, at unload and at exit) drives every
//! output pin to its inactive level, the physical level of its
//! `-out-invert`.

use std::sync::Arc;

use canonical::{ChannelNames, DigOut};
use hal_core::module::ModuleArgs;
use hal_core::{
    HalError, HalHost, Host, HostParam, HostPin, Out, ParamDecl, PinFactory, Result, Rw,
};
use hal_driver::fault::SafeState;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;
use hal_driver::DriverError;

use crate::cfg::{self, PortSpec, DEFAULT_CFG};
use crate::clock::{Clock, MonotonicClock};
use crate::driver::{Outputs, PortDriver};
use crate::port::PortError;
use crate::regs;
use crate::select::{self, SysPaths};

const NAME: &str = "hal_parport";

/// hal_parport's module parameters: the one table both hosts read (our
/// `loadrt` through [`HalParport::PARAMS`], LinuxCNC's `rtapi_app`
/// through the `rtapi_info_*` symbols of `hal_parport.so`).
#[macro_export]
macro_rules! hal_parport_params {
    ($($then:tt)*) => { $($then)*! {
        cfg: Str = "ports: \"<addr> [in|out|epp|x] [ppdev|raw|sim|simloop] ...\" (addr hex; <0x10 = parport number)",
    } };
}

/// The `hal_parport` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalParport;

/// The `hal_parport` module of our host.
pub static MODULE: hal_core::ModuleDef = module::module_def::<HalParport>();

/// The ports `cfg` asked for, opened and claimed, not yet exported.
pub struct OpenedPorts {
    specs: Vec<PortSpec>,
    ports: Vec<select::Opened>,
    clock: Arc<dyn Clock>,
}

impl DriverModule for HalParport {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "PC parallel port driver (ppdev, raw port I/O, or simulated)";
    const PARAMS: &'static [ParamDecl] = hal_parport_params!(hal_driver::param_table);
    type Opened = OpenedPorts;

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<OpenedPorts> {
        open_cfg(
            Params::new(NAME, args).str_or("cfg", DEFAULT_CFG),
            &SysPaths::system(),
            Arc::new(MonotonicClock),
        )
    }

    fn export<H: DriverHost>(o: OpenedPorts, ex: &mut Exporter<'_, H>) -> Result<()> {
        let comp = ex.component(NAME)?;
        let mut ports = Vec::with_capacity(o.ports.len());
        let mut sims = Vec::new();
        for (i, (spec, opened)) in o.specs.iter().zip(o.ports).enumerate() {
            let drv = PortDriver::new(spec.mode, opened.io, o.clock.clone());
            drv.init().map_err(|e| port_error(i, spec, e))?;
            ports.push(Arc::new(HalPort::export(ex.pins(comp), i, drv)?));
            if let Some(s) = opened.sim {
                sims.push((i, s));
            }
        }
        for (i, port) in ports.iter().enumerate() {
            let p = port.clone();
            ex.funct(comp, &format!("parport.{i}.read"), false, move |_| p.read())?;
            let p = port.clone();
            ex.funct(comp, &format!("parport.{i}.write"), false, move |_| {
                p.write()
            })?;
            let p = port.clone();
            ex.funct(comp, &format!("parport.{i}.reset"), false, move |ctx| {
                p.reset(ctx.period())
            })?;
        }
        let all = ports.clone();
        ex.funct(comp, "parport.read-all", false, move |_| {
            for p in &all {
                p.read();
            }
        })?;
        let all = ports.clone();
        ex.funct(comp, "parport.write-all", false, move |_| {
            for p in &all {
                p.write();
            }
        })?;
        ex.safe_state(comp, ports);
        for (i, s) in &sims {
            ex.publish_sim(&crate::sim::key(*i), s);
        }
        Ok(())
    }
}

/// LinuxCNC's names for one port's pins and their params:
/// `parport.<p>.pin-<NN>-<item>`, the channel being the DB-25 pin number.
/// The canonical digital output's `invert` is parport's `out-invert`.
fn port_names(p: usize) -> ChannelNames {
    ChannelNames::custom(move |pin, item| {
        let item = if item == "invert" { "out-invert" } else { item };
        format!("parport.{p}.pin-{pin:02}-{item}")
    })
}

/// An input pin pair, `-in` and `-in-not`.
///
/// Not [`canonical::DigIn`]: that one starts `in-not` TRUE, whereas
/// LinuxCNC's hal_parport leaves both pins FALSE until the first `read`,
/// which `halcmd show pin` after `loadrt` makes visible.
struct InPin<H: HalHost> {
    on: H::Pin<bool, Out>,
    off: H::Pin<bool, Out>,
}

impl<H: HalHost> InPin<H> {
    fn new(c: &impl PinFactory<H>, names: &ChannelNames, pin: u8) -> Result<Self> {
        Ok(InPin {
            on: c.pin(&names.item(pin as usize, "in"))?,
            off: c.pin(&names.item(pin as usize, "in-not"))?,
        })
    }

    #[inline]
    fn set(&self, level: bool) {
        self.on.set(level);
        self.off.set(!level);
    }
}

/// An output pin: the canonical digital output plus parport's reset flag.
struct OutPin<H: HalHost> {
    dig: DigOut<H>,
    reset: H::Param<bool, Rw>,
}

impl<H: HalHost> OutPin<H> {
    fn new(c: &impl PinFactory<H>, names: &ChannelNames, pin: u8) -> Result<Self> {
        Ok(OutPin {
            dig: DigOut::export(c, names, pin as usize)?,
            reset: c.param(&names.item(pin as usize, "out-reset"), false)?,
        })
    }
}

/// Gathers `out XOR invert`, the reset mask and the reset values of a
/// group of output pins, pin i on bit i.
#[inline]
fn gather<H: HalHost>(pins: &[OutPin<H>]) -> (u8, u8, u8) {
    let (mut v, mut mask, mut val) = (0u8, 0u8, 0u8);
    for (b, p) in pins.iter().enumerate() {
        if p.dig.level() {
            v |= 1 << b;
        }
        if p.reset.get() {
            mask |= 1 << b;
            if p.dig.safe_level() {
                val |= 1 << b;
            }
        }
    }
    (v, mask, val)
}

/// Invert bits of a group of output pins, pin i on bit i.
fn inverts<H: HalHost>(pins: &[OutPin<H>]) -> u8 {
    pins.iter().enumerate().fold(
        0,
        |v, (b, p)| if p.dig.safe_level() { v | 1 << b } else { v },
    )
}

/// One port's pins and driver.
struct HalPort<H: HalHost> {
    drv: PortDriver,
    status_in: Vec<InPin<H>>,
    data_in: Vec<InPin<H>>,
    control_in: Vec<InPin<H>>,
    data_out: Vec<OutPin<H>>,
    control_out: Vec<OutPin<H>>,
    reset_time: Option<H::Param<u32, Rw>>,
}

impl<H: HalHost> HalPort<H> {
    fn export(c: &impl PinFactory<H>, p: usize, drv: PortDriver) -> Result<Self> {
        let mode = drv.mode();
        let names = port_names(p);
        let inputs = |pins: &[u8]| -> Result<Vec<InPin<H>>> {
            pins.iter().map(|&n| InPin::new(c, &names, n)).collect()
        };
        let outputs = |pins: &[u8]| -> Result<Vec<OutPin<H>>> {
            pins.iter().map(|&n| OutPin::new(c, &names, n)).collect()
        };
        // LinuxCNC's export order: status, data, timing params, control.
        let status_in = inputs(&regs::STATUS_PINS)?;
        let (data_in, data_out, reset_time) = if mode.data_out() {
            let out = outputs(&regs::DATA_PINS)?;
            let rt = c.param(&format!("parport.{p}.reset-time"), 0u32)?;
            // Exported for LinuxCNC's configs, never read (as there).
            let _: H::Param<u32, Rw> = c.param(&format!("parport.{p}.debug1"), 0u32)?;
            let _: H::Param<u32, Rw> = c.param(&format!("parport.{p}.debug2"), 0u32)?;
            (Vec::new(), out, Some(rt))
        } else {
            (inputs(&regs::DATA_PINS)?, Vec::new(), None)
        };
        let (control_in, control_out) = if mode.control_in() {
            (inputs(&regs::CONTROL_PINS)?, Vec::new())
        } else {
            (Vec::new(), outputs(&regs::CONTROL_PINS)?)
        };
        Ok(HalPort {
            drv,
            status_in,
            data_in,
            control_in,
            data_out,
            control_out,
            reset_time,
        })
    }

    #[inline]
    fn read(&self) {
        let i = self.drv.read();
        for (b, pin) in self.status_in.iter().enumerate() {
            pin.set(i.status & (1 << (b as u32 + regs::STATUS_FIRST_BIT)) != 0);
        }
        if let Some(d) = i.data {
            for (b, pin) in self.data_in.iter().enumerate() {
                pin.set(d & (1 << b) != 0);
            }
        }
        if let Some(c) = i.control {
            for (b, pin) in self.control_in.iter().enumerate() {
                pin.set(c & (1 << b) != 0);
            }
        }
    }

    #[inline]
    fn write(&self) {
        let (data, data_reset_mask, data_reset_val) = gather(&self.data_out);
        let (control, control_reset_mask, control_reset_val) = gather(&self.control_out);
        self.drv.write(&Outputs {
            data,
            data_reset_mask,
            data_reset_val,
            control,
            control_reset_mask,
            control_reset_val,
        });
    }

    #[inline]
    fn reset(&self, period: i64) {
        // In `in` mode the parameter does not exist; its value is 0.
        let rt = self.reset_time.as_ref().map_or(0, |p| p.get());
        let used = self.drv.reset(rt, period);
        if used != rt {
            if let Some(p) = &self.reset_time {
                p.set(used);
            }
        }
    }
}

impl<H: HalHost> SafeState for HalPort<H> {
    /// Every output at its inactive level, the physical level of its
    /// `-out-invert`.
    fn go_safe(&self) {
        self.drv
            .safe_state(inverts(&self.data_out), inverts(&self.control_out));
    }
}

fn port_error(index: usize, spec: &PortSpec, e: PortError) -> HalError {
    HalError::module_failed(
        NAME,
        PortError::Port {
            index,
            spec: spec.to_string(),
            source: Box::new(e),
        },
    )
}

/// Parses `cfg`, chooses and opens every port it names (finding Linux's
/// ports under `paths`, timing write/reset with `clock`), claiming them
/// all before anything is exported.
fn open_cfg(cfg: &str, paths: &SysPaths, clock: Arc<dyn Clock>) -> Result<OpenedPorts> {
    let specs = cfg::parse(cfg).map_err(|e| {
        DriverError::BadParam {
            module: NAME.into(),
            param: "cfg".into(),
            reason: e.to_string(),
        }
        .into_hal(NAME)
    })?;
    // Choose every backend first: two entries for one port must be
    // refused before anything is claimed, since a second PPCLAIM of a
    // port blocks forever.
    let choices =
        select::choose_all(&specs, paths).map_err(|(i, e)| port_error(i, &specs[i], e))?;
    // Open and claim every port before exporting anything; a failure
    // drops (and so releases) the ports opened so far.
    let mut ports = Vec::with_capacity(specs.len());
    for (i, (spec, choice)) in specs.iter().zip(&choices).enumerate() {
        ports.push(
            select::open(choice, spec.mode, clock.clone()).map_err(|e| port_error(i, spec, e))?,
        );
    }
    Ok(OpenedPorts {
        specs,
        ports,
        clock,
    })
}

/// Loads the driver for `cfg` into our host, finding Linux's ports under
/// `paths` and timing write/reset with `clock`. `loadrt` does this with
/// the real system paths and CLOCK_MONOTONIC; tests may pass their own.
pub fn load_cfg(host: &Host, cfg: &str, paths: &SysPaths, clock: Arc<dyn Clock>) -> Result<()> {
    module::load_opened::<HalParport>(host, open_cfg(cfg, paths, clock)?)
}

impl std::fmt::Debug for OpenedPorts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OpenedPorts")
            .field("ports", &self.ports)
            .finish()
    }
}
