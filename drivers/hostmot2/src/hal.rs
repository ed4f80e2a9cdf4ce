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
use std::path::PathBuf;
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{HalError, Host, MsgLevel};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv, PublishedWord};
use hal_driver::pci::{EnableGuard, Sysfs};
use hal_driver::ForModule;

use crate::board::Board;
use crate::config;
use crate::error::Hm2Error;
use crate::firmware::Debug;
use crate::image::{FirmwareSpec, ImageTransport};
use crate::llio::Llio;
use crate::log::{BoardLog, MessageLog};
use crate::pci::{self, PciBoard};
pub use crate::shared_board::{publish_board, SharedBoard};
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

/// hostmot2's module parameters (one table, read by both hosts).
#[macro_export]
macro_rules! hostmot2_params {
    ($($then:tt)*) => { $($then)*! {
        debug_idrom: Int = "log the IDROM header of every board",
        debug_module_descriptors: Int = "log every module descriptor",
        debug_pin_descriptors: Int = "log every pin descriptor",
        debug_modules: Int = "log what each module uses",
        use_serial_numbers: Int = "name Smart Serial cards hm2_<card>.<unit number> instead of by board, port and channel",
        sserial_baudrate: Int = "set every Smart Serial channel to this baud rate at load (-1: leave it); 115200 is setup mode: any Mesa remote is found for setsserial flash, gets no pins and is not started",
    } };
}

/// The `hostmot2` driver: the core the board drivers register with; it
/// holds the debugging switches.
#[derive(Debug)]
pub struct HalHostmot2;

/// The `hostmot2` module.
pub static HOSTMOT2_MODULE: ModuleDef = module::module_def::<HalHostmot2>();

/// The core's settings, published for the board drivers while
/// `hostmot2` is loaded.
pub struct CoreLoaded {
    _published: PublishedWord,
}

impl DriverModule for HalHostmot2 {
    const NAME: &'static str = HOSTMOT2;
    const HELP: &'static str =
        "Mesa HostMot2 firmware driver core (load before hm2_pci or hm2_test)";
    const PARAMS: &'static [ParamDecl] = hostmot2_params!(hal_driver::param_table);
    type Opened = CoreLoaded;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<CoreLoaded> {
        let flag = |name: &str| args.int(name).is_some_and(|v| v != 0);
        let debug = Debug {
            idrom: flag("debug_idrom"),
            module_descriptors: flag("debug_module_descriptors"),
            pin_descriptors: flag("debug_pin_descriptors"),
            modules: flag("debug_modules"),
            use_serial_numbers: flag("use_serial_numbers"),
            sserial_baudrate: args
                .int("sserial_baudrate")
                .filter(|&b| b > 0)
                .map(|b| b.min(u32::MAX as i64) as u32),
        };
        env.log().info(format_args!(
            "hm2: loading Mesa HostMot2 driver version 0.15"
        ));
        Ok(CoreLoaded {
            _published: env.publish_word(HOSTMOT2, core_word(debug)),
        })
    }

    fn export<H: DriverHost>(core: CoreLoaded, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        let comp = ex.component(HOSTMOT2)?;
        // The component holds the settings: they go when it unloads.
        ex.keep(comp, core);
        Ok(())
    }
}

/// The settings as the word the core publishes: the five switches in
/// bits 0 to 4, bit 5 set when a baud rate is given, the rate in bits 32
/// to 63.
fn core_word(d: Debug) -> u64 {
    let bits = [
        d.idrom,
        d.module_descriptors,
        d.pin_descriptors,
        d.modules,
        d.use_serial_numbers,
    ];
    let mut w = bits
        .iter()
        .enumerate()
        .fold(0u64, |w, (i, &b)| w | (u64::from(b) << i));
    if let Some(baud) = d.sserial_baudrate {
        w |= 1 << 5 | u64::from(baud) << 32;
    }
    w
}

/// The settings of a [`core_word`].
fn core_of(w: u64) -> Debug {
    let bit = |i: u32| w >> i & 1 == 1;
    Debug {
        idrom: bit(0),
        module_descriptors: bit(1),
        pin_descriptors: bit(2),
        modules: bit(3),
        use_serial_numbers: bit(4),
        sserial_baudrate: bit(5).then_some((w >> 32) as u32),
    }
}

/// The core's settings in the HAL `env` loads into, or the error a board
/// driver gives when `hostmot2` is not loaded.
pub(crate) fn core(env: &LoadEnv, module: &str) -> hal_core::Result<Debug> {
    env.word(HOSTMOT2)
        .map(core_of)
        .ok_or_else(|| HalError::module_failed(module, Hm2Error::CoreNotLoaded))
}

// ---------------------------------------------------------------------
// Registering boards (hm2_pci, hm2_test and hm2_eth).
// ---------------------------------------------------------------------

/// Where a board's registers are.
pub enum Source {
    /// A PCI board, opened.
    Pci(Box<pci::OpenedBoard>),
    /// A simulated board.
    Sim(Arc<SimHm2>),
    /// A simulated PLX card whose FPGA is not loaded yet: it becomes a
    /// [`Source::Sim`] running the design `firmware=` loads.
    SimPlx(Box<crate::pci_fpga::SimPlxCard>),
    /// A fixed register image (hm2_test).
    Image(Vec<u32>),
    /// A board on the network (hm2_eth), probed; its HAL objects are
    /// made in the host it registers in.
    Eth(Box<crate::eth::EthTransport>),
    /// A board on a parallel port (hm2_7i43, hm2_7i90), set up for EPP.
    Epp(Box<crate::epp::EppSource>),
    /// A board on an SPI device (hm2_spi, hm2_rpspi), identified.
    Spi(Box<crate::spi::SpiSource>),
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

/// What a board driver's `open` found: the boards to register, their
/// config strings, and the core's settings.
pub struct Boards {
    module: &'static str,
    debug: Debug,
    candidates: Vec<Candidate>,
    configs: Vec<String>,
    firmware_dir: Option<PathBuf>,
    /// The HAL's name, for the board registry.
    instance: String,
}

impl Boards {
    /// The boards `module` registers into the HAL `env` loads into, with
    /// their config strings and the core's settings.
    pub fn new(
        env: &LoadEnv,
        module: &'static str,
        debug: Debug,
        candidates: Vec<Candidate>,
        configs: Vec<String>,
    ) -> Boards {
        Boards {
            module,
            debug,
            candidates,
            configs,
            firmware_dir: None,
            instance: env.instance().to_string(),
        }
    }

    /// Where `firmware=` files are read, instead of /lib/firmware.
    pub fn with_firmware_dir(mut self, dir: Option<PathBuf>) -> Boards {
        self.firmware_dir = dir;
        self
    }
}

/// The config strings' item for board `i`.
fn config_for(configs: &[String], i: usize) -> &str {
    configs.get(i).map_or("", String::as_str)
}

/// Registers every board on one new component named after the module,
/// all or nothing.
pub fn export_boards<H: DriverHost>(
    found: Boards,
    ex: &mut Exporter<'_, H>,
) -> hal_core::Result<()> {
    let Boards {
        module,
        debug,
        candidates,
        configs,
        firmware_dir,
        instance,
    } = found;
    let log = ex.log();
    let comp = ex.component(module)?;
    let mut shared = Vec::new();
    for (i, cand) in candidates.into_iter().enumerate() {
        let blog = BoardLog::new(log.clone(), &cand.llio.name);
        let name = cand.llio.name.clone();
        let fails = cand.fails.clone();
        let fail = |e: Hm2Error, blog: &BoardLog, ex: &Exporter<'_, H>| {
            for line in e.to_string().lines() {
                blog.say(MsgLevel::Err, format_args!("{line}"));
            }
            log.err(format_args!("{fails}"));
            ex.flush_log();
            HalError::module_failed(
                module,
                Hm2Error::Registration {
                    fails: fails.clone(),
                    source: Box::new(e),
                },
            )
        };
        let config = config::parse(config_for(&configs, i)).map_err(|e| fail(e, &blog, ex))?;
        let mut msgs = MessageLog::default();
        let source =
            crate::pci_fpga::configure(cand.source, &config, firmware_dir.as_deref(), &mut msgs);
        print_messages(&msgs, &blog);
        msgs = MessageLog::default();
        let source = source.map_err(|e| fail(e, &blog, ex))?;
        let mut llio = cand.llio;
        if let Source::Epp(epp) = &source {
            // The 7I43's CPLD said which FPGA the card carries.
            if let Some(part) = epp.fpga_part {
                llio.fpga_part = part.into();
            }
        }
        let (transport, sim, keep) = match transport_of(source, ex, comp, &name)? {
            Ok(opened) => opened,
            Err(e) => return Err(fail(e, &blog, ex)),
        };
        let board = Board::<H>::open(
            ex.pins(comp),
            llio,
            &config,
            debug,
            transport,
            blog.clone(),
            &mut msgs,
        );
        print_messages(&msgs, &blog);
        let board = board.map_err(|e| fail(e, &blog, ex))?;
        let board = Arc::new(SharedBoard::new(board, keep));
        export_functions(ex, comp, &name, &board, sim.clone())?;
        let access: Arc<dyn crate::registry::SserialAccess> = board.clone();
        crate::registry::register(&instance, &name, &access);
        log.info(format_args!(
            "{name}: initialized AnyIO board {}",
            cand.place
        ));
        if let Some(s) = sim {
            ex.publish_sim(&name, &s);
        }
        shared.push(board);
    }
    ex.safe_state(comp, shared);
    ex.flush_log();
    Ok(())
}

/// A board's transport, its simulator (when simulated) and what keeps
/// its device enabled.
type Opened = (Box<dyn Transport>, Option<Arc<SimHm2>>, Option<EnableGuard>);

/// Opens the transport to a board's registers. The outer error is HAL's
/// (an Ethernet board's error pins refused); the inner one fails the
/// board's registration.
fn transport_of<H: DriverHost>(
    source: Source,
    ex: &mut Exporter<'_, H>,
    comp: hal_driver::CompId,
    name: &str,
) -> hal_core::Result<Result<Opened, Hm2Error>> {
    Ok(Ok(match source {
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
        Source::Image(img) => (Box::new(ImageTransport::new(img, name)), None, None),
        Source::SimPlx(_) => {
            return Ok(Err(Hm2Error::SimFpgaNotRunning {
                what: "was not loaded",
            }))
        }
        Source::Epp(e) => {
            let e = *e;
            (Box::new(e.transport), e.sim, None)
        }
        Source::Spi(s) => {
            let s = *s;
            (Box::new(s.transport), s.sim, None)
        }
        Source::Eth(t) => {
            let mut t = t.into_host::<H>();
            t.errors().export(ex.pins(comp), name)?;
            if let Some(board) = t.sim_board() {
                // Tests and tools find the board under its HAL name.
                ex.publish_sim(name, &board.clone());
            }
            (Box::new(t), None, None)
        }
    }))
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

fn export_functions<H: DriverHost>(
    ex: &mut Exporter<'_, H>,
    comp: hal_driver::CompId,
    name: &str,
    board: &Arc<SharedBoard<H>>,
    sim: Option<Arc<SimHm2>>,
) -> hal_core::Result<()> {
    let (split, threadsafe, watchdog) = board
        .with(|bd| (bd.split_read(), bd.threadsafe(), bd.has_watchdog()))
        .unwrap_or((false, true, false));
    let bd = board.clone();
    ex.funct(comp, &format!("{name}.read"), true, move |ctx| {
        if let Some(s) = &sim {
            // Simulated time moves one thread period per read: runs are
            // identical whatever the host's load.
            s.advance(ctx.period().max(0) as u64);
        }
        bd.with(|bd| bd.read());
    })?;
    let bd = board.clone();
    ex.funct(comp, &format!("{name}.write"), true, move |ctx| {
        bd.with(|bd| bd.write(ctx.period()));
    })?;
    if split {
        let bd = board.clone();
        ex.funct(comp, &format!("{name}.read-request"), true, move |_| {
            bd.with(|bd| bd.read_request());
        })?;
    }
    if watchdog {
        let bd = board.clone();
        ex.funct(comp, &format!("{name}.pet_watchdog"), false, move |_| {
            bd.with(|bd| bd.pet_watchdog());
        })?;
    }
    if threadsafe {
        let bd = board.clone();
        ex.funct(comp, &format!("{name}.read_gpio"), true, move |_| {
            bd.with(|bd| bd.read_gpio());
        })?;
        let bd = board.clone();
        ex.funct(comp, &format!("{name}.write_gpio"), true, move |ctx| {
            bd.with(|bd| bd.write_gpio(ctx.period()));
        })?;
    }
    Ok(())
}

// ---------------------------------------------------------------------
// hm2_pci
// ---------------------------------------------------------------------

const HM2_PCI: &str = "hm2_pci";

/// hm2_pci's module parameters (one table, read by both hosts); the
/// arrays hold [`MAX_BOARDS`] items.
#[macro_export]
macro_rules! hm2_pci_params {
    ($($then:tt)*) => { $($then)*! {
        config: StrArray(8) = "hostmot2 config strings, one per board in probe order (see hostmot2(9))",
        sim: StrArray(8) = "simulated boards instead of the PCI bus: 5i25, 6i25, 5i24, 5i25-7i77, 5i25-pktuart, or a PLX card (5i20, 4i65, 5i22, 5i23, 4i68, 3x20, ...) loaded with firmware=, one per board",
        firmware_dir: Str = "where firmware= files are (default /lib/firmware); for simulated PLX cards, where to read their bitfiles instead of the simulator's own",
    } };
}

/// The `hm2_pci` driver: Mesa's PCI boards, or simulated ones.
#[derive(Debug)]
pub struct HalHm2Pci;

/// The `hm2_pci` module.
pub static HM2_PCI_MODULE: ModuleDef = module::module_def::<HalHm2Pci>();

impl DriverModule for HalHm2Pci {
    const NAME: &'static str = HM2_PCI;
    const HELP: &'static str =
        "Mesa PCI Anything I/O boards with HostMot2 firmware (or simulated ones: sim=5i25)";
    const PARAMS: &'static [ParamDecl] = hm2_pci_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        open_pci(args, env, &Sysfs::system(), pci::BOARDS)
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

/// `hm2_pci` with the PCI bus at `sysfs` and the board table `boards`
/// (tests point these at a fake tree or the VM rig's device), into our
/// host.
pub fn load_pci(
    host: &Host,
    args: &ModuleArgs,
    sysfs: &Sysfs,
    boards: &[PciBoard],
) -> hal_core::Result<()> {
    let found = open_pci(args, &module::env(host), sysfs, boards)?;
    module::load_opened::<HalHm2Pci>(host, found)
}

/// Finds (or simulates) the boards `args` ask for on the bus at `sysfs`.
fn open_pci(
    args: &ModuleArgs,
    env: &LoadEnv,
    sysfs: &Sysfs,
    boards: &[PciBoard],
) -> hal_core::Result<Boards> {
    let debug = core(env, HM2_PCI)?;
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
        sim_candidates(sims, &params, &mut next)?
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
    Ok(Boards {
        module: HM2_PCI,
        debug,
        candidates,
        configs,
        instance: env.instance().to_string(),
        firmware_dir: args
            .str("firmware_dir")
            .filter(|d| !d.is_empty())
            .map(PathBuf::from),
    })
}

/// The simulated boards `sim=` names; `next` numbers each board of a type.
fn sim_candidates(
    sims: &[String],
    params: &hal_driver::params::Params<'_>,
    next: &mut impl FnMut(&str) -> usize,
) -> hal_core::Result<Vec<Candidate>> {
    let mut v = Vec::new();
    for (i, s) in sims.iter().enumerate() {
        if let Some(card) = crate::pci_fpga::SimPlxCard::new(s) {
            let llio = card.board.llio(next(card.board.board));
            v.push(Candidate {
                fails: format!(
                    "hm2_pci: simulated board {} fails HM2 registration",
                    llio.name
                ),
                llio,
                source: Source::SimPlx(Box::new(card)),
                place: "(simulated)".into(),
            });
            continue;
        }
        let spec = boards::preset(s)
            .ok_or_else(|| {
                params.item_error(
                    "sim",
                    i,
                    s,
                    format!("not a simulated board ({})", boards::pci_sim_names()),
                )
            })
            .for_module(HM2_PCI)?;
        v.push(sim_candidate(spec, next(s), s));
    }
    Ok(v)
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

/// hm2_test's module parameters (one table, read by both hosts).
#[macro_export]
macro_rules! hm2_test_params {
    ($($then:tt)*) => { $($then)*! {
        test_pattern: Int = "which broken register image to serve (0 to 14)",
        config: StrArray(1) = "hostmot2 config string",
    } };
}

/// The `hm2_test` driver: LinuxCNC's test driver, a board serving a
/// fixed register image whose registration must fail.
#[derive(Debug)]
pub struct HalHm2Test;

/// The `hm2_test` module.
pub static HM2_TEST_MODULE: ModuleDef = module::module_def::<HalHm2Test>();

impl DriverModule for HalHm2Test {
    const NAME: &'static str = HM2_TEST;
    const HELP: &'static str = "HostMot2 test driver: broken register images for the IDROM checks";
    const PARAMS: &'static [ParamDecl] = hm2_test_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        let debug = core(env, HM2_TEST)?;
        let n = args.int("test_pattern").unwrap_or(0);
        let log = env.log();
        log.info(format_args!(
            "hm2_test: loading HostMot2 test driver with test pattern {n}"
        ));
        let Some((llio, image)) = u32::try_from(n).ok().and_then(test_patterns::pattern) else {
            log.err(format_args!("hm2_test: unknown test pattern {n}"));
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
        Ok(Boards {
            module: HM2_TEST,
            debug,
            candidates: vec![candidate],
            configs: args.str_array("config").to_vec(),
            firmware_dir: None,
            instance: env.instance().to_string(),
        })
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

/// Every module this crate provides, for the host's registry.
pub fn modules() -> [&'static ModuleDef; 10] {
    [
        &HOSTMOT2_MODULE,
        &HM2_PCI_MODULE,
        &HM2_TEST_MODULE,
        &crate::eth::hal::HM2_ETH_MODULE,
        &crate::epp::hal::HM2_7I43_MODULE,
        &crate::epp::hal::HM2_7I90_MODULE,
        &crate::spi::hal::HM2_SPI_MODULE,
        &crate::spi::hal::HM2_RPSPI_MODULE,
        &crate::setsserial::SETSSERIAL_MODULE,
        &crate::modbus::hal::HM2_MODBUS_MODULE,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_core_word_carries_every_switch() {
        let all = Debug {
            idrom: true,
            module_descriptors: false,
            pin_descriptors: true,
            modules: false,
            use_serial_numbers: true,
            sserial_baudrate: Some(2_500_000),
        };
        let back = core_of(core_word(all));
        assert_eq!(
            (back.idrom, back.module_descriptors, back.pin_descriptors),
            (true, false, true)
        );
        assert_eq!((back.modules, back.use_serial_numbers), (false, true));
        assert_eq!(back.sserial_baudrate, Some(2_500_000));
        assert_eq!(core_of(core_word(Debug::default())).sserial_baudrate, None);
    }

    #[test]
    fn the_tables_hold_max_boards() {
        assert_eq!(
            HM2_PCI_MODULE.params[0].kind,
            hal_core::ParamKind::StrArray(MAX_BOARDS)
        );
    }
}
