//! The `hm2_7i43` and `hm2_7i90` loadrt modules: one EPP transport per
//! board on its parallel port (raw port I/O, or a simulated port with a
//! simulated board with `sim=`), registered with the hostmot2 core.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::HalError;
use hal_driver::bus::{IopermPorts, PortBus, PortRange};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;
use hal_driver::sim::SimBoard;
use hal_driver::{DriverError, ForModule};

use super::transport::EppTransport;
use super::{reg, HI_OFFSET};
use crate::error::Hm2Error;
use crate::hal::{core, export_boards, Boards, Candidate, Source};
use crate::llio::Llio;
use crate::sim::epp::{self as sim_epp, EppPortModel};
use crate::sim::{self, machine};

/// Most boards one load drives (LinuxCNC's `HM2_7I43_MAX_BOARDS`, and
/// the 7I90's the same).
pub const MAX_EPP_BOARDS: usize = 4;
/// The first board's port when `ioaddr` names none.
pub const DEFAULT_IOADDR: u16 = 0x378;

/// The parameters of both EPP modules (one table, read by both hosts);
/// the arrays hold [`MAX_EPP_BOARDS`] items.
#[macro_export]
macro_rules! hm2_epp_params {
    ($($then:tt)*) => { $($then)*! {
        ioaddr: IntArray(4) = "the parallel ports' base addresses, one per board (default 0x378)",
        ioaddr_hi: IntArray(4) = "the ports' ECR blocks: 0 = ioaddr + 0x400 (default), -1 = the port has no ECR",
        epp_wide: IntArray(4) = "1 (default): 32-bit EPP accesses; 0: byte accesses only",
        config: StrArray(4) = "hostmot2 config strings, one per board (see hostmot2(9))",
        debug_epp: Int = "LinuxCNC prints every EPP cycle; here the load says so and the simulator's access log shows them",
        sim: StrArray(4) = "simulated boards behind simulated ports instead of real ones (7i43, 7i43-2 or 7i90), one per board",
        firmware_dir: Str = "where firmware= files are (default /lib/firmware); for a simulated 7i43, where to read its bitfiles instead of the simulator's own",
    } };
}

/// What tells the two EPP boards apart.
#[derive(Debug, Clone, Copy)]
pub struct EppBoardKind {
    /// The module (`hm2_7i43`).
    pub module: &'static str,
    /// The board (`7i43`): the HAL prefix is `hm2_<board>.<n>`.
    pub board: &'static str,
    /// Connector names in I/O order.
    pub connectors: &'static [&'static str],
    /// LEDs.
    pub leds: u32,
    /// The FPGA part.
    pub fpga_part: &'static str,
}

/// The 7I43: two 24-pin connectors (P4, P3), 8 LEDs.
pub const SEVEN_I43: EppBoardKind = EppBoardKind {
    module: "hm2_7i43",
    board: "7i43",
    connectors: &["P4", "P3"],
    leds: 8,
    fpga_part: "3s400tq144",
};

/// The 7I90HD: three 24-pin connectors (P1, P2, P3), 2 LEDs.
pub const SEVEN_I90: EppBoardKind = EppBoardKind {
    module: "hm2_7i90",
    board: "7i90",
    connectors: &["P1", "P2", "P3"],
    leds: 2,
    fpga_part: "6slx9tq144",
};

impl EppBoardKind {
    /// Board `n`'s llio.
    pub fn llio(&self, n: usize) -> Llio {
        Llio {
            name: format!("hm2_{}.{n}", self.board),
            connectors: self.connectors.iter().map(|c| c.to_string()).collect(),
            pins_per_connector: 24,
            num_leds: self.leds,
            fpga_part: self.fpga_part.into(),
        }
    }
}

/// The `hm2_7i43` driver.
#[derive(Debug)]
pub struct HalHm2_7i43;

/// The `hm2_7i90` driver.
#[derive(Debug)]
pub struct HalHm2_7i90;

/// The `hm2_7i43` module.
pub static HM2_7I43_MODULE: ModuleDef = module::module_def::<HalHm2_7i43>();
/// The `hm2_7i90` module.
pub static HM2_7I90_MODULE: ModuleDef = module::module_def::<HalHm2_7i90>();

impl DriverModule for HalHm2_7i43 {
    const NAME: &'static str = "hm2_7i43";
    const HELP: &'static str =
        "Mesa 7I43 EPP Anything I/O board with HostMot2 firmware (or a simulated one: sim=7i43)";
    const PARAMS: &'static [ParamDecl] = hm2_epp_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        open_epp(&SEVEN_I43, args, env, &real_port)
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

impl DriverModule for HalHm2_7i90 {
    const NAME: &'static str = "hm2_7i90";
    const HELP: &'static str =
        "Mesa 7I90 EPP Anything I/O board with HostMot2 firmware (or a simulated one: sim=7i90)";
    const PARAMS: &'static [ParamDecl] = hm2_epp_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        open_epp(&SEVEN_I90, args, env, &real_port)
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

/// Where board `i`'s port is: base, ECR block (if any), wide accesses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortPlace {
    /// The base address.
    pub base: u16,
    /// The ECR block, if the port has one.
    pub base_hi: Option<u16>,
    /// 32-bit data accesses.
    pub wide: bool,
}

/// Board `i`'s port from the `ioaddr`, `ioaddr_hi` and `epp_wide`
/// arrays (LinuxCNC's defaults where an item is missing).
fn place_of(params: &Params<'_>, args: &ModuleArgs, i: usize) -> Result<PortPlace, DriverError> {
    let item = |name: &str| args.int_array(name).get(i).copied();
    // Addresses as hex, as they are written; anything else as given.
    let bad = |name: &str, v: i64, why: &str| {
        let shown = if name.starts_with("ioaddr") && v >= 0 {
            format!("{v:#x}")
        } else {
            v.to_string()
        };
        params.item_error(name, i, &shown, why)
    };
    let base = match item("ioaddr") {
        None => DEFAULT_IOADDR,
        Some(v) => u16::try_from(v)
            .ok()
            .filter(|b| *b != 0 && b.checked_add(reg::SPAN - 1).is_some())
            .ok_or_else(|| bad("ioaddr", v, "not a port address (0x1 .. 0xfff8)"))?,
    };
    let base_hi = match item("ioaddr_hi").unwrap_or(0) {
        -1 => None,
        0 => Some(base.checked_add(HI_OFFSET).ok_or_else(|| {
            bad(
                "ioaddr",
                base as i64,
                "ioaddr + 0x400 is past 0xffff: give ioaddr_hi",
            )
        })?),
        v => Some(
            u16::try_from(v)
                .ok()
                .filter(|h| h.checked_add(reg::SPAN_HI - 1).is_some())
                .ok_or_else(|| bad("ioaddr_hi", v, "not a port address, 0 or -1"))?,
        ),
    };
    let wide = match item("epp_wide").unwrap_or(1) {
        0 => false,
        1 => true,
        v => return Err(bad("epp_wide", v, "must be 0 or 1")),
    };
    Ok(PortPlace {
        base,
        base_hi,
        wide,
    })
}

/// The real port at `place`: raw port I/O over its two register blocks.
fn real_port(place: PortPlace) -> Result<Arc<dyn PortBus>, Hm2Error> {
    let range = |b: u16, n: u16| {
        PortRange::new(b, n).map_err(|e| Hm2Error::EppPort {
            base: place.base,
            reason: e.to_string(),
        })
    };
    let mut ranges = vec![range(place.base, reg::SPAN)?];
    if let Some(hi) = place.base_hi {
        ranges.push(range(hi, reg::SPAN_HI)?);
    }
    let ports = IopermPorts::open(&ranges).map_err(|e| Hm2Error::EppPort {
        base: place.base,
        reason: format!(
            "{e} (raw port I/O needs CAP_SYS_RAWIO: setcap cap_sys_rawio+ep on the HAL host binary)"
        ),
    })?;
    Ok(Arc::new(ports))
}

/// A simulated board of preset `name` behind a simulated port at
/// `place`: the transport, and the board for the HAL functions.
pub fn sim_port(
    name: &str,
    place: PortPlace,
) -> Option<(Arc<SimBoard<EppPortModel>>, Arc<sim::SimHm2>)> {
    let spec = sim_epp::preset(name)?;
    let (board, _) = sim::board(spec, Box::new(machine::preset(name)));
    let hi = place.base_hi.unwrap_or(place.base.wrapping_add(HI_OFFSET));
    let mut model = EppPortModel::new(place.base, hi, board.clone());
    if let Some(part) = sim_epp::seven_i43_part(name) {
        model = model.with_cpld(part);
    }
    Some((Arc::new(SimBoard::new(model)), board))
}

/// Opens a real parallel port.
type PortOpener = dyn Fn(PortPlace) -> Result<Arc<dyn PortBus>, Hm2Error>;

/// Loads module `M` (for `kind`) into our `host` with its simulated
/// boards only: a board without `sim=` is refused instead of reaching a
/// real port (the fuzzers load the EPP modules so, hal-fuzz's registry).
pub fn load_without_ports<M: DriverModule<Opened = Boards>>(
    host: &hal_core::Host,
    args: &ModuleArgs,
    kind: &EppBoardKind,
) -> hal_core::Result<()> {
    let refuse = |place: PortPlace| -> Result<Arc<dyn PortBus>, Hm2Error> {
        Err(Hm2Error::EppPort {
            base: place.base,
            reason: "real ports are not reached in this load (simulated boards only: sim=)".into(),
        })
    };
    let found = open_epp(kind, args, &module::env(host), &refuse)?;
    module::load_opened::<M>(host, found)
}

/// Opens the boards `args` ask for, as `kind`; real ports through `real`.
fn open_epp(
    kind: &EppBoardKind,
    args: &ModuleArgs,
    env: &LoadEnv,
    real: &PortOpener,
) -> hal_core::Result<Boards> {
    let module = kind.module;
    let debug = core(env, module)?;
    let params = Params::new(module, args);
    let log = env.log();
    if params.int_or("debug_epp", 0) != 0 {
        log.info(format_args!(
            "{module}: debug_epp: EPP cycles are not printed here (a realtime function must not print); a simulated port's access log shows them"
        ));
    }
    let sims = args.str_array("sim");
    let count = if sims.is_empty() {
        args.int_array("ioaddr").len().max(1)
    } else {
        sims.len()
    };
    if count > MAX_EPP_BOARDS {
        return Err(HalError::module_failed(
            module,
            Hm2Error::TooManyBoards {
                found: count,
                max: MAX_EPP_BOARDS,
            },
        ));
    }
    let mut candidates = Vec::new();
    for i in 0..count {
        let place = place_of(&params, args, i).for_module(module)?;
        let llio = kind.llio(i);
        let fails = format!(
            "{module}: board at {:#x} fails HM2 registration",
            place.base
        );
        let (bus, sim, sim_port): (Arc<dyn PortBus>, _, _) = match sims.get(i) {
            Some(name) => {
                let (port, board) = sim_port(name, place)
                    .filter(|_| sim_epp::board_of(name) == Some(kind.board))
                    .ok_or_else(|| {
                        let names: Vec<&str> = sim_epp::EPP_PRESETS
                            .iter()
                            .copied()
                            .filter(|n| sim_epp::board_of(n) == Some(kind.board))
                            .collect();
                        params.item_error(
                            "sim",
                            i,
                            name,
                            format!(
                                "not a simulated board of this module ({})",
                                names.join(", ")
                            ),
                        )
                    })
                    .for_module(module)?;
                (port.clone(), Some(board), Some(port))
            }
            None => (
                real(place).map_err(|e| HalError::module_failed(module, e))?,
                None,
                None,
            ),
        };
        let mut t = EppTransport::new(bus, place.base, place.base_hi, place.wide);
        t.set_up().map_err(|source| {
            log.err(format_args!(
                "{module}: port at {:#x}: {source}",
                place.base
            ));
            HalError::module_failed(
                module,
                Hm2Error::EppBoard {
                    base: place.base,
                    source,
                },
            )
        })?;
        log.info(format_args!(
            "{module}: {} on the parallel port at {:#x}{}",
            llio.name,
            place.base,
            if sim.is_some() { " (simulated)" } else { "" }
        ));
        candidates.push(Candidate {
            place: format!("at {:#x}", place.base),
            fails,
            llio,
            source: Source::Epp(Box::new(super::EppSource {
                transport: t,
                sim,
                sim_port,
                has_cpld: kind.board == SEVEN_I43.board,
                fpga_part: None,
            })),
        });
    }
    Ok(Boards::new(
        env,
        module,
        debug,
        candidates,
        args.str_array("config").to_vec(),
    )
    .with_firmware_dir(
        args.str("firmware_dir")
            .filter(|d| !d.is_empty())
            .map(std::path::PathBuf::from),
    ))
}
