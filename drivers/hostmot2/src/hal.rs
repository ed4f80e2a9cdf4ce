//! The HAL binding: `loadrt hostmot2`, `loadrt hm2_pci config="..."` (on
//! PCI boards or simulated ones) and `loadrt hm2_test test_pattern=N`.
//!
//! As in LinuxCNC, `hostmot2` must be loaded first; it makes the
//! component `hostmot2` and holds the debugging switches. `hm2_pci` and
//! `hm2_test` register their boards with it: the component `hm2_pci`
//! (`hm2_test`) owns every board's pins and params, and each board
//! exports `<board>.read`, `.write`, `.pet_watchdog` (with a watchdog)
//! and, the transport being thread-safe, `.read_gpio` and `.write_gpio`.
//!
//! Messages carry LinuxCNC's prefixes (`hm2/hm2_5i25.0: ...`) and go
//! through the host's realtime log, so they obey its level (errors only by
//! default). The `debug_*` switches print their dumps unconditionally, as
//! LinuxCNC's do.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, TryLockError, Weak};

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, MsgLevel, RtComponentBuilder};
use hal_driver::fault::{self, SafeState};
use hal_driver::pci::{EnableGuard, Sysfs};
use hal_driver::{sim as layer_sim, ForModule};

use crate::board::Board;
use crate::config;
use crate::error::Hm2Error;
use crate::firmware::Debug;
use crate::image::{FirmwareSpec, ImageTransport};
use crate::llio::Llio;
use crate::log::{BoardLog, MessageLog};
use crate::pci::{self, PciBoard};
use crate::sim::{self, boards, machine, SimHm2};
use crate::test_patterns;
use crate::transport::Transport;
use crate::window::WindowTransport;

/// Most boards one `hm2_pci` load drives.
pub const MAX_BOARDS: usize = 8;

// ---------------------------------------------------------------------
// hostmot2
// ---------------------------------------------------------------------

const HOSTMOT2: &str = "hostmot2";

const HOSTMOT2_PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "debug_idrom",
        kind: ParamKind::Int,
        help: "log the IDROM header of every board",
    },
    ParamDecl {
        name: "debug_module_descriptors",
        kind: ParamKind::Int,
        help: "log every module descriptor",
    },
    ParamDecl {
        name: "debug_pin_descriptors",
        kind: ParamKind::Int,
        help: "log every pin descriptor",
    },
    ParamDecl {
        name: "debug_modules",
        kind: ParamKind::Int,
        help: "log what each module uses",
    },
    ParamDecl {
        name: "use_serial_numbers",
        kind: ParamKind::Int,
        help:
            "name Smart Serial cards hm2_<card>.<unit number> instead of by board, port and channel",
    },
    ParamDecl {
        name: "sserial_baudrate",
        kind: ParamKind::Int,
        help: "set every Smart Serial channel to this baud rate at load (-1: leave it)",
    },
];

/// The `hostmot2` module: the core the board drivers register with.
pub static HOSTMOT2_MODULE: ModuleDef = ModuleDef {
    name: HOSTMOT2,
    params: HOSTMOT2_PARAMS,
    help: "Mesa HostMot2 firmware driver core (load before hm2_pci or hm2_test)",
    load: load_hostmot2,
};

/// The core's settings, alive while `hostmot2` is loaded in an instance.
pub(crate) struct Core {
    debug: Debug,
}

type CoreEntry = (String, Weak<Core>);

/// `hostmot2` loads per HAL instance (one process may host several).
static CORES: Mutex<Vec<CoreEntry>> = Mutex::new(Vec::new());

fn cores() -> std::sync::MutexGuard<'static, Vec<CoreEntry>> {
    CORES.lock().unwrap_or_else(|e| e.into_inner())
}

fn load_hostmot2(host: &Host, args: &ModuleArgs) -> hal_core::Result<()> {
    let flag = |name: &str| args.int(name).is_some_and(|v| v != 0);
    let core = Arc::new(Core {
        debug: Debug {
            idrom: flag("debug_idrom"),
            module_descriptors: flag("debug_module_descriptors"),
            pin_descriptors: flag("debug_pin_descriptors"),
            modules: flag("debug_modules"),
            use_serial_numbers: flag("use_serial_numbers"),
            sserial_baudrate: args
                .int("sserial_baudrate")
                .filter(|&b| b > 0)
                .map(|b| b.min(u32::MAX as i64) as u32),
        },
    });
    let log = host.rt_log();
    log.info(format_args!(
        "hm2: loading Mesa HostMot2 driver version 0.15"
    ));
    let mut b = host.new_rt_component(HOSTMOT2)?;
    // The hook owns the settings: they go when the component unloads.
    let held = core.clone();
    b.on_safe_state(move || {
        let _ = &held;
    });
    b.ready()?;
    let instance = host.instance().name().to_string();
    let mut c = cores();
    c.retain(|(i, w)| w.strong_count() > 0 && *i != instance);
    c.push((instance, Arc::downgrade(&core)));
    Ok(())
}

/// The core's settings in `host`, or the error a board driver gives when
/// `hostmot2` is not loaded.
pub(crate) fn core(host: &Host, module: &str) -> hal_core::Result<Arc<Core>> {
    let name = host.instance().name();
    cores()
        .iter()
        .find(|(i, _)| i == name)
        .and_then(|(_, w)| w.upgrade())
        .ok_or_else(|| HalError::module_failed(module, Hm2Error::CoreNotLoaded))
}

// ---------------------------------------------------------------------
// A board behind a lock its functions share.
// ---------------------------------------------------------------------

/// A registered board shared by its functions and the safe-state hook.
/// The functions of one instance never run at the same time (the host
/// serialises threads), so the lock is never contended: a function takes
/// it with `try_lock`, which never waits, and would skip its cycle rather
/// than block if it ever were.
pub struct SharedBoard {
    board: Mutex<Board>,
    /// What must live as long as the board (a PCI device's enable).
    _keep: Option<EnableGuard>,
}

impl SharedBoard {
    /// Shares `board`, keeping `keep` alive with it.
    pub fn new(board: Board, keep: Option<EnableGuard>) -> SharedBoard {
        SharedBoard {
            board: Mutex::new(board),
            _keep: keep,
        }
    }

    /// Runs `f` on the board unless another function holds it.
    #[inline]
    pub fn with<R>(&self, f: impl FnOnce(&mut Board) -> R) -> Option<R> {
        match self.board.try_lock() {
            Ok(mut b) => Some(f(&mut b)),
            Err(TryLockError::Poisoned(p)) => Some(f(&mut p.into_inner())),
            Err(TryLockError::WouldBlock) => None,
        }
    }
}

impl SafeState for SharedBoard {
    fn go_safe(&self) {
        let mut b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.go_safe();
    }
}

// ---------------------------------------------------------------------
// Registering boards (hm2_pci and hm2_test).
// ---------------------------------------------------------------------

/// Where a board's registers are.
pub enum Source {
    /// A PCI board, opened.
    Pci(Box<pci::OpenedBoard>),
    /// A simulated board.
    Sim(Arc<SimHm2>),
    /// A fixed register image (hm2_test).
    Image(Vec<u32>),
    /// A board on the network (hm2_eth), probed.
    Eth(Box<crate::eth::EthTransport>),
}

/// A board to register: its llio, where it is, and what to say when it
/// succeeds or fails.
pub struct Candidate {
    /// The llio.
    pub llio: Llio,
    /// Its registers.
    pub source: Source,
    /// Where it is, for the success line (`at 0000:02:00.0`).
    pub place: String,
    /// The failure line (`hm2_pci: board at 0000:02:00.0 fails HM2 registration`).
    pub fails: String,
}

/// The config strings' item for board `i`.
fn config_for(configs: &[String], i: usize) -> &str {
    configs.get(i).map_or("", String::as_str)
}

/// Registers every candidate on one new component `comp`, all or nothing.
pub fn register_boards(
    host: &Host,
    module: &str,
    comp: &str,
    candidates: Vec<Candidate>,
    configs: &[String],
) -> hal_core::Result<()> {
    let debug = core(host, module)?.debug;
    let log = host.rt_log();
    let mut b = host.new_rt_component(comp)?;
    let mut shared = Vec::new();
    let mut sims = Vec::new();
    for (i, cand) in candidates.into_iter().enumerate() {
        let blog = BoardLog::new(log.clone(), &cand.llio.name);
        let name = cand.llio.name.clone();
        let fails = cand.fails.clone();
        let fail = |e: Hm2Error, blog: &BoardLog| {
            for line in e.to_string().lines() {
                blog.say(MsgLevel::Err, format_args!("{line}"));
            }
            log.err(format_args!("{fails}"));
            host.flush_rt_log();
            HalError::module_failed(
                module,
                Hm2Error::Registration {
                    fails: fails.clone(),
                    source: Box::new(e),
                },
            )
        };
        let config = config::parse(config_for(configs, i)).map_err(|e| fail(e, &blog))?;
        let (transport, sim, keep): (Box<dyn Transport>, _, _) = match cand.source {
            Source::Pci(opened) => {
                let o = *opened;
                (
                    Box::new(WindowTransport::new(o.window)),
                    None,
                    Some(o.enabled),
                )
            }
            Source::Sim(board) => (
                Box::new(WindowTransport::new(board.clone())),
                Some(board),
                None,
            ),
            Source::Image(img) => (Box::new(ImageTransport::new(img, &name)), None, None),
            Source::Eth(mut t) => {
                t.errors().export(b.component(), &name)?;
                (t, None, None)
            }
        };
        let mut msgs = MessageLog::default();
        let board = Board::open(
            b.component(),
            cand.llio,
            &config,
            debug,
            transport,
            blog.clone(),
            &mut msgs,
        );
        print_messages(&msgs, &blog);
        let board = Arc::new(SharedBoard::new(board.map_err(|e| fail(e, &blog))?, keep));
        export_functions(&mut b, &name, &board, sim.clone())?;
        log.info(format_args!(
            "{name}: initialized AnyIO board {}",
            cand.place
        ));
        if let Some(s) = sim {
            sims.push((name, s));
        }
        shared.push(board);
    }
    fault::install(&mut b, shared);
    b.ready()?;
    for (name, s) in &sims {
        layer_sim::publish(host.instance().name(), name, s);
    }
    host.flush_rt_log();
    Ok(())
}

/// Prints registration messages: the debug dumps unconditionally (they
/// exist only when asked for, and LinuxCNC prints them so), the rest
/// through the log's level.
fn print_messages(msgs: &MessageLog, blog: &BoardLog) {
    for m in msgs.messages() {
        if m.level == MsgLevel::Dbg {
            eprintln!("{}{}", blog.prefix(), m.text);
        } else {
            blog.say(m.level, format_args!("{}", m.text));
        }
    }
}

fn export_functions(
    b: &mut RtComponentBuilder<'_>,
    name: &str,
    board: &Arc<SharedBoard>,
    sim: Option<Arc<SimHm2>>,
) -> hal_core::Result<()> {
    let (split, threadsafe, watchdog) = board
        .with(|bd| (bd.split_read(), bd.threadsafe(), bd.has_watchdog()))
        .unwrap_or((false, true, false));
    let bd = board.clone();
    b.funct(&format!("{name}.read"), true, move |ctx| {
        if let Some(s) = &sim {
            // Simulated time moves one thread period per read: runs are
            // identical whatever the host's load.
            s.advance(ctx.period().max(0) as u64);
        }
        bd.with(|bd| bd.read());
    })?;
    let bd = board.clone();
    b.funct(&format!("{name}.write"), true, move |ctx| {
        bd.with(|bd| bd.write(ctx.period()));
    })?;
    if split {
        let bd = board.clone();
        b.funct(&format!("{name}.read-request"), true, move |_| {
            bd.with(|bd| bd.read_request());
        })?;
    }
    if watchdog {
        let bd = board.clone();
        b.funct(&format!("{name}.pet_watchdog"), false, move |_| {
            bd.with(|bd| bd.pet_watchdog());
        })?;
    }
    if threadsafe {
        let bd = board.clone();
        b.funct(&format!("{name}.read_gpio"), true, move |_| {
            bd.with(|bd| bd.read_gpio());
        })?;
        let bd = board.clone();
        b.funct(&format!("{name}.write_gpio"), true, move |ctx| {
            bd.with(|bd| bd.write_gpio(ctx.period()));
        })?;
    }
    Ok(())
}

// ---------------------------------------------------------------------
// hm2_pci
// ---------------------------------------------------------------------

const HM2_PCI: &str = "hm2_pci";

const HM2_PCI_PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "config",
        kind: ParamKind::StrArray(MAX_BOARDS),
        help: "hostmot2 config strings, one per board in probe order (see hostmot2(9))",
    },
    ParamDecl {
        name: "sim",
        kind: ParamKind::StrArray(MAX_BOARDS),
        help:
            "simulated boards instead of the PCI bus: 5i25, 6i25, 5i24 or 5i25-7i77, one per board",
    },
];

/// The `hm2_pci` module.
pub static HM2_PCI_MODULE: ModuleDef = ModuleDef {
    name: HM2_PCI,
    params: HM2_PCI_PARAMS,
    help: "Mesa PCI Anything I/O boards with HostMot2 firmware (or simulated ones: sim=5i25)",
    load: load_hm2_pci,
};

fn load_hm2_pci(host: &Host, args: &ModuleArgs) -> hal_core::Result<()> {
    load_pci(host, args, &Sysfs::system(), pci::BOARDS)
}

/// `hm2_pci` with the PCI bus at `sysfs` and the board table `boards`
/// (tests point these at a fake tree or the VM rig's device).
pub fn load_pci(
    host: &Host,
    args: &ModuleArgs,
    sysfs: &Sysfs,
    boards: &[PciBoard],
) -> hal_core::Result<()> {
    core(host, HM2_PCI)?;
    let params = hal_driver::params::Params::new(HM2_PCI, args);
    let configs = args.str_array("config").to_vec();
    let sims = args.str_array("sim");
    let mut counts: HashMap<String, usize> = HashMap::new();
    let mut next = |board: &str| {
        let n = counts.entry(board.to_string()).or_insert(0);
        *n += 1;
        *n - 1
    };
    let candidates: Vec<Candidate> = if !sims.is_empty() {
        let mut v = Vec::new();
        for (i, s) in sims.iter().enumerate() {
            let spec = boards::preset(s)
                .ok_or_else(|| {
                    params.item_error(
                        "sim",
                        i,
                        s,
                        format!("not a simulated board ({})", boards::PRESETS.join(", ")),
                    )
                })
                .for_module(HM2_PCI)?;
            v.push(sim_candidate(spec, next(s), s));
        }
        v
    } else {
        pci::open_all(sysfs, boards)
            .map_err(|e| match e {
                hal_driver::DriverError::PciNotFound { wanted, searched } => {
                    HalError::module_failed(HM2_PCI, Hm2Error::NoPciCard { wanted, searched })
                }
                e => e.into_hal(HM2_PCI),
            })?
            .into_iter()
            .map(|o| Candidate {
                llio: o.kind.llio(next(o.kind.board)),
                place: format!("at {}", o.device.address),
                fails: format!(
                    "hm2_pci: board at {} fails HM2 registration",
                    o.device.address
                ),
                source: Source::Pci(Box::new(o)),
            })
            .collect()
    };
    if candidates.len() > MAX_BOARDS {
        return Err(HalError::module_failed(
            HM2_PCI,
            Hm2Error::TooManyBoards {
                found: candidates.len(),
                max: MAX_BOARDS,
            },
        ));
    }
    register_boards(host, HM2_PCI, HM2_PCI, candidates, &configs)
}

/// A simulated board of firmware `spec`, the `n`th of its type, with the
/// machine its preset connects.
fn sim_candidate(spec: FirmwareSpec, n: usize, preset: &str) -> Candidate {
    let llio = spec.llio(n);
    let (board, _) = sim::board(spec, Box::new(machine::preset(preset)));
    Candidate {
        fails: format!(
            "hm2_pci: simulated board {} fails HM2 registration",
            llio.name
        ),
        llio,
        source: Source::Sim(board),
        place: "(simulated)".into(),
    }
}

// ---------------------------------------------------------------------
// hm2_test
// ---------------------------------------------------------------------

const HM2_TEST: &str = "hm2_test";

const HM2_TEST_PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "test_pattern",
        kind: ParamKind::Int,
        help: "which broken register image to serve (0 to 14)",
    },
    ParamDecl {
        name: "config",
        kind: ParamKind::StrArray(1),
        help: "hostmot2 config string",
    },
];

/// The `hm2_test` module: LinuxCNC's test driver, a board serving a
/// fixed register image whose registration must fail.
pub static HM2_TEST_MODULE: ModuleDef = ModuleDef {
    name: HM2_TEST,
    params: HM2_TEST_PARAMS,
    help: "HostMot2 test driver: broken register images for the IDROM checks",
    load: load_hm2_test,
};

fn load_hm2_test(host: &Host, args: &ModuleArgs) -> hal_core::Result<()> {
    core(host, HM2_TEST)?;
    let n = args.int("test_pattern").unwrap_or(0);
    let log = host.rt_log();
    log.info(format_args!(
        "hm2_test: loading HostMot2 test driver with test pattern {n}"
    ));
    let Some((llio, image)) = u32::try_from(n).ok().and_then(test_patterns::pattern) else {
        log.err(format_args!("hm2_test: unknown test pattern {n}"));
        host.flush_rt_log();
        return Err(HalError::module_failed(
            HM2_TEST,
            Hm2Error::UnknownTestPattern(n),
        ));
    };
    log.info(format_args!(
        "hm2: no firmware specified in config modparam!  the board had better have firmware configured already, or this won't work"
    ));
    let candidate = Candidate {
        fails: format!("{}: hm2_test fails HM2 registration", llio.name),
        llio,
        source: Source::Image(image),
        place: format!("(hm2 test-pattern {n})"),
    };
    register_boards(
        host,
        HM2_TEST,
        HM2_TEST,
        vec![candidate],
        args.str_array("config"),
    )
}

/// Every module this crate provides, for the host's registry.
pub fn modules() -> [&'static ModuleDef; 4] {
    [
        &HOSTMOT2_MODULE,
        &HM2_PCI_MODULE,
        &HM2_TEST_MODULE,
        &crate::eth::hal::HM2_ETH_MODULE,
    ]
}
