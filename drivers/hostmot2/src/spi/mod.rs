//! `hm2_spi` and `hm2_rpspi`: Mesa's SPI cards (7I90HD in SPI mode, the
//! Raspberry Pi hats 7C80 and 7C81, a 7I43), reached through Linux's
//! spidev (`/dev/spidevB.C`).
//!
//! ```text
//! loadrt hostmot2
//! loadrt hm2_spi spidev_path=/dev/spidev0.0 spidev_rate=24000 config="num_stepgens=5"
//! addf hm2_7i90.0.read servo-thread
//! addf hm2_7i90.0.write servo-thread
//! ```
//!
//! # The link
//!
//! Every register access is a Mesa SPI frame ([`frame`]): a command word
//! (address, read or write, burst count) and its data, in one spidev
//! message ([`transport`]), over the shared driver layer's
//! [`SpiBus`](hal_driver::bus::SpiBus): the real
//! [`Spidev`](hal_driver::bus::Spidev) or, with `sim=`, a simulated
//! board behind a simulated link ([`sim::spi`](crate::sim::spi)). The
//! board names itself: after the HostMot2 cookie, the IDROM's board name
//! says which card it is ([`BOARDS`]), and so its HAL prefix
//! (`hm2_7i90.0`, `hm2_7c80.0`) and connectors.
//!
//! # Parameters
//!
//! `hm2_spi`, as LinuxCNC's: `config` (one hostmot2 config string per
//! board), `spidev_path` (default `/dev/spidev1.0`), `spidev_rate` (SPI
//! clock in kHz, default 24000), one item per board; and `sim`
//! (simulated boards: 7i90, 7c80, 7c81).
//!
//! `hm2_rpspi`, as LinuxCNC's: `config`, `spiclk_rate` (kHz, default
//! 31250), `spiclk_rate_rd` (read clock, -1: the same), `spi_probe`
//! (which SPI/CE pairs to look at: 1 SPI0/CE0, 2 SPI0/CE1, 4 SPI1/CE0,
//! 8 SPI1/CE1, 16 SPI1/CE2, here `/dev/spidev0.0` .. `/dev/spidev1.2`),
//! `spiclk_base`, `spi_pull_miso`, `spi_pull_mosi`, `spi_pull_sclk` and
//! `spi_debug`, and `sim` (the probed places in order get the simulated
//! boards). LinuxCNC's hm2_rpspi drives the Raspberry Pi's SPI
//! controller registers itself; here it goes through spidev like
//! hm2_spi, so the clock divider base and the pin pulls are the kernel's
//! business: those parameters are checked and otherwise have no effect
//! (the load says so).
//!
//! # Modules
//!
//! [`frame`] (the framing), [`transport`] (the SPI transport), [`hal`]
//! (the two `loadrt` modules).

pub mod frame;
pub mod hal;
pub mod transport;

pub use transport::SpiTransport;

use std::sync::Arc;

use crate::error::Hm2Error;
use crate::llio::Llio;
use crate::regs;
use crate::transport::Transport;

/// A board on an SPI device: its transport and, when simulated, the
/// board behind the simulated link (whose time the HAL `read` moves).
#[derive(Debug)]
pub struct SpiSource {
    /// The transport.
    pub transport: SpiTransport,
    /// The simulated board, if it is one.
    pub sim: Option<Arc<crate::sim::SimHm2>>,
}

/// A board the SPI drivers know, by its IDROM name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpiBoardKind {
    /// The IDROM's board name.
    pub idrom_name: &'static [u8; 8],
    /// The board (`7i90`): the HAL prefix is `hm2_<board>.<n>`.
    pub board: &'static str,
    /// Connector names in I/O order.
    pub connectors: &'static [&'static str],
    /// Pins per connector.
    pub width: u32,
    /// LEDs.
    pub leds: u32,
    /// The FPGA part.
    pub fpga_part: &'static str,
}

/// The SPI boards (LinuxCNC's: 7C80 2 × 27, 7C81 3 × 19, 7I90 3 × 24,
/// 7I43 2 × 24).
pub const BOARDS: &[SpiBoardKind] = &[
    SpiBoardKind {
        idrom_name: b"MESA7I90",
        board: "7i90",
        connectors: &["P1", "P2", "P3"],
        width: 24,
        leds: 2,
        fpga_part: "6slx9tq144",
    },
    SpiBoardKind {
        idrom_name: b"MESA7C80",
        board: "7c80",
        connectors: &["P1", "P2"],
        width: 27,
        leds: 2,
        fpga_part: "6slx9tq144",
    },
    SpiBoardKind {
        idrom_name: b"MESA7C81",
        board: "7c81",
        connectors: &["P1", "P2", "P7"],
        width: 19,
        leds: 2,
        fpga_part: "6slx9tq144",
    },
    SpiBoardKind {
        idrom_name: b"MESA7I43",
        board: "7i43",
        connectors: &["P4", "P3"],
        width: 24,
        leds: 8,
        fpga_part: "3s400tq144",
    },
];

impl SpiBoardKind {
    /// Board `n`'s llio.
    pub fn llio(&self, n: usize) -> Llio {
        Llio {
            name: format!("hm2_{}.{n}", self.board),
            connectors: self.connectors.iter().map(|c| c.to_string()).collect(),
            pins_per_connector: self.width,
            num_leds: self.leds,
            fpga_part: self.fpga_part.into(),
        }
    }
}

/// Which board answers on `device` through `t`: the HostMot2 cookie and
/// configuration name at 0x100, then the board name in the IDROM.
pub fn identify(t: &mut dyn Transport, device: &str) -> Result<&'static SpiBoardKind, Hm2Error> {
    let failed = |source| Hm2Error::SpiBoard {
        device: device.into(),
        source,
    };
    let mut head = [0u32; 4];
    t.read(regs::COOKIE_ADDR as u32, &mut head)
        .map_err(failed)?;
    let text = |w: &[u32]| -> String {
        w.iter()
            .flat_map(|v| v.to_le_bytes())
            .map(|b| if b.is_ascii_graphic() { b as char } else { '.' })
            .collect()
    };
    let config = text(&head[1..3]);
    if head[0] != regs::COOKIE || config != "HOSTMOT2" {
        return Err(Hm2Error::SpiNotHostmot2 {
            device: device.into(),
            cookie: head[0],
            name: config,
        });
    }
    let mut name = [0u32; 2];
    let at = head[3].wrapping_add(0x0C);
    if at > 0xFFF8 {
        return Err(Hm2Error::SpiUnknownBoard {
            device: device.into(),
            name: format!("(IDROM offset 0x{:X} out of range)", head[3]),
        });
    }
    t.read(at, &mut name).map_err(failed)?;
    let bytes: Vec<u8> = name.iter().flat_map(|v| v.to_le_bytes()).collect();
    BOARDS
        .iter()
        .find(|b| b.idrom_name[..] == bytes[..])
        .ok_or_else(|| Hm2Error::SpiUnknownBoard {
            device: device.into(),
            name: text(&name),
        })
}
