//! The PCI boards `hm2_pci` drives (hardware.md 5.1) and how it opens
//! them through the shared driver layer: find in sysfs, enable, map the
//! FPGA window's BAR.
//!
//! Every board LinuxCNC's table has is here, plus the 6i25T that
//! LinuxCNC's probe code handles but its table misses. The PLX-bridged
//! boards (5i20 ... 3x20) are found and mapped like the others; with
//! `firmware=` their FPGA is loaded through the bridge's I/O BARs
//! ([`crate::pci_fpga`]), which also sets the PLX 9030's local-bus ready
//! bits an old EEPROM leaves clear.

use hal_driver::bus::MmapWindow;
use hal_driver::pci::{self, EnableGuard, PciDevice, PciMatch, Sysfs};

use crate::llio::Llio;
use crate::regs::WINDOW_BYTES;

/// One kind of board.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PciBoard {
    /// How to recognise it.
    pub ids: PciMatch,
    /// Its type in HAL names (`hm2_<board>.<n>`).
    pub board: &'static str,
    /// The BAR holding the FPGA's 64 KiB window.
    pub bar: usize,
    /// Connector names, in I/O order.
    pub connectors: &'static [&'static str],
    /// Pins per connector.
    pub pins_per_connector: u32,
    /// LEDs.
    pub leds: u32,
    /// FPGA part.
    pub fpga_part: &'static str,
}

const PLX: u16 = 0x10B5;
const MESA: u16 = 0x2718;

const fn plx(device: u16, sub: u16, board: &'static str) -> PciMatch {
    PciMatch::new(PLX, device, board).subsystem(PLX, sub)
}

const fn mesa(device: u16, board: &'static str) -> PciMatch {
    PciMatch::new(MESA, device, board).subsystem(MESA, device)
}

const P234: &[&str] = &["P2", "P3", "P4"];
const P134: &[&str] = &["P1", "P3", "P4"];

/// Every board, LinuxCNC's table order.
pub const BOARDS: &[PciBoard] = &[
    PciBoard {
        ids: plx(0x9030, 0x3131, "5i20"),
        board: "5i20",
        bar: 5,
        connectors: P234,
        pins_per_connector: 24,
        leds: 8,
        fpga_part: "2s200pq208",
    },
    PciBoard {
        ids: plx(0x9030, 0x3132, "4i65"),
        board: "4i65",
        bar: 5,
        connectors: P134,
        pins_per_connector: 24,
        leds: 8,
        fpga_part: "2s200pq208",
    },
    PciBoard {
        ids: plx(0x9054, 0x3312, "5i21"),
        board: "5i21",
        bar: 3,
        connectors: &["P1", "P1"],
        pins_per_connector: 32,
        leds: 8,
        fpga_part: "3s400pq208",
    },
    PciBoard {
        ids: plx(0x9054, 0x3314, "5i22-1.0M"),
        board: "5i22",
        bar: 3,
        connectors: &["P2", "P3", "P4", "P5"],
        pins_per_connector: 24,
        leds: 8,
        fpga_part: "3s1000fg320",
    },
    PciBoard {
        ids: plx(0x9054, 0x3313, "5i22-1.5M"),
        board: "5i22",
        bar: 3,
        connectors: &["P2", "P3", "P4", "P5"],
        pins_per_connector: 24,
        leds: 8,
        fpga_part: "3s1500fg320",
    },
    PciBoard {
        ids: plx(0x9054, 0x3315, "5i23"),
        board: "5i23",
        bar: 3,
        connectors: P234,
        pins_per_connector: 24,
        leds: 2,
        fpga_part: "3s400pq208",
    },
    PciBoard {
        ids: plx(0x9054, 0x3311, "4i68"),
        board: "4i68",
        bar: 3,
        connectors: &["P1", "P2", "P4"],
        pins_per_connector: 24,
        leds: 4,
        fpga_part: "3s400pq208",
    },
    PciBoard {
        ids: plx(0x9054, 0x3133, "4i68 (old EEPROM)"),
        board: "4i68",
        bar: 3,
        connectors: &["P1", "P2", "P4"],
        pins_per_connector: 24,
        leds: 4,
        fpga_part: "3s400pq208",
    },
    PciBoard {
        ids: plx(0x9054, 0x3472, "4i69-16"),
        board: "4i69",
        bar: 3,
        connectors: P134,
        pins_per_connector: 24,
        leds: 0,
        fpga_part: "6slx16ftg256",
    },
    PciBoard {
        ids: plx(0x9054, 0x3473, "4i69-25"),
        board: "4i69",
        bar: 3,
        connectors: P134,
        pins_per_connector: 24,
        leds: 0,
        fpga_part: "6slx25ftg256",
    },
    PciBoard {
        ids: plx(0x9056, 0x3427, "3x20-1.0M"),
        board: "3x20",
        bar: 3,
        connectors: &["P4", "P5", "P6", "P9", "P8", "P7"],
        pins_per_connector: 24,
        leds: 0,
        fpga_part: "3s1000fg456",
    },
    PciBoard {
        ids: plx(0x9056, 0x3428, "3x20-1.5M"),
        board: "3x20",
        bar: 3,
        connectors: &["P4", "P5", "P6", "P9", "P8", "P7"],
        pins_per_connector: 24,
        leds: 0,
        fpga_part: "3s1500fg456",
    },
    PciBoard {
        ids: plx(0x9056, 0x3429, "3x20-2.0M"),
        board: "3x20",
        bar: 3,
        connectors: &["P4", "P5", "P6", "P9", "P8", "P7"],
        pins_per_connector: 24,
        leds: 0,
        fpga_part: "3s2000fg456",
    },
    PciBoard {
        ids: mesa(0x5124, "5i24"),
        board: "5i24",
        bar: 0,
        connectors: &["P4", "P3", "P2"],
        pins_per_connector: 24,
        leds: 2,
        fpga_part: "6slx16ftg256",
    },
    PciBoard {
        ids: mesa(0x5125, "5i25"),
        board: "5i25",
        bar: 0,
        connectors: &["P3", "P2"],
        pins_per_connector: 17,
        leds: 2,
        fpga_part: "6slx9tqg144",
    },
    PciBoard {
        ids: mesa(0x5925, "5i25T"),
        board: "5i25",
        bar: 0,
        connectors: &["P3", "P2"],
        pins_per_connector: 17,
        leds: 2,
        fpga_part: "t20f256",
    },
    PciBoard {
        ids: mesa(0x6125, "6i25"),
        board: "6i25",
        bar: 0,
        connectors: &["P3", "P2"],
        pins_per_connector: 17,
        leds: 2,
        fpga_part: "6slx9tqg144",
    },
    PciBoard {
        ids: mesa(0x6925, "6i25T"),
        board: "6i25",
        bar: 0,
        connectors: &["P3", "P2"],
        pins_per_connector: 17,
        leds: 2,
        fpga_part: "t20f256",
    },
];

/// The ID table of `boards`, for [`pci::scan`].
pub fn id_table(boards: &[PciBoard]) -> Vec<PciMatch> {
    boards.iter().map(|b| b.ids).collect()
}

/// The board kind a found device matched.
pub fn kind_of<'a>(boards: &'a [PciBoard], dev: &PciDevice) -> Option<&'a PciBoard> {
    boards.iter().find(|b| b.ids == dev.matched)
}

impl PciBoard {
    /// The llio of the `n`th board of this type.
    pub fn llio(&self, n: usize) -> Llio {
        Llio {
            name: format!("hm2_{}.{n}", self.board),
            connectors: self.connectors.iter().map(|s| s.to_string()).collect(),
            pins_per_connector: self.pins_per_connector,
            num_leds: self.leds,
            fpga_part: self.fpga_part.to_string(),
        }
    }
}

/// An opened board: its kind, device, the enable guard (kept as long as
/// the driver runs) and its mapped window.
#[derive(Debug)]
pub struct OpenedBoard {
    /// The kind.
    pub kind: PciBoard,
    /// The device.
    pub device: PciDevice,
    /// Keeps the device enabled.
    pub enabled: EnableGuard,
    /// The FPGA window.
    pub window: MmapWindow,
}

/// Finds every board of `boards` under `sysfs` (bus address order),
/// enables each and maps its 64 KiB window. Fails, naming the board and
/// the reason, if none is found or one cannot be opened.
pub fn open_all(sysfs: &Sysfs, boards: &[PciBoard]) -> hal_driver::Result<Vec<OpenedBoard>> {
    let found = pci::find(sysfs, &id_table(boards))?;
    let mut out = Vec::with_capacity(found.len());
    for device in found {
        let Some(kind) = kind_of(boards, &device) else {
            continue;
        };
        let enabled = device.enable()?;
        let window = device.map_bar_window(kind.bar, WINDOW_BYTES)?;
        out.push(OpenedBoard {
            kind: *kind,
            device,
            enabled,
            window,
        });
    }
    Ok(out)
}
