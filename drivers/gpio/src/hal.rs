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
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, In, Param, Pin, Result, Rw};
use hal_driver::fault::{self, Fault, FaultLatch, SafeState};
use hal_driver::params::{Backend, BackendTokens, Params};
use hal_driver::sim::{Clock, MonotonicClock};

use crate::cdev::CdevChips;
use crate::cfg::{self, Config, Direction, MAX_NAMES};
use crate::chip::ChipSet;
use crate::driver::{clamp_reset, Driver, InputBank, OutputBank};
use crate::resolve::resolve;
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

const fn list(name: &'static str, help: &'static str) -> ParamDecl {
    ParamDecl {
        name,
        kind: ParamKind::StrArray(MAX_NAMES),
        help,
    }
}

const PARAMS: &[ParamDecl] = &[
    list("inputs", "input lines, by the names gpioinfo prints"),
    list("outputs", "output lines"),
    list("invert", "outputs whose level is inverted"),
    list("reset", "outputs hal_gpio.reset returns to inactive"),
    list("opendrain", "outputs driven open drain"),
    list("opensource", "outputs driven open source"),
    list("biasdisable", "lines with their bias disabled"),
    list("pulldown", "lines with the internal pull-down"),
    list("pullup", "lines with the internal pull-up"),
    ParamDecl {
        name: "backend",
        kind: ParamKind::Str,
        help: "cdev (default: /dev/gpiochip*), sim, or simloop (outputs wired to inputs)",
    },
];

/// The `hal_gpio` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: PARAMS,
    help: "Linux GPIO lines through the GPIO character device (or simulated)",
    load,
};

static READ_FAILED: Fault = Fault::new(
    1,
    "reading GPIO lines failed (chip gone?); outputs set inactive and left alone until hal_gpio is reloaded",
);
static WRITE_FAILED: Fault = Fault::new(
    2,
    "writing GPIO lines failed (chip gone?); outputs set inactive and left alone until hal_gpio is reloaded",
);

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
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
        Backend::Real(_) => load_on(host, &cfg, &CdevChips, clock, None),
        Backend::Sim(t) => {
            let sim = Arc::new(SimChips::for_config(&cfg, t == "simloop", clock.clone()));
            load_on(host, &cfg, &*sim, clock, Some(sim.clone()))?;
            hal_driver::sim::publish(host.instance().name(), SIM_KEY, &sim);
            Ok(())
        }
    }
}

/// Publishes the bits of one input request on its pins (bit k on
/// `pins[k]`): what `hal_gpio.read` does per request after its ioctl.
#[inline]
pub fn publish_inputs(bits: u64, pins: &[DigIn]) {
    for (k, pin) in pins.iter().enumerate() {
        pin.update(bits & (1 << k) != 0);
    }
}

/// Gathers the `-out` pins of one output request into its bits (`pins[k]`
/// on bit k): what `hal_gpio.write` does per request before its ioctl.
#[inline]
pub fn gather_outputs(pins: &[Pin<bool, In>]) -> u64 {
    let mut bits = 0u64;
    for (k, pin) in pins.iter().enumerate() {
        bits |= (pin.get() as u64) << k;
    }
    bits
}

/// The loaded driver: requests, their pins (per request, in request
/// order), fault latch.
struct HalGpio {
    driver: Driver,
    in_pins: Vec<Vec<DigIn>>,
    out_pins: Vec<Vec<Pin<bool, In>>>,
    reset_ns: Option<Param<u32, Rw>>,
    latch: FaultLatch,
    /// Keeps a simulator alive while loaded.
    _keep: Option<Arc<dyn Any + Send + Sync>>,
}

impl HalGpio {
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

impl SafeState for HalGpio {
    /// Every output at its inactive level.
    fn go_safe(&self) {
        self.driver.go_safe();
    }
}

impl Drop for HalGpio {
    /// Says once how many line accesses failed while loaded, if any did.
    fn drop(&mut self) {
        let errors = self.driver.errors();
        if errors > 0 {
            eprintln!("{NAME}: {errors} line accesses failed while loaded");
        }
    }
}

/// Loads the driver for `cfg` on the chips of `chips`, timing writes and
/// reset deadlines with `clock`; `keep` is held while the driver is
/// loaded (a simulator). `loadrt` calls this with the character device
/// or a simulator; tests may pass chips and clocks of their own.
pub fn load_on(
    host: &Host,
    cfg: &Config,
    chips: &dyn ChipSet,
    clock: Arc<dyn Clock>,
    keep: Option<Arc<dyn Any + Send + Sync>>,
) -> Result<()> {
    // Find every line and request them all before exporting anything; a
    // failure drops (and so releases) the requests made so far.
    let found = chips.chips().map_err(|e| e.into_hal())?;
    let groups = resolve(cfg, &found).map_err(|e| e.into_hal())?;
    let mut requests = Vec::with_capacity(groups.len());
    for g in &groups {
        requests.push(
            chips
                .request(&found[g.chip], &g.lines)
                .map_err(|e| e.into_hal())?,
        );
    }
    let mut b = host.new_rt_component(NAME)?;
    let c = b.component();
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
    let gpio = HalGpio {
        driver,
        in_pins,
        out_pins,
        reset_ns,
        latch: FaultLatch::new(NAME).with_log(host.rt_log()),
        _keep: keep,
    };
    let gpio = Arc::new(gpio);
    let g = gpio.clone();
    b.funct(&format!("{NAME}.read"), false, move |_| g.read())?;
    let g = gpio.clone();
    b.funct(&format!("{NAME}.write"), false, move |_| g.write())?;
    if cfg.has_reset() {
        let g = gpio.clone();
        b.funct(&format!("{NAME}.reset"), false, move |ctx| {
            g.reset(ctx.period())
        })?;
    }
    fault::install(&mut b, gpio);
    b.ready()
}
