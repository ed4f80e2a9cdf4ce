//! The FPGA step of a board's registration (hardware.md 5.7 step 3),
//! between the config string and the cookie: a PLX-bridged card named
//! with `firmware=` is loaded from its bitfile; one without is assumed
//! configured already, as LinuxCNC says; boards with flash ignore
//! `firmware=`. The 7I43 on EPP is loaded through its CPLD
//! ([`crate::epp::load`]). A simulated PLX card is loaded the same way through its
//! simulated bridge and then runs the design it was loaded with.

use std::path::Path;
use std::sync::Arc;

use hal_driver::pci::PciDevice;

use crate::config::Config;
use crate::error::{Hm2Error, Result};
use crate::fpga::{self, bitfile, BitFile, Bridge, FpgaError, PlxPorts, ProgramStep};
use crate::hal::Source;
use crate::log::MessageLog;
use crate::pci::PciBoard;
use crate::sim::{self, plx::SimPlxBridge, plx_boards};

/// A simulated PLX card before its FPGA is loaded.
pub struct SimPlxCard {
    /// Its PCI table entry.
    pub board: &'static PciBoard,
    /// Its bridge and FPGA.
    pub bridge: Arc<SimPlxBridge>,
}

impl SimPlxCard {
    /// The simulated card `name` (`5i20`, ...), if there is one.
    pub fn new(name: &str) -> Option<SimPlxCard> {
        let (board, bridge) = plx_boards::card(name)?;
        Some(SimPlxCard {
            board,
            bridge: Arc::new(SimPlxBridge::new(bridge, board.fpga_part)),
        })
    }
}

/// LinuxCNC's words when a programmable board gets no `firmware=`.
pub(crate) const NO_FIRMWARE: &str = "no firmware specified in config modparam!  the board had better have firmware configured already, or this won't work";

/// Loads the FPGA of `source` as `config` asks; returns where the
/// board's registers now are. `dir` overrides the firmware directory.
pub fn configure(
    source: Source,
    config: &Config,
    dir: Option<&Path>,
    log: &mut MessageLog,
) -> Result<Source> {
    let firmware = config.firmware.as_deref();
    match source {
        Source::Pci(opened) => {
            let bridge = Bridge::of_device(opened.kind.ids.vendor, opened.kind.ids.device);
            match (bridge, firmware) {
                (Some(bridge), Some(name)) => {
                    let file = load_pci(&opened.device, bridge, opened.kind.fpga_part, dir, name)
                        .map_err(|source| load_error(name, source))?;
                    log.info(fpga::describe(name, &file));
                }
                (Some(_), None) => log.info(NO_FIRMWARE),
                (None, Some(name)) => log.info(ignored(name)),
                (None, None) => {}
            }
            Ok(Source::Pci(opened))
        }
        Source::SimPlx(card) => {
            let Some(name) = firmware else {
                return Err(Hm2Error::SimNoFirmware {
                    board: card.board.board.into(),
                });
            };
            load_sim(&card, dir, name, log)
        }
        Source::Epp(epp) => crate::epp::load::configure(epp, firmware, dir, log).map(Source::Epp),
        other => {
            if let Some(name) = firmware {
                log.info(ignored(name));
            }
            Ok(other)
        }
    }
}

/// The message for `firmware=` on a board that loads from its flash.
pub(crate) fn ignored(name: &str) -> String {
    format!("firmware={name} ignored: this board loads its FPGA from its own flash")
}

/// A failed load of `name`, as the registration reports it.
pub(crate) fn load_error(name: &str, source: FpgaError) -> Hm2Error {
    Hm2Error::FpgaLoad {
        file: name.to_string(),
        source,
    }
}

/// Opens a PCI card's bridge BARs and loads `name` through them.
fn load_pci(
    device: &PciDevice,
    bridge: Bridge,
    part: &str,
    dir: Option<&Path>,
    name: &str,
) -> std::result::Result<BitFile, FpgaError> {
    let setup = |e: hal_driver::DriverError| FpgaError::Program {
        step: ProgramStep::BridgeSetup,
        reason: e.to_string(),
    };
    let ctrl = device.io_bar(bridge.ctrl_bar()).map_err(setup)?;
    let data = device.io_bar(bridge.data_bar()).map_err(setup)?;
    let ports = PlxPorts {
        bridge,
        ctrl: &ctrl,
        ctrl_base: ctrl.range().base,
        data: &data,
        data_base: data.range().base,
    };
    if bridge == Bridge::Plx9030 {
        fpga::plx::fix_9030_ready(&ports)?;
    }
    fpga::load(
        dir.unwrap_or(Path::new(fpga::FIRMWARE_DIR)),
        name,
        part,
        &ports,
    )
}

/// Loads a simulated card: the bitfile from `dir`, or the simulator's
/// own of the design `name` names; then the card runs that design.
fn load_sim(
    card: &SimPlxCard,
    dir: Option<&Path>,
    name: &str,
    log: &mut MessageLog,
) -> Result<Source> {
    let board = card.board;
    let file = match dir {
        Some(dir) => fpga::resolve(dir, name).and_then(|p| bitfile::read(&p)),
        None => {
            let design = plx_boards::design_of_path(name);
            plx_boards::firmware(&board.into(), design)?;
            bitfile::parse(&sim::plx::bitfile(design, board.fpga_part))
        }
    }
    .map_err(|e| load_error(name, e))?;
    fpga::check_part(&file, board.fpga_part)
        .and_then(|()| fpga::plx::program(&card.bridge.ports(), &file.bitstream))
        .map_err(|e| load_error(name, e))?;
    log.info(fpga::describe(name, &file));
    let design = card.bridge.design().ok_or(Hm2Error::SimFpgaNotRunning {
        what: "raised DONE but runs no design",
    })?;
    Ok(Source::Sim(plx_boards::running(&board.into(), &design)?))
}
