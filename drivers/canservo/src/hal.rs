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

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, HalError, Host, In, Io, Out, Param, Pin, Result, Ro, Rw};
use hal_driver::fault::{self, SafeState};
use hal_driver::params::Backend;
use hal_driver::sim::SimClock;
use hal_driver::ForModule;

use crate::bus::{CanBus, Filters, SimBus, SocketCanBus};
use crate::config::{self, Config, NAME};
use crate::engine::{DriveInputs, DriveShared, DriveStatus, Engine, RtCell};
use crate::helper::{Helper, HelperDrive};
use crate::regs::sw;
use crate::sim::SimDriveConfig;
use crate::startup::Network;

/// The `canservo` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: config::PARAMS,
    help: "CANopen CiA 402 servo drives over SocketCAN (or simulated: backend=sim)",
    load,
};

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

/// The statusword bits as pins, in bit order.
const STATUS_BITS: [(u16, &str); 13] = sw::NAMES;

/// One drive's pins and params.
struct DrivePins {
    enable: Pin<bool, In>,
    position_cmd: Pin<f64, In>,
    velocity_cmd: Pin<f64, In>,
    fault_reset: Pin<bool, In>,
    home: Pin<bool, Io>,
    position_fb: Pin<f64, Out>,
    velocity_fb: Pin<f64, Out>,
    amp_fault: Pin<bool, Out>,
    fault_code: Pin<u32, Out>,
    error_code: Pin<u32, Out>,
    error_register: Pin<u32, Out>,
    enabled: Pin<bool, Out>,
    state: Pin<i32, Out>,
    statusword: Pin<u32, Out>,
    bits: Vec<Pin<bool, Out>>,
    mode: Pin<i32, Out>,
    homing: Pin<bool, Out>,
    home_complete: Pin<bool, Out>,
    nmt_state: Pin<u32, Out>,
    scale: Param<f64, Rw>,
    tolerance: Param<f64, Rw>,
}

impl DrivePins {
    fn export(c: &Component, n: usize, scale: f64) -> Result<DrivePins> {
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
        self.amp_fault.set(s.amp_fault);
        self.fault_code.set(s.fault_code);
        self.error_code.set(u32::from(s.error_code));
        self.error_register.set(s.error_register);
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

/// The two endpoints (setup, realtime) and the simulated bus, if any.
type Opened = (Box<dyn CanBus>, Arc<dyn CanBus>, Option<Arc<SimBus>>);

fn open(cfg: &Config) -> Result<Opened> {
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

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    load_config(host, config::parse(args).for_module(NAME)?)
}

fn load_sim_only(host: &Host, args: &ModuleArgs) -> Result<()> {
    let mut cfg = config::parse(args).for_module(NAME)?;
    cfg.backend = Backend::Sim("sim");
    load_config(host, cfg)
}

fn load_config(host: &Host, cfg: Config) -> Result<()> {
    let (setup, rt, sim) = open(&cfg)?;
    // Bring the drives up to the point before NMT start; nothing moves
    // and no HAL object exists yet, so a failure leaves nothing behind.
    let configured = Network::boot(&*setup, cfg.plans.clone(), cfg.startup.clone())
        .and_then(|n| n.identify())
        .and_then(|n| n.configure())
        .map_err(load_error)?;
    let mut b = host.new_rt_component(NAME)?;
    let mut pins = Vec::with_capacity(cfg.plans.len());
    for (i, (n, scale)) in configured.nodes().iter().zip(&cfg.scales).enumerate() {
        let p = DrivePins::export(b.component(), i, *scale)?;
        let c = b.component();
        let id = &n.identity;
        for (item, value) in [
            ("node", u32::from(n.plan.node)),
            ("vendor-id", id.vendor),
            ("product-code", id.product),
            ("revision", id.revision),
            ("serial-number", id.serial),
        ] {
            let _: Param<u32, Ro> = c.param(&format!("canservo.{i}.{item}"), value)?;
        }
        pins.push(p);
    }
    let bus_errors: Pin<u32, Out> = b.component().pin("canservo.bus-errors")?;
    let nodes = configured.start().map_err(load_error)?.into_nodes();
    while rt.try_recv().is_some() {}
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
    let log = host.rt_log();
    for (i, n) in nodes.iter().enumerate() {
        log.info(format_args!(
            "canservo.{i}: node {}: {}",
            n.plan.node, n.identity
        ));
    }
    let engine = Engine::new(
        rt,
        nodes,
        shared,
        cfg.engine.clone(),
        Some(log.clone()),
        true,
    );
    let cell = Arc::new(RtCell::new(engine));
    let pins = Arc::new(pins);
    let count = pins.len();

    let (c, p) = (cell.clone(), pins.clone());
    let mut inputs = vec![DriveInputs::default(); count];
    b.funct("canservo.read", true, move |ctx| {
        for (slot, pin) in inputs.iter_mut().zip(p.iter()) {
            *slot = pin.inputs();
        }
        c.try_with(|e| {
            e.read(ctx.now_ns(), &inputs);
            for (pin, st) in p.iter().zip(e.status()) {
                pin.publish(st);
            }
            let (error_frames, _) = e.counters();
            bus_errors.set((e.bus_errors() + error_frames) as u32);
        });
    })?;
    let (c, p) = (cell.clone(), pins);
    let mut inputs = vec![DriveInputs::default(); count];
    b.funct("canservo.write", true, move |ctx| {
        for (slot, pin) in inputs.iter_mut().zip(p.iter()) {
            *slot = pin.inputs();
        }
        c.try_with(|e| e.write(ctx.now_ns(), ctx.period(), &inputs));
    })?;
    let helper = Helper::spawn(setup, helper_drives, cfg.startup.clone(), cfg.diag, log).map_err(
        |source| {
            load_error(crate::Error::Thread {
                what: "helper thread",
                source,
            })
        },
    )?;
    fault::install(
        &mut b,
        SafeDrives {
            engine: cell,
            _helper: helper,
        },
    );
    b.ready()?;
    if let Some(bus) = sim {
        hal_driver::sim::publish(host.instance().name(), NAME, &bus);
    }
    Ok(())
}
