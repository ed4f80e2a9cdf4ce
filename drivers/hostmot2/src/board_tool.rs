//! The board bring-up tool's logic (`hal-board`): a list of the boards on
//! the PCI bus that the suite's drivers know, with each driver family's ID
//! table and identification, the simulated boards, and register access
//! to one board, on the PCI bus, on the network (by IP address) or
//! simulated (IDROM listing, single reads and writes, a module's
//! registers watched live, the Smart Serial cards and their process
//! data).
//!
//! A driver family joins the list with a [`Family`] in [`families`]: its
//! name, its driver, its ID table and a function that identifies a found
//! device (hostmot2 reads the FPGA's IDROM; the MOTENC its boardVersion
//! and board ID jumpers).

use std::net::SocketAddr;
use std::sync::Arc;

use hal_driver::bus::MmapWindow;
use hal_driver::pci::{self, EnableGuard, PciDevice, PciMatch, Sysfs};
use hal_driver::sim::SimBoard;
use hal_motenc::sim::MotencModel;
use hal_motenc::BoardKind;

use crate::eth::{self, EthTransport};
use crate::image::FirmwareSpec;
use crate::md::{self, ModuleDescriptor};
use crate::pci::{PciBoard, BOARDS};
use crate::readhmid;
use crate::regs::{gtag, WINDOW_BYTES};
use crate::sim::{self, boards, machine, SimHm2};
use crate::tool_error::ToolError;
use crate::transport::Transport;
use crate::window::WindowTransport;

/// A driver family's boards on the PCI bus.
pub struct Family {
    /// The family (`Mesa HostMot2`).
    pub name: &'static str,
    /// The `loadrt` module that drives them.
    pub driver: &'static str,
    /// Its ID table.
    pub table: fn() -> Vec<PciMatch>,
    /// What a found device says about itself (or why it cannot be read).
    pub identify: fn(&PciDevice) -> String,
}

/// Every family the tool knows.
pub fn families() -> Vec<Family> {
    vec![
        Family {
            name: "Mesa HostMot2",
            driver: "hm2_pci",
            table: || crate::pci::id_table(BOARDS),
            identify: identify_hm2,
        },
        Family {
            name: "Vital Systems MOTENC",
            driver: "hal_motenc",
            table: || hal_motenc::regs::PCI_TABLE.to_vec(),
            identify: identify_motenc,
        },
    ]
}

/// A MOTENC's kind, version and board ID jumpers, read from BAR 2.
fn identify_motenc(dev: &PciDevice) -> String {
    let open = || -> Result<String, ToolError> {
        let _on = dev.enable()?;
        let win = dev.map_bar_window(hal_motenc::regs::BAR, hal_motenc::regs::WINDOW_LEN)?;
        Ok(hal_motenc::identify(&win)?.to_string())
    };
    open().unwrap_or_else(|e| format!("(not readable: {e})"))
}

fn identify_hm2(dev: &PciDevice) -> String {
    let Some(kind) = crate::pci::kind_of(BOARDS, dev) else {
        return "not a known HostMot2 board".into();
    };
    let open = || -> Result<String, ToolError> {
        let _on = dev.enable()?;
        let win = dev.map_bar_window(kind.bar, WINDOW_BYTES)?;
        Ok(readhmid::identify(&mut WindowTransport::new(win))?)
    };
    open().unwrap_or_else(|e| format!("(not readable: {})", e.to_string().replace('\n', "; ")))
}

/// The list: one line per board found, then the simulated boards.
pub fn list(sysfs: &Sysfs) -> Vec<String> {
    let mut lines = Vec::new();
    let mut found = 0;
    for f in families() {
        match pci::scan(sysfs, &(f.table)()) {
            Ok(devs) => {
                for d in devs {
                    found += 1;
                    lines.push(format!(
                        "{}  {}  {}  {}: {}",
                        d.address,
                        d.ids,
                        d.name(),
                        f.driver,
                        (f.identify)(&d)
                    ));
                }
            }
            Err(e) => lines.push(format!("{}: {e}", f.name)),
        }
    }
    if found == 0 {
        lines.push(format!(
            "no board any driver knows under {}",
            sysfs.root().display()
        ));
    }
    lines.push(
        "Ethernet boards are not scanned: give a board's address (hal-board idrom 192.168.1.121)"
            .into(),
    );
    for (title, names) in [
        ("simulated boards (hm2_pci sim=NAME):", boards::PRESETS),
        (
            "simulated Ethernet boards (hm2_eth sim=NAME, hm2-eth-sim --board NAME):",
            boards::ETH_PRESETS,
        ),
    ] {
        lines.push(title.into());
        for name in names {
            let spec = boards::preset(name).expect("preset");
            let mut t = sim::board(spec, Box::new(machine::preset(name))).1;
            let id = readhmid::identify(&mut t).unwrap_or_else(|e| e.to_string());
            lines.push(format!("sim:{name}  {id}"));
        }
    }
    let motenc: Vec<String> = [BoardKind::Motenc100, BoardKind::MotencLite]
        .into_iter()
        .map(|k| {
            let sim = SimBoard::new(MotencModel::new(k, 0));
            hal_motenc::identify(&sim).map_or_else(|e| e.to_string(), |id| id.to_string())
        })
        .collect();
    lines.push(format!(
        "simulated MOTENC boards (hal_motenc backend=sim sim_boards=100|lite): {}",
        motenc.join(", ")
    ));
    lines
}

/// The board a command works on.
pub enum Board {
    /// A PCI board, enabled and mapped.
    Pci {
        /// The device.
        device: PciDevice,
        /// Its kind.
        kind: PciBoard,
        /// Keeps it enabled.
        _enabled: EnableGuard,
        /// Its FPGA window.
        window: Arc<MmapWindow>,
    },
    /// A simulated board, fresh for this command.
    Sim {
        /// Its firmware.
        spec: FirmwareSpec,
        /// The board.
        board: Arc<SimHm2>,
    },
    /// A board on the network.
    Eth {
        /// Its address.
        addr: SocketAddr,
        /// Its space-7 name (`7I96S`).
        name: String,
        /// What hm2_eth makes of it.
        llio: crate::llio::Llio,
    },
}

impl Board {
    /// Opens `which`: `sim:NAME` for a simulated board, an IP address
    /// (optionally `:port`) for an Ethernet board, else a PCI bus address
    /// (`0000:02:00.0`, optionally `pci:` in front) of a HostMot2 board
    /// under `sysfs`.
    pub fn open(which: &str, sysfs: &Sysfs) -> Result<Board, ToolError> {
        if let Ok(addr) = eth::hal::parse_board_address(which) {
            let mut t = EthTransport::connect(addr)?;
            let found = eth::hal::probe(&mut t)?;
            let llio = match eth::boards::lookup(&found.name) {
                Some(kind) => kind.llio(0),
                None => eth::hal::llio_from_idrom(&mut t, &found.name, 0)?,
            };
            return Ok(Board::Eth {
                addr,
                name: found.name,
                llio,
            });
        }
        if let Some(name) = which.strip_prefix("sim:") {
            let spec = boards::preset(name).ok_or_else(|| ToolError::NoSimBoard {
                name: name.to_string(),
                boards: boards::PRESETS.join(", "),
            })?;
            let (board, _) = sim::board(spec.clone(), Box::new(machine::preset(name)));
            return Ok(Board::Sim { spec, board });
        }
        let address = which.strip_prefix("pci:").unwrap_or(which);
        let devs = pci::scan(sysfs, &crate::pci::id_table(BOARDS))?;
        let device = devs
            .into_iter()
            .find(|d| d.address == address)
            .ok_or_else(|| ToolError::NoPciBoard {
                address: address.to_string(),
                root: sysfs.root().to_path_buf(),
            })?;
        let kind = *crate::pci::kind_of(BOARDS, &device).ok_or(ToolError::UnknownKind)?;
        let enabled = device.enable()?;
        let window = device.map_bar_window(kind.bar, WINDOW_BYTES)?;
        Ok(Board::Pci {
            device,
            kind,
            _enabled: enabled,
            window: Arc::new(window),
        })
    }

    /// A transport to the board's registers.
    pub fn transport(&self) -> Result<Box<dyn Transport>, ToolError> {
        Ok(match self {
            Board::Pci { window, .. } => Box::new(WindowTransport::new(window.clone())),
            Board::Sim { board, .. } => Box::new(WindowTransport::new(board.clone())),
            Board::Eth { addr, name, .. } => {
                let mut t = EthTransport::connect(*addr)?;
                t.set_name(name);
                Box::new(t)
            }
        })
    }

    /// The board's llio (connectors, pins per connector).
    pub fn llio(&self) -> crate::llio::Llio {
        match self {
            Board::Pci { kind, .. } => kind.llio(0),
            Board::Sim { spec, .. } => spec.llio(0),
            Board::Eth { llio, .. } => llio.clone(),
        }
    }

    /// What it is, for headers: `5i25 at 0000:02:00.0`, `simulated 5i25`,
    /// `7I96S at 192.168.1.121:27181`.
    pub fn describe(&self) -> String {
        match self {
            Board::Pci { device, kind, .. } => format!("{} at {}", kind.board, device.address),
            Board::Sim { spec, .. } => format!("simulated {}", spec.board),
            Board::Eth { addr, name, .. } => format!("{name} at {addr}"),
        }
    }

    /// Lets simulated time pass (a PCI board's time passes by itself).
    pub fn advance(&self, ns: u64) {
        if let Board::Sim { board, .. } = self {
            board.advance(ns);
        }
    }
}

/// Parses a register address: decimal or `0x` hex, 4-aligned, inside the
/// 64 KiB window.
pub fn parse_address(s: &str) -> Result<u32, ToolError> {
    let v = hal_driver::params::parse_number(s, (WINDOW_BYTES - 4) as u64).map_err(|source| {
        ToolError::BadAddress {
            text: s.to_string(),
            source,
        }
    })? as u32;
    if v % 4 != 0 {
        return Err(ToolError::Unaligned {
            text: s.to_string(),
        });
    }
    Ok(v)
}

/// Parses a register value: decimal or `0x` hex, 32 bits.
pub fn parse_value(s: &str) -> Result<u32, ToolError> {
    hal_driver::params::parse_number(s, u32::MAX as u64)
        .map(|v| v as u32)
        .map_err(|source| ToolError::BadValue {
            text: s.to_string(),
            source,
        })
}

/// The IDROM, modules and pin-out in `mesaflash --readhmid`'s layout.
pub fn idrom(board: &Board) -> Result<String, ToolError> {
    let connectors = board.llio().connectors;
    Ok(readhmid::read_hmid(
        board.transport()?.as_mut(),
        &connectors,
    )?)
}

/// Reads one register.
pub fn read(board: &Board, addr: u32) -> Result<u32, ToolError> {
    let mut w = [0u32; 1];
    board.transport()?.read(addr, &mut w)?;
    Ok(w[0])
}

/// Writes one register.
pub fn write(board: &Board, addr: u32, value: u32) -> Result<(), ToolError> {
    Ok(board.transport()?.write(addr, &[value])?)
}

/// The Smart Serial ports, their cards and process data, found as the
/// driver finds them with `config` (`sserial_port_0=...`; every port and
/// channel in mode 0 by default). This resets the ports: not while a HAL
/// runs the board.
pub fn sserial(board: &Board, config: &str) -> Result<String, ToolError> {
    let config = crate::config::parse(config)?;
    let llio = board.llio();
    let mut t = board.transport()?;
    let mut log = crate::log::MessageLog::default();
    let fw = crate::firmware::load(
        &llio,
        &config,
        crate::firmware::Debug::default(),
        t.as_mut(),
        &mut log,
    )?;
    match fw.sserial {
        Some(f) => Ok(crate::sserial::report::report(&f, &llio.name)),
        None => Ok("the firmware has no Smart Serial module\n".into()),
    }
}

/// Finds the module named `name` (LinuxCNC's or mesaflash's name, any
/// case: `stepgen`, `encoder`, `qcount`, `pwmgen`, `pwm`, `ioport`,
/// `watchdog`, `led`).
pub fn find_module(board: &Board, name: &str) -> Result<ModuleDescriptor, ToolError> {
    let mut t = board.transport()?;
    crate::idrom::check_identity(t.as_mut())?;
    let h = crate::idrom::read_header(t.as_mut(), &board.llio())?;
    let mds = md::read_all(t.as_mut(), &h)?;
    let want = name.to_ascii_lowercase();
    mds.into_iter()
        .find(|m| {
            let names = [gtag::name(m.gtag), gtag::mesaflash_name(m.gtag)];
            names
                .iter()
                .flatten()
                .any(|n| n.to_ascii_lowercase() == want)
        })
        .ok_or_else(|| ToolError::NoModule {
            name: name.to_string(),
        })
}

/// One snapshot of a module's registers: a line per register with its
/// address and the value of every instance.
pub fn module_frame(board: &Board, m: &ModuleDescriptor) -> Result<String, ToolError> {
    let mut t = board.transport()?;
    let names = readhmid::register_names(m.gtag);
    let mut out = format!(
        "{} {} at 0x{:04X}: {} instance(s), version {}\n{:<14} {:>6} ",
        board.describe(),
        m.name(),
        m.base_address,
        m.instances,
        m.version,
        "register",
        "addr"
    );
    for i in 0..m.instances {
        out.push_str(&format!(" {i:>8}"));
    }
    out.push('\n');
    for r in 0..m.num_registers as usize {
        let name = names.get(r).copied().unwrap_or("?");
        let per_instance = m.multiple_registers & (1 << r) != 0;
        out.push_str(&format!("{name:<14} {:>6} ", format!("{:04X}", m.reg(r))));
        let n = if per_instance {
            m.instances as usize
        } else {
            1
        };
        for i in 0..n {
            let mut w = [0u32];
            t.read(m.inst_reg(r, i), &mut w)?;
            out.push_str(&format!(" {:08X}", w[0]));
        }
        out.push('\n');
    }
    Ok(out)
}
