//! The HAL binding: `loadrt hal_ppmc`.
//!
//! One component `hal_ppmc`; per bus the functions `ppmc.<bus>.read`
//! (strobe the counters, read every board's inputs in register runs,
//! publish) and `ppmc.<bus>.write` (compute every output, write the runs),
//! and the pins of the boards found, numbered per kind across the bus in
//! slot order, as LinuxCNC numbers them.

pub mod digital;
pub mod encoder;
pub mod outputs;
pub mod slot;

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{FunctCtx, HalHost, Host, PinFactory, Result};
use hal_driver::fault::{Fault, FaultLatch, SafeState};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::rt_cell::RtCell;
use hal_driver::sim::SimBoard;
use hal_driver::ForModule;

use crate::epp::Epp;
use crate::open::{self, OpenedBus, Planned};
use crate::params;
use crate::sim::PpmcPort;
use slot::{Numbers, Slot};

/// The module's name.
pub const NAME: &str = "hal_ppmc";

/// hal_ppmc's module parameters, the one table both hosts read:
/// LinuxCNC's, and the simulator.
#[macro_export]
macro_rules! hal_ppmc_params {
    ($($then:tt)*) => { $($then)*! {
        port_addr: IntArray(3) = "EPP port addresses (or Linux port numbers 0..15), one per bus; default 0x378",
        extradac: IntArray(24) = "bus/slot codes 0xBS of USC/UPC boards whose extra port drives the 8-bit DAC",
        extradout: IntArray(24) = "bus/slot codes 0xBS of USC/UPC boards whose extra port is 8 more outputs",
        timestamp: IntArray(24) = "bus/slot codes 0xBS of encoder boards or UPCs whose timestamps give the velocity",
        enc_clock: IntArray(24) = "0xFBS: encoder filter clock F MHz (1, 2 for 2.5, 5, a for 10) of the encoder board at bus B slot S",
        epp_dir: IntArray(3) = "per bus: 0 (default) turns the data lines for reads, 1 leaves them (old ports)",
        sim: StrArray(3) = "per bus: simulated boards instead of the port, e.g. ppmc, usc, upc, encoder+dac+dio, upc:2",
    } };
}

/// The module's parameters.
pub const PARAMS: &[ParamDecl] = hal_ppmc_params!(hal_driver::param_table);

/// The `hal_ppmc` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalPpmc;

/// The `hal_ppmc` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalPpmc>();

/// The boards stopped answering.
pub static BUS_LOST: Fault = Fault::new(
    1,
    "the boards stopped answering (EPP timeouts in two periods running): estop outputs off, \
     generators stopped, DACs at 0 V; reload the driver once the cable and boards are back",
);

/// Periods running with timeouts that trip the fault.
pub const TIMEOUT_PERIODS: u32 = 2;

impl DriverModule for HalPpmc {
    const NAME: &'static str = NAME;
    const HELP: &'static str =
        "Pico Systems PPMC, USC and UPC boards on EPP parallel ports (or simulated ones)";
    const PARAMS: &'static [ParamDecl] = PARAMS;
    type Opened = Vec<OpenedBus>;

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<Vec<OpenedBus>> {
        let cfg = params::parse(args).for_module(NAME)?;
        open::open(&cfg).map_err(|e| e.into_hal(NAME))
    }

    fn export<H: DriverHost>(buses: Vec<OpenedBus>, ex: &mut Exporter<'_, H>) -> Result<()> {
        let comp = ex.component(NAME)?;
        for bus in buses {
            export_bus(bus, comp, ex)?;
        }
        Ok(())
    }
}

/// Exports buses already opened into our host (what `loadrt` does after
/// opening them; tests give buses of their own).
pub fn load_opened(host: &Host, buses: Vec<OpenedBus>) -> Result<()> {
    module::load_opened::<HalPpmc>(host, buses)
}

/// What the safe state and the fault latch need: the port and the boards.
struct SafeBus {
    epp: Epp,
    boards: Vec<Planned>,
}

impl SafeState for SafeBus {
    fn go_safe(&self) {
        open::go_safe(&self.epp, &self.boards);
    }
}

/// One bus's realtime state.
struct BusRt<H: HalHost> {
    epp: Epp,
    slots: Vec<Slot<H>>,
}

/// What both functions share.
struct Shared<H: HalHost> {
    cell: RtCell<BusRt<H>>,
    safe: Arc<SafeBus>,
    latch: FaultLatch<H>,
    /// Periods running whose reads timed out.
    bad_periods: AtomicU32,
    sim: Option<Arc<SimBoard<PpmcPort>>>,
}

fn export_bus<H: DriverHost>(
    bus: OpenedBus,
    comp: module::CompId,
    ex: &mut Exporter<'_, H>,
) -> Result<()> {
    let n = bus.number;
    let c = ex.pins(comp);
    let mut numbers = Numbers::default();
    let mut slots = bus
        .boards
        .iter()
        .map(|p| Slot::export(c, n, p, &mut numbers))
        .collect::<Result<Vec<_>>>()?;
    // The counters were just cleared: the first reading is their zero.
    for s in &mut slots {
        s.fetch(&bus.epp);
        s.prime();
    }
    let place = if bus.sim.is_some() { ", simulated" } else { "" };
    let latch = FaultLatch::named(format!("ppmc.{n} (port {:#x}{place})", bus.epp.base()))
        .with_log(ex.log())
        .with_pin(c.pin(&format!("ppmc.{n}.fault"))?);
    let safe = Arc::new(SafeBus {
        epp: bus.epp.clone(),
        boards: bus.boards.clone(),
    });
    let sh = Arc::new(Shared {
        cell: RtCell::new(BusRt {
            epp: bus.epp,
            slots,
        }),
        safe: safe.clone(),
        latch,
        bad_periods: AtomicU32::new(0),
        sim: bus.sim,
    });
    let s = sh.clone();
    ex.funct(comp, &format!("ppmc.{n}.read"), true, move |ctx| {
        read(&s, ctx)
    })?;
    let s = sh.clone();
    ex.funct(comp, &format!("ppmc.{n}.write"), true, move |_| write(&s))?;
    ex.safe_state(comp, safe);
    if let Some(s) = &sh.sim {
        ex.publish_sim(&format!("ppmc.{n}"), s);
    }
    Ok(())
}

/// `ppmc.<bus>.read`: moves a simulated bus one period, strobes and reads
/// every board; a period with EPP timeouts publishes nothing, two running
/// trip the fault.
fn read<H: HalHost>(sh: &Shared<H>, ctx: &FunctCtx) {
    if let Some(s) = &sh.sim {
        s.advance(ctx.period().max(0) as u64);
    }
    if sh.latch.is_tripped() {
        return;
    }
    let period_s = ctx.period().max(0) as f64 * 1e-9;
    let outcome = sh.cell.try_with(|b| {
        let before = b.epp.timeouts();
        for s in &mut b.slots {
            s.fetch(&b.epp);
        }
        let clean = b.epp.timeouts() == before && !b.epp.timed_out();
        if clean {
            for s in &mut b.slots {
                s.publish(period_s);
            }
        }
        clean
    });
    match outcome {
        Some(true) => sh.bad_periods.store(0, Relaxed),
        Some(false) if sh.bad_periods.fetch_add(1, Relaxed) + 1 >= TIMEOUT_PERIODS => {
            sh.latch.trip_into(&BUS_LOST, &*sh.safe);
        }
        Some(false) | None => {}
    }
}

/// `ppmc.<bus>.write`: every board's outputs. Nothing once faulted.
fn write<H: HalHost>(sh: &Shared<H>) {
    if sh.latch.is_tripped() {
        return;
    }
    sh.cell.try_with(|b| {
        for s in &mut b.slots {
            s.write(&b.epp);
        }
    });
}

/// Loads `hal_ppmc` into `host` only when every bus is simulated (the
/// fuzzers' registry): a bus without `sim=` is refused before any port
/// is touched.
pub fn load_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    let cfg = params::parse(args).for_module(NAME)?;
    if cfg.buses.iter().any(|b| b.sim.is_none()) {
        let p = hal_driver::params::Params::new(NAME, args);
        return Err(p
            .error(
                "sim",
                "this registry drives simulated buses only: give sim= for every port",
            )
            .into_hal(NAME));
    }
    module::load::<HalPpmc>(host, args)
}
