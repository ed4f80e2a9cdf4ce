//! The HAL bindings: one `loadrt` module per chip type ([`pca9685`],
//! [`mcp23017`], [`ads1115`]), each taking up to [`MAX_CHIPS`] chips.
//!
//! Module parameters every module has, one item per chip:
//!
//! | parameter | meaning | default |
//! |---|---|---|
//! | `address` | the chips' 7-bit addresses; their number is the number of chips | the chip's first strap address |
//! | `bus` | the I2C bus of each chip, `/dev/i2c-<bus>` | 1 (a Raspberry Pi's header bus) |
//! | `backend` | `dev` (i2c-dev) or `sim` (register models on a simulated bus per bus number) | `dev` |
//!
//! Per chip `N` of module `M` (names `M.N.`): the canonical interface
//! pins, and
//!
//! | pin | type | dir | meaning |
//! |---|---|---|---|
//! | `M.N.fault` | bit | out | the chip failed (no answer, bus error, reset); latched |
//! | `M.N.errors` | u32 | out | failed transfers and set-ups so far |
//! | `M.N.fault-reset` | bit | in | a rising edge clears the latch once the chip works |
//!
//! and the function `M.N.read` (status and inputs), plus `M.N.write`
//! (outputs) for chips with outputs. Chips on one bus share one helper
//! thread ([`crate::worker`]), whichever module loaded them; two chips
//! at one address of one bus are refused.
//!
//! Everything is opened, reserved and set up before anything is
//! exported: a chip that does not answer at `loadrt` fails the load,
//! naming chip, bus and address, and nothing stays loaded.

pub mod ads1115;
pub mod mcp23017;
pub mod pca9685;

use std::ops::RangeInclusive;
use std::sync::Arc;

use hal_core::module::ModuleArgs;
use hal_core::{HalHost, HostPin, In, Ours, Out, PinFactory, Result};
use hal_driver::fault::SafeState;
use hal_driver::params::{Backend, BackendTokens, Params};
use hal_driver::sim::SimClock;
use hal_driver::{CompId, DriverError, DriverHost, Exporter, LogSink};

use crate::bus::I2cBus;
use crate::chips::Chip;
use crate::error::I2cError;
use crate::handoff::{Status, StatusPort};
use crate::linux::LinuxBus;
use crate::sim::{ChipModel, SimBus};
use crate::worker::{self, Attachment, BusWorker, ChipRunner, ChipSafe, RealtimeEnds, Reservation};

/// The most chips one module takes.
pub const MAX_CHIPS: usize = 8;

/// The backends: i2c-dev and the simulator.
pub const BACKENDS: BackendTokens = BackendTokens::new(&["dev"], &[]);

/// The bus number when none is given.
pub const DEFAULT_BUS: i64 = 1;

/// A chip module's parameter table: the parameters every module has
/// (`address` and `bus` first, `backend` last) around the module's own,
/// handed to `$then` as the module's table macro does.
#[doc(hidden)]
#[macro_export]
macro_rules! __i2c_params {
    ([$($then:tt)*] $($own:tt)*) => { $($then)*! {
        address: IntArray($crate::hal::MAX_CHIPS) =
            "7-bit address of each chip (its number is the number of chips)",
        bus: IntArray($crate::hal::MAX_CHIPS) = "I2C bus of each chip: /dev/i2c-<bus> (default 1)",
        $($own)*
        backend: Str = "dev (default: /dev/i2c-N) or sim (simulated chips)",
    } };
}

/// Where a chip is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChipAt {
    /// Its bus number.
    pub bus: u32,
    /// Its address.
    pub addr: u8,
}

/// The common parameters: backend and where each chip is; at least one
/// chip (at `default_addr` when no address is given).
pub fn read_common(
    p: &Params<'_>,
    args: &ModuleArgs,
    addresses: RangeInclusive<u8>,
    default_addr: u8,
) -> std::result::Result<(Backend, Vec<ChipAt>), DriverError> {
    let token = p.str_or("backend", "dev");
    let backend = BACKENDS.parse(token).ok_or_else(|| {
        p.error(
            "backend",
            format!("'{token}' is not one of {}", BACKENDS.list()),
        )
    })?;
    let given = args.int_array("address");
    let addrs: Vec<i64> = if given.is_empty() {
        vec![default_addr as i64]
    } else {
        given.to_vec()
    };
    let buses = p.ints_per("bus", addrs.len(), DEFAULT_BUS, 0..=1023)?;
    let mut chips: Vec<ChipAt> = Vec::with_capacity(addrs.len());
    for (i, (&a, &bus)) in addrs.iter().zip(&buses).enumerate() {
        let text = format!("{a:#04x}");
        if a < *addresses.start() as i64 || a > *addresses.end() as i64 {
            return Err(p.item_error(
                "address",
                i,
                &text,
                format_args!(
                    "not an address this chip can have ({:#04x}..={:#04x})",
                    addresses.start(),
                    addresses.end()
                ),
            ));
        }
        let at = ChipAt {
            bus: bus as u32,
            addr: a as u8,
        };
        if let Some(j) = chips.iter().position(|c| *c == at) {
            return Err(p.item_error(
                "address",
                i,
                &text,
                format_args!("chip {j} is at this address of bus {bus} already"),
            ));
        }
        chips.push(at);
    }
    Ok((backend, chips))
}

/// A per-chip 0/1 parameter.
pub fn flags_per(
    p: &Params<'_>,
    name: &str,
    chips: usize,
) -> std::result::Result<Vec<bool>, DriverError> {
    Ok(p.ints_per(name, chips, 0, 0..=1)?
        .into_iter()
        .map(|v| v != 0)
        .collect())
}

/// The key of a simulated bus for [`hal_driver::sim::find`].
pub fn sim_key(bus: u32) -> String {
    format!("i2c.{bus}")
}

/// The simulated bus `bus` of `instance`, while a module uses it.
pub fn sim_bus(instance: &str, bus: u32) -> Option<Arc<SimBus>> {
    hal_driver::sim::find(instance, &sim_key(bus))
}

/// The helper thread of bus `bus` on `backend` in HAL `instance`,
/// started if need be.
pub fn worker_for(
    instance: &str,
    backend: Backend,
    bus: u32,
) -> std::result::Result<Arc<BusWorker>, I2cError> {
    let spawn_failed = |e: std::io::Error| I2cError::Open {
        path: format!("bus {bus}"),
        reason: format!("starting its helper thread: {e}"),
    };
    match backend {
        Backend::Sim(_) => worker::worker(
            instance,
            &format!("sim.{bus}"),
            || {
                let sim = Arc::new(SimBus::new(
                    &format!("simulated i2c-{bus}"),
                    Arc::new(SimClock::following_thread()),
                ));
                let as_bus: Arc<dyn I2cBus> = sim.clone();
                Ok((as_bus, Some(sim)))
            },
            spawn_failed,
        ),
        Backend::Real(_) => {
            let path = LinuxBus::path_of(bus);
            worker::worker(
                instance,
                &path.display().to_string(),
                || {
                    let b: Arc<dyn I2cBus> = Arc::new(LinuxBus::open(&path)?);
                    Ok((b, None))
                },
                spawn_failed,
            )
        }
    }
}

/// A chip found, reserved and set up, not yet running.
pub struct Prepared<C: Chip> {
    worker: Arc<BusWorker>,
    reservation: Reservation,
    chip: C,
}

/// Finds the bus, reserves the address, puts a model there on a
/// simulated bus, takes the address and sets `chip` up with its outputs
/// at `safe`. `name` is the chip's HAL name, for messages.
pub fn prepare<C: Chip>(
    instance: &str,
    backend: Backend,
    at: ChipAt,
    name: &str,
    model: impl FnOnce() -> Box<dyn ChipModel>,
    mut chip: C,
    safe: &C::Cmd,
) -> std::result::Result<Prepared<C>, I2cError> {
    let worker = worker_for(instance, backend, at.bus)?;
    let bus_name = worker.bus().describe();
    let reservation = worker.reserve(at.addr, name)?;
    if let Some(sim) = worker.sim() {
        sim.add_chip(at.addr, model());
    }
    worker
        .bus()
        .claim(at.addr)
        .map_err(|e| I2cError::claim(name, &bus_name, at.addr, e))?;
    chip.init(&**worker.bus(), safe)
        .map_err(|source| I2cError::Init {
            chip: name.into(),
            bus: bus_name,
            addr: at.addr,
            source,
        })?;
    Ok(Prepared {
        worker,
        reservation,
        chip,
    })
}

/// [`prepare`]s every chip of module `module` (chip i called `module.i`),
/// `make` giving chip i's driver and the safe command it starts with,
/// `model` the register model a simulated bus gets. Any failure fails
/// the whole load; what was prepared is released.
pub fn prepare_all<C: Chip>(
    instance: &str,
    backend: Backend,
    module: &str,
    chips: &[ChipAt],
    model: fn() -> Box<dyn ChipModel>,
    mut make: impl FnMut(usize, ChipAt) -> Result<(C, C::Cmd)>,
) -> Result<Vec<(Prepared<C>, ChipAt)>> {
    let mut prepared = Vec::with_capacity(chips.len());
    for (i, &at) in chips.iter().enumerate() {
        let (chip, safe) = make(i, at)?;
        let name = format!("{module}.{i}");
        let p = prepare(instance, backend, at, &name, model, chip, &safe)
            .map_err(|e| e.into_hal(module))?;
        prepared.push((p, at));
    }
    Ok(prepared)
}

/// Makes component `module` for the `prepared` chips: puts each on its
/// helper thread and lets `each` make its pins and functions on the
/// component (given the chip's index and HAL name, and the realtime ends
/// of its hand-offs); then gives the chips' safe state and what keeps
/// them running to the component, and publishes the simulated buses.
pub fn export_chips<H: DriverHost, C: Chip>(
    ex: &mut Exporter<'_, H>,
    module: &str,
    prepared: Vec<(Prepared<C>, ChipAt)>,
    mut each: impl FnMut(&mut Exporter<'_, H>, CompId, usize, &str, RealtimeEnds<C>) -> Result<()>,
) -> Result<()> {
    let comp = ex.component(module)?;
    let mut chips = ModuleChips {
        safes: Vec::new(),
        running: Vec::new(),
    };
    for (i, (prep, at)) in prepared.into_iter().enumerate() {
        let name = format!("{module}.{i}");
        let (running, ends) = start(ex.log(), prep, at, &name);
        chips.safes.push(ChipSafe {
            flags: ends.flags.clone(),
        });
        if let Some((bus, sim)) = &running.simulated {
            ex.publish_sim(&sim_key(*bus), sim);
        }
        chips.running.push(running);
        each(ex, comp, i, &name, ends)?;
    }
    ex.safe_state(comp, chips);
    Ok(())
}

/// What keeps a running chip on its helper thread.
pub struct Running {
    _attachment: Attachment,
    _reservation: Reservation,
    simulated: Option<(u32, Arc<SimBus>)>,
}

/// Puts a prepared chip on its helper thread; returns what keeps it
/// there and the realtime ends of its hand-offs.
pub fn start<C: Chip>(
    log: LogSink,
    p: Prepared<C>,
    at: ChipAt,
    name: &str,
) -> (Running, RealtimeEnds<C>) {
    let (runner, ends) = ChipRunner::new(name, p.chip, log);
    let attachment = p.worker.attach(runner);
    let simulated = p.worker.sim().map(|s| (at.bus, s.clone()));
    (
        Running {
            _attachment: attachment,
            _reservation: p.reservation,
            simulated,
        },
        ends,
    )
}

/// The running chips of one module and their safe-state hooks.
pub struct ModuleChips {
    /// The chips' hooks.
    pub safes: Vec<ChipSafe>,
    /// What keeps them running.
    pub running: Vec<Running>,
}

impl SafeState for ModuleChips {
    /// Every chip's outputs safe.
    fn go_safe(&self) {
        for s in &self.safes {
            s.go_safe();
        }
    }
}

/// A chip's fault, error-count and fault-reset pins, in host `H`.
pub struct StatusPins<H: HalHost = Ours> {
    fault: H::Pin<bool, Out>,
    errors: H::Pin<u32, Out>,
    reset: H::Pin<bool, In>,
}

impl<H: HalHost> StatusPins<H> {
    /// Exports `<name>.fault`, `<name>.errors`, `<name>.fault-reset`.
    pub fn export(c: &impl PinFactory<H>, name: &str) -> Result<Self> {
        Ok(StatusPins {
            fault: c.pin(&format!("{name}.fault"))?,
            errors: c.pin(&format!("{name}.errors"))?,
            reset: c.pin(&format!("{name}.fault-reset"))?,
        })
    }

    /// Takes the newest status: sets the pins, passes a fault-reset edge
    /// on, and returns the status for the chip's own pins.
    #[inline]
    pub fn update<'a, S: Send>(&self, port: &'a mut StatusPort<S>) -> &'a Status<S> {
        port.fault_reset(self.reset.get());
        let st = port.latest();
        self.fault.set(st.fault);
        self.errors.set(st.errors);
        st
    }
}
