//! The HAL binding: `loadrt hal_gpio inputs=... outputs=...`.
//!
//! One realtime component `hal_gpio` with LinuxCNC's names:
//!
//! * `hal_gpio.<line>-in` and `hal_gpio.<line>-in-not` (bit OUT; `in-not`
//!   starts TRUE) for every input, canonical digital inputs
//!   ([`canonical::DigIn`]) under hal_gpio's historic names;
//! * `hal_gpio.<line>-out` (bit IN) for every output;
//! * `hal_gpio.reset_ns` (u32 RW, default 5000) when some line is in
//!   `reset=`;
//! * functions `hal_gpio.read`, `hal_gpio.write`, and `hal_gpio.reset`
//!   when some line is in `reset=` (after `write`, in the same thread).
//!
//! A failed read or write (the chip went away) trips the driver's fault
//! latch: the realtime log says so once, every output is set inactive,
//! and `write`/`reset` leave the outputs alone from then on; inputs keep
//! their last values until a read succeeds again. The safe-state hook
//! (after a fault, at unload and at exit) also sets every output
//! inactive.

use std::any::Any;
use std::sync::Arc;

use canonical::{ChannelNames, DigIn};
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{HalHost, Host, HostParam, HostPin, In, PinFactory, Result, Rw};
use hal_driver::fault::{Fault, FaultLatch, SafeState};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::{Backend, BackendTokens, Params};
use hal_driver::sim::{Clock, MonotonicClock};

use crate::cdev::CdevChips;
use crate::cfg::{self, Config, Direction};
use crate::chip::{ChipSet, LineRequest};
use crate::driver::{clamp_reset, Driver, InputBank, OutputBank};
use crate::resolve::{resolve, Group};
use crate::sim::SimChips;

/// The module's and component's name.
pub const NAME: &str = "hal_gpio";

/// `hal_gpio.reset_ns` at load.
pub const DEFAULT_RESET_NS: u32 = 5_000;

/// The backends: the character device, the simulator, and the simulator
/// with the n-th output wired to the n-th input.
pub const BACKENDS: BackendTokens = BackendTokens::new(&["cdev"], &["simloop"]);

/// The key [`hal_driver::sim::find`] finds the simulated chips under.
pub const SIM_KEY: &str = "hal_gpio";

/// hal_gpio's module parameters, the one table both hosts read.
#[macro_export]
macro_rules! hal_gpio_params {
    ($($then:tt)*) => { $($then)*! {
        inputs: StrArray($crate::cfg::MAX_NAMES) = "input lines, by the names gpioinfo prints",
        outputs: StrArray($crate::cfg::MAX_NAMES) = "output lines",
        invert: StrArray($crate::cfg::MAX_NAMES) = "outputs whose level is inverted",
        reset: StrArray($crate::cfg::MAX_NAMES) = "outputs hal_gpio.reset returns to inactive",
        opendrain: StrArray($crate::cfg::MAX_NAMES) = "outputs driven open drain",
        opensource: StrArray($crate::cfg::MAX_NAMES) = "outputs driven open source",
        biasdisable: StrArray($crate::cfg::MAX_NAMES) = "lines with their bias disabled",
        pulldown: StrArray($crate::cfg::MAX_NAMES) = "lines with the internal pull-down",
        pullup: StrArray($crate::cfg::MAX_NAMES) = "lines with the internal pull-up",
        backend: Str = "cdev (default: /dev/gpiochip*), sim, or simloop (outputs wired to inputs)",
    } };
}

/// The `hal_gpio` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalGpio;

/// The `hal_gpio` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalGpio>();

/// The lines a load asked for, found and requested, not yet exported.
pub struct OpenedLines {
    cfg: Config,
    groups: Vec<Group>,
    requests: Vec<Box<dyn LineRequest>>,
    clock: Arc<dyn Clock>,
    keep: Option<Arc<dyn Any + Send + Sync>>,
    sim: Option<Arc<SimChips>>,
}

impl DriverModule for HalGpio {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "Linux GPIO lines through the GPIO character device (or simulated)";
    const PARAMS: &'static [ParamDecl] = hal_gpio_params!(hal_driver::param_table);
    type Opened = OpenedLines;

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<OpenedLines> {
        let cfg = cfg::parse(NAME, args).map_err(|e| e.into_hal(NAME))?;
        let p = Params::new(NAME, args);
        let token = p.str_or("backend", "cdev");
        let backend = BACKENDS.parse(token).ok_or_else(|| {
            p.error(
                "backend",
                format!("'{token}' is not one of {}", BACKENDS.list()),
            )
            .into_hal(NAME)
        })?;
        let clock: Arc<dyn Clock> = Arc::new(MonotonicClock);
        match backend {
            Backend::Real(_) => open_on(cfg, &CdevChips, clock, None),
            Backend::Sim(t) => {
                let sim = Arc::new(SimChips::for_config(&cfg, t == "simloop", clock.clone()));
                let mut opened = open_on(cfg, &*sim, clock, Some(sim.clone()))?;
                opened.sim = Some(sim);
                Ok(opened)
            }
        }
    }

    fn export<H: DriverHost>(mut o: OpenedLines, ex: &mut Exporter<'_, H>) -> Result<()> {
        let comp = ex.component(NAME)?;
        let sim = o.sim.take();
        let gpio = Arc::new(export_lines(o, ex, comp)?);
        let g = gpio.clone();
        ex.funct(comp, &format!("{NAME}.read"), false, move |_| g.read())?;
        let g = gpio.clone();
        ex.funct(comp, &format!("{NAME}.write"), false, move |_| g.write())?;
        if gpio.reset_ns.is_some() {
            let g = gpio.clone();
            ex.funct(comp, &format!("{NAME}.reset"), false, move |ctx| {
                g.reset(ctx.period())
            })?;
        }
        ex.safe_state(comp, gpio);
        if let Some(sim) = &sim {
            ex.publish_sim(SIM_KEY, sim);
        }
        Ok(())
    }
}

static READ_FAILED: Fault = Fault::new(
    1,
    "reading GPIO lines failed (chip gone?); outputs set inactive and left alone until hal_gpio is reloaded",
);
static WRITE_FAILED: Fault = Fault::new(
    2,
    "writing GPIO lines failed (chip gone?); outputs set inactive and left alone until hal_gpio is reloaded",
);

/// Publishes the bits of one input request on its pins (bit k on
/// `pins[k]`): what `hal_gpio.read` does per request after its ioctl.
#[inline]
pub fn publish_inputs<H: HalHost>(bits: u64, pins: &[DigIn<H>]) {
    for (k, pin) in pins.iter().enumerate() {
        pin.update(bits & (1 << k) != 0);
    }
}

/// Gathers the `-out` pins of one output request into its bits (`pins[k]`
/// on bit k): what `hal_gpio.write` does per request before its ioctl.
#[inline]
pub fn gather_outputs<P: HostPin<bool, In>>(pins: &[P]) -> u64 {
    let mut bits = 0u64;
    for (k, pin) in pins.iter().enumerate() {
        bits |= (pin.get() as u64) << k;
    }
    bits
}

/// The loaded driver: requests, their pins (per request, in request
/// order), fault latch.
struct GpioState<H: HalHost> {
    driver: Driver,
    in_pins: Vec<Vec<DigIn<H>>>,
    out_pins: Vec<Vec<H::Pin<bool, In>>>,
    reset_ns: Option<H::Param<u32, Rw>>,
    latch: FaultLatch<H>,
    /// Keeps a simulator alive while loaded.
    _keep: Option<Arc<dyn Any + Send + Sync>>,
}

impl<H: HalHost> GpioState<H> {
    #[inline]
    fn read(&self) {
        for (bank, pins) in self.driver.inputs.iter().zip(&self.in_pins) {
            match bank.read() {
                Ok(bits) => publish_inputs(bits, pins),
                Err(_) => self.fail(&READ_FAILED),
            }
        }
    }

    #[inline]
    fn write(&self) {
        if self.latch.is_tripped() {
            return;
        }
        for (bank, pins) in self.driver.outputs.iter().zip(&self.out_pins) {
            if bank
                .write(gather_outputs(pins), &*self.driver.clock)
                .is_err()
            {
                self.fail(&WRITE_FAILED);
                return;
            }
        }
    }

    #[inline]
    fn reset(&self, period: i64) {
        let Some(param) = &self.reset_ns else { return };
        let asked = param.get();
        let used = clamp_reset(asked, period);
        if used != asked {
            param.set(used);
        }
        if self.latch.is_tripped() {
            return;
        }
        if self.driver.reset(used).is_err() {
            self.fail(&WRITE_FAILED);
        }
    }

    /// Trips the latch; the first trip sets every output inactive.
    #[inline]
    fn fail(&self, why: &'static Fault) {
        if self.latch.trip(why) {
            self.go_safe();
        }
    }
}

impl<H: HalHost> SafeState for GpioState<H> {
    /// Every output at its inactive level.
    fn go_safe(&self) {
        self.driver.go_safe();
    }
}

impl<H: HalHost> Drop for GpioState<H> {
    /// Says once how many line accesses failed while loaded, if any did.
    fn drop(&mut self) {
        let errors = self.driver.errors();
        if errors > 0 {
            eprintln!("{NAME}: {errors} line accesses failed while loaded");
        }
    }
}

/// Finds every line of `cfg` on the chips of `chips` and requests them
/// all before anything is exported; a failure drops (and so releases)
/// the requests made so far.
fn open_on(
    cfg: Config,
    chips: &dyn ChipSet,
    clock: Arc<dyn Clock>,
    keep: Option<Arc<dyn Any + Send + Sync>>,
) -> Result<OpenedLines> {
    let found = chips.chips().map_err(|e| e.into_hal())?;
    let groups = resolve(&cfg, &found).map_err(|e| e.into_hal())?;
    let mut requests = Vec::with_capacity(groups.len());
    for g in &groups {
        requests.push(
            chips
                .request(&found[g.chip], &g.lines)
                .map_err(|e| e.into_hal())?,
        );
    }
    Ok(OpenedLines {
        cfg,
        groups,
        requests,
        clock,
        keep,
        sim: None,
    })
}

/// Loads the driver for `cfg` into our host on the chips of `chips`,
/// timing writes and reset deadlines with `clock`; `keep` is held while
/// the driver is loaded (a simulator). `loadrt` does this with the
/// character device or a simulator; tests may pass chips and clocks of
/// their own.
pub fn load_on(
    host: &Host,
    cfg: &Config,
    chips: &dyn ChipSet,
    clock: Arc<dyn Clock>,
    keep: Option<Arc<dyn Any + Send + Sync>>,
) -> Result<()> {
    module::load_opened::<HalGpio>(host, open_on(cfg.clone(), chips, clock, keep)?)
}

/// The pins of every requested line, and the driver over the requests.
fn export_lines<H: DriverHost>(
    o: OpenedLines,
    ex: &Exporter<'_, H>,
    comp: hal_driver::CompId,
) -> Result<GpioState<H>> {
    let OpenedLines {
        cfg,
        groups,
        requests,
        clock,
        keep,
        ..
    } = o;
    let c = ex.pins(comp);
    let names: Vec<String> = cfg.lines.iter().map(|l| l.name.clone()).collect();
    let hal_names =
        ChannelNames::custom(move |line, item| format!("{NAME}.{}-{item}", names[line]));
    let mut driver = Driver {
        inputs: Vec::new(),
        outputs: Vec::new(),
        clock,
    };
    let mut in_pins = Vec::new();
    let mut out_pins = Vec::new();
    for (g, req) in groups.iter().zip(requests) {
        match g.direction {
            Direction::Input => {
                in_pins.push(
                    g.specs
                        .iter()
                        .map(|&s| DigIn::export(c, &hal_names, s))
                        .collect::<Result<Vec<_>>>()?,
                );
                driver.inputs.push(InputBank::new(req, g.lines.len()));
            }
            Direction::Output => {
                out_pins.push(
                    g.specs
                        .iter()
                        .map(|&s| c.pin(&hal_names.item(s, "out")))
                        .collect::<Result<Vec<_>>>()?,
                );
                let reset_mask = g
                    .specs
                    .iter()
                    .enumerate()
                    .filter(|(_, &s)| cfg.lines[s].reset)
                    .fold(0u64, |m, (k, _)| m | 1 << k);
                driver
                    .outputs
                    .push(OutputBank::new(req, g.lines.len(), reset_mask));
            }
        }
    }
    let reset_ns = if cfg.has_reset() {
        Some(c.param(&format!("{NAME}.reset_ns"), DEFAULT_RESET_NS)?)
    } else {
        None
    };
    Ok(GpioState {
        driver,
        in_pins,
        out_pins,
        reset_ns,
        latch: FaultLatch::named(NAME).with_log(ex.log()),
        _keep: keep,
    })
}
