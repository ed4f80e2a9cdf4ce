//! The `hm2_spi` and `hm2_rpspi` loadrt modules: one SPI transport per
//! board on its spidev device (or a simulated link to a simulated board
//! with `sim=`), the board identified from its IDROM and registered with
//! the hostmot2 core.

use std::path::Path;
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::HalError;
use hal_driver::bus::{SpiBus, Spidev};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;
use hal_driver::sim::SimBoard;
use hal_driver::{DriverError, ForModule};

use super::transport::SpiTransport;
use super::{identify, SpiSource};
use crate::error::Hm2Error;
use crate::hal::{core, export_boards, Boards, Candidate, Source};
use crate::sim::spi::{self as sim_spi, SpiBoardModel};
use crate::sim::{self, machine};

/// Most boards `hm2_spi` drives.
pub const MAX_SPI_BOARDS: usize = 4;
/// Most boards `hm2_rpspi` probes (SPI0 CE0, CE1; SPI1 CE0..CE2).
pub const MAX_RPSPI_BOARDS: usize = 5;
/// `hm2_spi`'s device when `spidev_path` names none.
pub const DEFAULT_SPIDEV: &str = "/dev/spidev1.0";
/// `hm2_spi`'s clock when `spidev_rate` gives none, kHz.
pub const DEFAULT_SPIDEV_RATE_KHZ: i64 = 24_000;
/// `hm2_rpspi`'s clock when `spiclk_rate` gives none, kHz.
pub const DEFAULT_RPSPI_RATE_KHZ: i64 = 31_250;
/// The clocks the drivers accept, kHz (LinuxCNC's hm2_rpspi: 30 kHz to
/// 62.5 MHz).
pub const RATE_KHZ: std::ops::RangeInclusive<i64> = 30..=62_500;
/// `hm2_rpspi`'s probe places, bit by bit, as spidev devices.
pub const RPSPI_PLACES: [&str; MAX_RPSPI_BOARDS] = [
    "/dev/spidev0.0",
    "/dev/spidev0.1",
    "/dev/spidev1.0",
    "/dev/spidev1.1",
    "/dev/spidev1.2",
];

/// `hm2_spi`'s parameters.
#[macro_export]
macro_rules! hm2_spi_params {
    ($($then:tt)*) => { $($then)*! {
        config: StrArray(4) = "hostmot2 config strings, one per board (see hostmot2(9))",
        spidev_path: StrArray(4) = "the spidev devices, one per board (default /dev/spidev1.0)",
        spidev_rate: IntArray(4) = "the SPI clocks in kHz, one per board (default 24000)",
        sim: StrArray(4) = "simulated boards behind simulated SPI links instead of real ones (7i90, 7c80, 7c81), one per board",
    } };
}

/// `hm2_rpspi`'s parameters.
#[macro_export]
macro_rules! hm2_rpspi_params {
    ($($then:tt)*) => { $($then)*! {
        config: StrArray(5) = "hostmot2 config strings, one per board found (see hostmot2(9))",
        spiclk_rate: Int = "the SPI clock in kHz (default 31250)",
        spiclk_rate_rd: Int = "the SPI read clock in kHz (default -1: spiclk_rate)",
        spiclk_base: Int = "the SPI clock divider's base in Hz (default 400000000; spidev divides the clock itself)",
        spi_pull_miso: Int = "MISO pull: 0 none, 1 down (default), 2 up (set by the kernel's device tree under spidev)",
        spi_pull_mosi: Int = "MOSI pull: 0 none, 1 down (default), 2 up (set by the kernel's device tree under spidev)",
        spi_pull_sclk: Int = "SCLK pull: 0 none, 1 down (default), 2 up (set by the kernel's device tree under spidev)",
        spi_probe: Int = "where to look for boards: 1 SPI0/CE0, 2 SPI0/CE1, 4 SPI1/CE0, 8 SPI1/CE1, 16 SPI1/CE2 (default 1)",
        spi_debug: Int = "message level 0..5, -1 (default) leaves it",
        sim: StrArray(5) = "simulated boards behind simulated SPI links at the probed places, in order (7i90, 7c80, 7c81)",
    } };
}

/// The `hm2_spi` driver.
#[derive(Debug)]
pub struct HalHm2Spi;

/// The `hm2_rpspi` driver.
#[derive(Debug)]
pub struct HalHm2Rpspi;

/// The `hm2_spi` module.
pub static HM2_SPI_MODULE: ModuleDef = module::module_def::<HalHm2Spi>();
/// The `hm2_rpspi` module.
pub static HM2_RPSPI_MODULE: ModuleDef = module::module_def::<HalHm2Rpspi>();

impl DriverModule for HalHm2Spi {
    const NAME: &'static str = "hm2_spi";
    const HELP: &'static str =
        "Mesa SPI Anything I/O boards with HostMot2 firmware on spidev (or simulated ones: sim=7i90)";
    const PARAMS: &'static [ParamDecl] = hm2_spi_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        let places = spi_places(args).for_module(HalHm2Spi::NAME)?;
        open_spi(HalHm2Spi::NAME, args, env, &places, &real_device)
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

impl DriverModule for HalHm2Rpspi {
    const NAME: &'static str = "hm2_rpspi";
    const HELP: &'static str =
        "Mesa SPI Anything I/O boards on a Raspberry Pi's SPI ports (or simulated ones: sim=7c80)";
    const PARAMS: &'static [ParamDecl] = hm2_rpspi_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        let places = rpspi_places(args, env).for_module(HalHm2Rpspi::NAME)?;
        open_spi(HalHm2Rpspi::NAME, args, env, &places, &real_device)
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

/// Where one board is: its device and clocks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SpiPlace {
    /// The spidev device.
    pub device: String,
    /// Write clock, Hz.
    pub write_hz: u32,
    /// Read clock, Hz.
    pub read_hz: u32,
}

/// `hm2_spi`'s boards: one per `spidev_path` (at least one), or per `sim`.
pub fn spi_places(args: &ModuleArgs) -> Result<Vec<SpiPlace>, DriverError> {
    let params = Params::new(HalHm2Spi::NAME, args);
    let paths = args.str_array("spidev_path");
    let count = paths.len().max(args.str_array("sim").len()).max(1);
    if count > MAX_SPI_BOARDS {
        return Err(params.error(
            "spidev_path",
            format!("{count} boards, at most {MAX_SPI_BOARDS}"),
        ));
    }
    let rates = params.ints_per("spidev_rate", count, DEFAULT_SPIDEV_RATE_KHZ, RATE_KHZ)?;
    (0..count)
        .map(|i| {
            let device = paths
                .get(i)
                .map(String::as_str)
                .filter(|p| !p.is_empty())
                .unwrap_or(DEFAULT_SPIDEV);
            if !device.starts_with('/') {
                return Err(params.item_error(
                    "spidev_path",
                    i,
                    device,
                    "not a device path (/dev/spidevB.C)",
                ));
            }
            let hz = (rates[i] * 1000) as u32;
            Ok(SpiPlace {
                device: device.into(),
                write_hz: hz,
                read_hz: hz,
            })
        })
        .collect()
}

/// `hm2_rpspi`'s boards: the places `spi_probe` names, in order.
pub fn rpspi_places(args: &ModuleArgs, env: &LoadEnv) -> Result<Vec<SpiPlace>, DriverError> {
    let params = Params::new(HalHm2Rpspi::NAME, args);
    let write = params.int_in("spiclk_rate", DEFAULT_RPSPI_RATE_KHZ, RATE_KHZ)?;
    let read = match params.int_or("spiclk_rate_rd", -1) {
        -1 => write,
        v if RATE_KHZ.contains(&v) => v,
        v => {
            return Err(params.error(
                "spiclk_rate_rd",
                format!("{v} is out of range (-1 or 30..=62500)"),
            ))
        }
    };
    params.int_in("spiclk_base", 400_000_000, 1_000_000..=2_000_000_000)?;
    for pull in ["spi_pull_miso", "spi_pull_mosi", "spi_pull_sclk"] {
        params.int_in(pull, 1, 0..=2)?;
    }
    params.int_in("spi_debug", -1, -1..=5)?;
    let probe = params.int_in("spi_probe", 1, 1..=31)?;
    let touched = [
        "spiclk_base",
        "spi_pull_miso",
        "spi_pull_mosi",
        "spi_pull_sclk",
        "spi_debug",
    ]
    .iter()
    .filter(|p| args.int(p).is_some())
    .copied()
    .collect::<Vec<_>>();
    if !touched.is_empty() {
        env.log().info(format_args!(
            "hm2_rpspi: {} checked; on spidev the kernel sets the clock divider, pulls and messages",
            touched.join(", ")
        ));
    }
    Ok(RPSPI_PLACES
        .iter()
        .enumerate()
        .filter(|(bit, _)| probe & (1 << bit) != 0)
        .map(|(_, dev)| SpiPlace {
            device: dev.to_string(),
            write_hz: (write * 1000) as u32,
            read_hz: (read * 1000) as u32,
        })
        .collect())
}

/// The real device at `place`.
fn real_device(place: &SpiPlace) -> Result<Arc<dyn SpiBus>, Hm2Error> {
    let dev =
        Spidev::open(Path::new(&place.device), place.write_hz.max(place.read_hz)).map_err(|e| {
            Hm2Error::SpiDevice {
                device: place.device.clone(),
                reason: e.to_string(),
            }
        })?;
    Ok(Arc::new(dev))
}

/// A simulated board of preset `name` behind a simulated link: the bus,
/// and the board for the HAL functions.
pub fn sim_link(name: &str) -> Option<(Arc<SimBoard<SpiBoardModel>>, Arc<sim::SimHm2>)> {
    let spec = sim_spi::preset(name)?;
    let (board, _) = sim::board(spec, Box::new(machine::preset(name)));
    let link = Arc::new(SimBoard::new(SpiBoardModel::new(board.clone())));
    Some((link, board))
}

/// Opens a real SPI device.
type DeviceOpener = dyn Fn(&SpiPlace) -> Result<Arc<dyn SpiBus>, Hm2Error>;

/// Loads module `M` into our `host` with simulated boards only: a board
/// without `sim=` is refused before any device is opened (the fuzzers
/// load the SPI modules so).
pub fn load_without_devices<M: DriverModule<Opened = Boards>>(
    host: &hal_core::Host,
    args: &ModuleArgs,
) -> hal_core::Result<()> {
    let refuse = |place: &SpiPlace| -> Result<Arc<dyn SpiBus>, Hm2Error> {
        Err(Hm2Error::SpiDevice {
            device: place.device.clone(),
            reason: "real devices are not reached in this load (simulated boards only: sim=)"
                .into(),
        })
    };
    let env = module::env(host);
    let places = if M::NAME == HalHm2Rpspi::NAME {
        rpspi_places(args, &env)
    } else {
        spi_places(args)
    }
    .for_module(M::NAME)?;
    let found = open_spi(M::NAME, args, &env, &places, &refuse)?;
    module::load_opened::<M>(host, found)
}

/// Opens the boards at `places` for `module`; real devices through
/// `real`, the `sim` items in order as simulated ones.
fn open_spi(
    module: &'static str,
    args: &ModuleArgs,
    env: &LoadEnv,
    places: &[SpiPlace],
    real: &DeviceOpener,
) -> hal_core::Result<Boards> {
    let debug = core(env, module)?;
    let params = Params::new(module, args);
    let log = env.log();
    let sims = args.str_array("sim");
    if sims.len() > places.len() {
        return Err(HalError::module_failed(
            module,
            params.error(
                "sim",
                format!(
                    "{} simulated boards for {} places (spi_probe)",
                    sims.len(),
                    places.len()
                ),
            ),
        ));
    }
    let mut counts: Vec<(&str, usize)> = Vec::new();
    let mut candidates = Vec::new();
    for (i, place) in places.iter().enumerate() {
        let (bus, sim): (Arc<dyn SpiBus>, _) = match sims.get(i) {
            Some(name) => {
                let (link, board) = sim_link(name)
                    .ok_or_else(|| {
                        params.item_error(
                            "sim",
                            i,
                            name,
                            format!(
                                "not a simulated SPI board ({})",
                                sim_spi::SPI_PRESETS.join(", ")
                            ),
                        )
                    })
                    .for_module(module)?;
                (link, Some(board))
            }
            None => (
                real(place).map_err(|e| HalError::module_failed(module, e))?,
                None,
            ),
        };
        let mut t = SpiTransport::new(bus, place.write_hz, place.read_hz);
        let kind = identify(&mut t, &place.device).map_err(|e| {
            log.err(format_args!("{module}: {e}"));
            HalError::module_failed(module, e)
        })?;
        let n = match counts.iter_mut().find(|(b, _)| *b == kind.board) {
            Some((_, n)) => {
                *n += 1;
                *n - 1
            }
            None => {
                counts.push((kind.board, 1));
                0
            }
        };
        let llio = kind.llio(n);
        log.info(format_args!(
            "{module}: {} on {}{}",
            llio.name,
            place.device,
            if sim.is_some() { " (simulated)" } else { "" }
        ));
        candidates.push(Candidate {
            place: format!("on {}", place.device),
            fails: format!("{module}: board on {} fails HM2 registration", place.device),
            llio,
            source: Source::Spi(Box::new(SpiSource { transport: t, sim })),
        });
    }
    Ok(Boards::new(
        env,
        module,
        debug,
        candidates,
        args.str_array("config").to_vec(),
    ))
}
