//! The HAL binding: `loadrt canservo nodes=... [iface=...|backend=sim]`.
//!
//! One realtime component `canservo`; per drive N (in `nodes=` order):
//!
//! | name | kind | type | dir | meaning |
//! |---|---|---|---|---|
//! | `canservo.N.enable` | pin | bit | in | power the drive up (Operation enabled) or down |
//! | `canservo.N.position-cmd` | pin | float | in | target position, user units (CSP) |
//! | `canservo.N.velocity-cmd` | pin | float | in | target velocity, user units/s (PV, CSV) |
//! | `canservo.N.fault-reset` | pin | bit | in | rising edge: reset a fault |
//! | `canservo.N.home` | pin | bit | io | rising edge: start drive-internal homing; the driver clears it when homing is done (wire it to `joint.N.index-enable`) |
//! | `canservo.N.position-fb` | pin | float | out | actual position, user units (echoes `position-cmd` while homing) |
//! | `canservo.N.velocity-fb` | pin | float | out | actual velocity, user units/s |
//! | `canservo.N.amp-fault` | pin | bit | out | the drive is faulted (master-side latch or drive Fault) |
//! | `canservo.N.fault-code` | pin | u32 | out | why the master faulted it (0 = clear; the codes of [`crate::engine::faults`]) |
//! | `canservo.N.error-code` | pin | u32 | out | the drive's error code (last EMCY, else 0x603F) |
//! | `canservo.N.error-register` | pin | u32 | out | 0x1001, read by the helper |
//! | `canservo.N.enabled` | pin | bit | out | Operation enabled and not faulted |
//! | `canservo.N.state` | pin | s32 | out | CiA 402 state: 1 not ready to switch on, 2 switch on disabled, 3 ready to switch on, 4 switched on, 5 operation enabled, 6 quick stop active, 7 fault reaction active, 8 fault (0 unknown) |
//! | `canservo.N.statusword` | pin | u32 | out | the statusword |
//! | `canservo.N.status.<bit>` | pin | bit | out | its bits: `ready-to-switch-on`, `switched-on`, `operation-enabled`, `fault`, `voltage-enabled`, `quick-stop`, `switch-on-disabled`, `warning`, `remote`, `target-reached`, `internal-limit`, `mode-bit-12`, `mode-bit-13` |
//! | `canservo.N.mode` | pin | s32 | out | the mode in use (0x6061: 8 CSP, 3 PV, 9 CSV, 6 homing) |
//! | `canservo.N.homing` | pin | bit | out | drive-internal homing in progress |
//! | `canservo.N.home-complete` | pin | bit | out | the last homing succeeded |
//! | `canservo.N.nmt-state` | pin | u32 | out | heartbeat state byte (5 operational) |
//! | `canservo.N.position-scale` | param | float | rw | counts per user unit (loadrt `scale`) |
//! | `canservo.N.command-tolerance` | param | float | rw | user units; see below (default 0.01) |
//! | `canservo.N.node` | param | u32 | ro | node id |
//! | `canservo.N.vendor-id`, `.product-code`, `.revision`, `.serial-number` | param | u32 | ro | 0x1018 |
//!
//! and `canservo.bus-errors` (u32 out: failed sends and receives plus
//! error frames). Functions: `canservo.read` and `canservo.write` (the
//! whole bus each: `write` sends every RPDO before the one SYNC).
//!
//! After enabling and after homing, a CSP drive is held where it is
//! until `position-cmd` comes within `command-tolerance` of its actual
//! position, so a command that is not in step never makes it jump (the
//! motion core's command tracks feedback while disabled, so it is).
//!
//! The safe-state hook (unload, exit, a panic in any realtime function)
//! quick-stops every drive, then disables voltage.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{
    HalError, HalHost, Host, HostParam, HostPin, In, Io, Out, PinFactory, Result, Ro, Rw,
};
use hal_driver::fault::SafeState;
use hal_driver::module::{self, CompId, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Backend;
use hal_driver::sim::SimClock;
use hal_driver::ForModule;

use crate::bus::{CanBus, Filters, SimBus, SocketCanBus};
use crate::config::{self, Config, NAME};
use crate::engine::{DriveInputs, DriveShared, DriveStatus, Engine, RtCell};
use crate::helper::{Helper, HelperDrive};
use crate::regs::sw;
use crate::sim::SimDriveConfig;
use crate::startup::{Detached, Network, NodeInfo};

/// The `canservo` driver, declared once for both hosts.
#[derive(Debug)]
pub struct Canservo;

/// The `canservo` module of our host.
pub static MODULE: ModuleDef = module::module_def::<Canservo>();

/// `canservo` with every drive simulated whatever `backend=` says: the
/// form fuzzers and other tests that must never reach a real bus load
/// (the parameters are parsed by the driver's own code, and a line that
/// does not parse fails exactly as with [`MODULE`]).
pub static SIM_ONLY_MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: config::PARAMS,
    help: "canservo on simulated drives only (for fuzzing)",
    load: load_sim_only,
};

impl DriverModule for Canservo {
    const NAME: &'static str = NAME;
    const HELP: &'static str =
        "CANopen CiA 402 servo drives over SocketCAN (or simulated: backend=sim)";
    const PARAMS: &'static [ParamDecl] = config::PARAMS;
    type Opened = OpenedDrives;

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<OpenedDrives> {
        open_config(config::parse(args).for_module(NAME)?)
    }

    fn export<H: DriverHost>(o: OpenedDrives, ex: &mut Exporter<'_, H>) -> Result<()> {
        let comp = ex.component(NAME)?;
        let pins = export_pins(ex.pins(comp), &o)?;
        let nodes = o
            .configured
            .attach(&*o.setup)
            .start()
            .map_err(load_error)?
            .into_nodes();
        while o.rt.try_recv().is_some() {}
        let log = ex.log();
        for (i, n) in nodes.iter().enumerate() {
            log.info(format_args!(
                "canservo.{i}: node {}: {}",
                n.plan.node, n.identity
            ));
        }
        let shared: Vec<Arc<DriveShared>> = nodes
            .iter()
            .map(|_| Arc::new(DriveShared::default()))
            .collect();
        let helper_drives = nodes
            .iter()
            .zip(&shared)
            .enumerate()
            .map(|(index, (n, s))| HelperDrive {
                index,
                plan: n.plan.clone(),
                shared: s.clone(),
            })
            .collect();
        let engine = Engine::new(
            o.rt,
            nodes,
            shared,
            o.cfg.engine.clone(),
            Some(log.clone()),
            true,
        );
        let cell = Arc::new(RtCell::new(engine));
        export_functs(ex, comp, &cell, pins)?;
        let helper = Helper::spawn(o.setup, helper_drives, o.cfg.startup, o.cfg.diag, log)
            .map_err(|source| {
                load_error(crate::Error::Thread {
                    what: "helper thread",
                    source,
                })
            })?;
        ex.safe_state(
            comp,
            SafeDrives {
                engine: cell,
                _helper: helper,
            },
        );
        if let Some(bus) = &o.sim {
            ex.publish_sim(NAME, bus);
        }
        Ok(())
    }
}

/// The statusword bits as pins, in bit order.
const STATUS_BITS: [(u16, &str); 13] = sw::NAMES;

/// One drive's pins and params, in host `H`.
struct DrivePins<H: HalHost> {
    enable: H::Pin<bool, In>,
    position_cmd: H::Pin<f64, In>,
    velocity_cmd: H::Pin<f64, In>,
    fault_reset: H::Pin<bool, In>,
    home: H::Pin<bool, Io>,
    position_fb: H::Pin<f64, Out>,
    velocity_fb: H::Pin<f64, Out>,
    amp_fault: H::Pin<bool, Out>,
    fault_code: H::Pin<u32, Out>,
    error_code: H::Pin<u32, Out>,
    error_register: H::Pin<u32, Out>,
    enabled: H::Pin<bool, Out>,
    state: H::Pin<i32, Out>,
    statusword: H::Pin<u32, Out>,
    bits: Vec<H::Pin<bool, Out>>,
    mode: H::Pin<i32, Out>,
    homing: H::Pin<bool, Out>,
    home_complete: H::Pin<bool, Out>,
    nmt_state: H::Pin<u32, Out>,
    scale: H::Param<f64, Rw>,
    tolerance: H::Param<f64, Rw>,
}

impl<H: HalHost> DrivePins<H> {
    fn export(c: &impl PinFactory<H>, n: usize, scale: f64) -> Result<Self> {
        let name = |item: &str| format!("canservo.{n}.{item}");
        Ok(DrivePins {
            enable: c.pin(&name("enable"))?,
            position_cmd: c.pin(&name("position-cmd"))?,
            velocity_cmd: c.pin(&name("velocity-cmd"))?,
            fault_reset: c.pin(&name("fault-reset"))?,
            home: c.pin(&name("home"))?,
            position_fb: c.pin(&name("position-fb"))?,
            velocity_fb: c.pin(&name("velocity-fb"))?,
            amp_fault: c.pin(&name("amp-fault"))?,
            fault_code: c.pin(&name("fault-code"))?,
            error_code: c.pin(&name("error-code"))?,
            error_register: c.pin(&name("error-register"))?,
            enabled: c.pin(&name("enabled"))?,
            state: c.pin(&name("state"))?,
            statusword: c.pin(&name("statusword"))?,
            bits: STATUS_BITS
                .iter()
                .map(|(_, b)| c.pin(&name(&format!("status.{b}"))))
                .collect::<Result<_>>()?,
            mode: c.pin(&name("mode"))?,
            homing: c.pin(&name("homing"))?,
            home_complete: c.pin(&name("home-complete"))?,
            nmt_state: c.pin(&name("nmt-state"))?,
            scale: c.param(&name("position-scale"), scale)?,
            tolerance: c.param(&name("command-tolerance"), 0.01)?,
        })
    }

    /// The drive's identity, read-only.
    fn export_identity(c: &impl PinFactory<H>, n: usize, node: &NodeInfo) -> Result<()> {
        let id = &node.identity;
        for (item, value) in [
            ("node", u32::from(node.plan.node)),
            ("vendor-id", id.vendor),
            ("product-code", id.product),
            ("revision", id.revision),
            ("serial-number", id.serial),
        ] {
            let _: H::Param<u32, Ro> = c.param(&format!("canservo.{n}.{item}"), value)?;
        }
        Ok(())
    }

    #[inline]
    fn inputs(&self) -> DriveInputs {
        DriveInputs {
            enable: self.enable.get(),
            fault_reset: self.fault_reset.get(),
            position_cmd: self.position_cmd.get(),
            velocity_cmd: self.velocity_cmd.get(),
            home: self.home.get(),
            scale: canonical::usable_scale(&self.scale),
            command_tolerance: self.tolerance.get(),
        }
    }

    #[inline]
    fn publish(&self, s: &DriveStatus) {
        self.position_fb.set(s.position_fb);
        self.velocity_fb.set(s.velocity_fb);
        // The codes go out before the flag, so whoever sees amp-fault
        // TRUE also sees why.
        self.fault_code.set(s.fault_code);
        self.error_code.set(u32::from(s.error_code));
        self.error_register.set(s.error_register);
        self.amp_fault.set(s.amp_fault);
        self.enabled.set(s.enabled);
        self.state.set(s.state.map_or(0, |st| st.number()));
        self.statusword.set(u32::from(s.statusword));
        for (pin, (bit, _)) in self.bits.iter().zip(STATUS_BITS) {
            pin.set(s.statusword & bit != 0);
        }
        self.mode.set(i32::from(s.mode_display));
        self.homing.set(s.homing);
        self.home_complete.set(s.home_complete);
        self.nmt_state.set(u32::from(s.nmt_state));
        if s.home_clear {
            self.home.set(false);
        }
    }
}

/// Every drive's pins and the bus's error count, in host `H`.
struct BusPins<H: HalHost> {
    drives: Vec<DrivePins<H>>,
    bus_errors: H::Pin<u32, Out>,
}

/// Exports every configured drive's pins and identity, then the bus's.
fn export_pins<H: HalHost>(c: &impl PinFactory<H>, o: &OpenedDrives) -> Result<BusPins<H>> {
    let nodes = o.configured.nodes();
    let mut drives = Vec::with_capacity(nodes.len());
    for (i, (n, scale)) in nodes.iter().zip(&o.cfg.scales).enumerate() {
        drives.push(DrivePins::export(c, i, *scale)?);
        DrivePins::<H>::export_identity(c, i, n)?;
    }
    Ok(BusPins {
        drives,
        bus_errors: c.pin("canservo.bus-errors")?,
    })
}

/// Exports `canservo.read` and `canservo.write`, which run the engine in
/// `cell` against `pins`.
fn export_functs<H: DriverHost>(
    ex: &mut Exporter<'_, H>,
    comp: CompId,
    cell: &Arc<RtCell<Engine>>,
    pins: BusPins<H>,
) -> Result<()> {
    let pins = Arc::new(pins);
    let count = pins.drives.len();
    let (c, p) = (cell.clone(), pins.clone());
    let mut inputs = vec![DriveInputs::default(); count];
    ex.funct(comp, "canservo.read", true, move |ctx| {
        for (slot, pin) in inputs.iter_mut().zip(&p.drives) {
            *slot = pin.inputs();
        }
        c.try_with(|e| {
            e.read(ctx.now_ns(), &inputs);
            for (pin, st) in p.drives.iter().zip(e.status()) {
                pin.publish(st);
            }
            let (error_frames, _) = e.counters();
            p.bus_errors.set((e.bus_errors() + error_frames) as u32);
        });
    })?;
    let (c, p) = (cell.clone(), pins);
    let mut inputs = vec![DriveInputs::default(); count];
    ex.funct(comp, "canservo.write", true, move |ctx| {
        for (slot, pin) in inputs.iter_mut().zip(&p.drives) {
            *slot = pin.inputs();
        }
        c.try_with(|e| e.write(ctx.now_ns(), ctx.period(), &inputs));
    })
}

/// What the safe-state hook needs: the engine, and the helper (dropped,
/// and so stopped, with the component).
struct SafeDrives {
    engine: Arc<RtCell<Engine>>,
    _helper: Helper,
}

impl SafeState for SafeDrives {
    fn go_safe(&self) {
        self.engine.try_with(|e| e.go_safe());
    }
}

fn load_error(e: crate::Error) -> HalError {
    HalError::module_failed(NAME, e)
}

/// The bus, its drives booted, identified and configured (not yet
/// started), and what `loadrt` said: what [`Canservo`]'s `open` opened.
pub struct OpenedDrives {
    cfg: Config,
    /// The setup endpoint: start-up SDOs here, then the helper's.
    setup: Box<dyn CanBus>,
    /// The realtime endpoint: the engine's.
    rt: Arc<dyn CanBus>,
    sim: Option<Arc<SimBus>>,
    configured: Detached,
}

/// The two endpoints (setup, realtime) and the simulated bus, if any.
type Buses = (Box<dyn CanBus>, Arc<dyn CanBus>, Option<Arc<SimBus>>);

fn open_buses(cfg: &Config) -> Result<Buses> {
    let nodes: Vec<u8> = cfg.plans.iter().map(|p| p.node).collect();
    if cfg.backend.is_sim() {
        let bus = SimBus::with_clock(Arc::new(SimClock::following_thread()));
        for (p, home) in cfg.plans.iter().zip(&cfg.sim_home) {
            let mut d = SimDriveConfig::new(p.node);
            d.home_switch = Some(hal_driver::plant::Switch::at_or_above(*home as f64));
            bus.add_drive(d);
        }
        let setup: Box<dyn CanBus> = Box::new(bus.open(Filters::setup(&nodes)));
        let rt: Arc<dyn CanBus> = Arc::new(bus.open(Filters::realtime(&nodes)));
        return Ok((setup, rt, Some(bus)));
    }
    let setup = SocketCanBus::open(&cfg.iface, &Filters::setup(&nodes)).map_err(load_error)?;
    let rt = SocketCanBus::open(&cfg.iface, &Filters::realtime(&nodes)).map_err(load_error)?;
    Ok((Box::new(setup), Arc::new(rt), None))
}

/// Opens the bus and brings the drives up to the point before NMT
/// start; nothing moves and no HAL object exists yet, so a failure
/// leaves nothing behind.
fn open_config(cfg: Config) -> Result<OpenedDrives> {
    let (setup, rt, sim) = open_buses(&cfg)?;
    let configured = Network::boot(&*setup, cfg.plans.clone(), cfg.startup.clone())
        .and_then(|n| n.identify())
        .and_then(|n| n.configure())
        .map_err(load_error)?
        .detach();
    Ok(OpenedDrives {
        cfg,
        setup,
        rt,
        sim,
        configured,
    })
}

/// `canservo` on simulated drives only: the configuration's backend is
/// replaced before anything is opened.
fn load_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    let mut cfg = config::parse(args).for_module(NAME)?;
    cfg.backend = Backend::Sim("sim");
    module::load_opened::<Canservo>(host, open_config(cfg)?)
}
