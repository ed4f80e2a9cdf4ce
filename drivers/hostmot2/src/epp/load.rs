//! The FPGA step of a 7I43's registration: `firmware=` names a bitfile
//! under the firmware directory, the CPLD resets the FPGA and reports its
//! size, the bitfile's part is checked against it, and the bitstream goes
//! through the CPLD ([`super::cpld`]). A simulated 7I43 is loaded the
//! same way (with the simulator's own bitfile of the named design unless
//! `firmware_dir=` says where real files are) and then runs the design.
//! The 7I90 loads from its flash: `firmware=` is ignored with a message.

use std::path::Path;

use super::EppSource;
use crate::error::{Hm2Error, Result};
use crate::fpga::{self, bitfile, BitFile, FpgaError};
use crate::log::MessageLog;
use crate::pci_fpga::{ignored, load_error, NO_FIRMWARE};
use crate::sim::{plx_boards, xilinx};

/// Loads `firmware` into the 7I43 behind `epp`; `dir` overrides the
/// firmware directory.
pub fn configure(
    mut epp: Box<EppSource>,
    firmware: Option<&str>,
    dir: Option<&Path>,
    log: &mut MessageLog,
) -> Result<Box<EppSource>> {
    let Some(name) = firmware else {
        if epp.has_cpld {
            log.info(NO_FIRMWARE);
        }
        return Ok(epp);
    };
    if !epp.has_cpld {
        log.info(ignored(name));
        return Ok(epp);
    }
    let simulated = epp.sim_port.is_some();
    let (part, file) = {
        let cpld = epp.transport.cpld();
        let part = cpld
            .reset()
            .and_then(|()| cpld.fpga_part())
            .map_err(|e| load_error(name, e))?;
        let file = bitfile_for(name, part, dir, simulated)?;
        fpga::check_part(&file, part)
            .and_then(|()| cpld.program(&file.bitstream))
            .map_err(|e| load_error(name, e))?;
        (part, file)
    };
    log.info(fpga::describe(name, &file));
    epp.fpga_part = Some(part);
    if let Some(port) = &epp.sim_port {
        let design = port
            .with(|m| m.loaded_design())
            .ok_or(Hm2Error::SimFpgaNotRunning {
                what: "raised DONE but runs no design",
            })?;
        let board = plx_boards::running(&plx_boards::seven_i43(part), &design)?;
        port.with(|m| m.install(board.clone()));
        epp.sim = Some(board);
    }
    Ok(epp)
}

/// The bitfile `name`: read from `dir` (or the system's firmware
/// directory), or for a simulated card without `dir` made by the
/// simulator for the design `name` names, if the simulator knows it.
fn bitfile_for(name: &str, part: &str, dir: Option<&Path>, simulated: bool) -> Result<BitFile> {
    let file: std::result::Result<BitFile, FpgaError> = match dir {
        None if simulated => {
            let design = plx_boards::design_of_path(name);
            plx_boards::firmware(&plx_boards::seven_i43(part), design)?;
            bitfile::parse(&xilinx::bitfile(design, part))
        }
        _ => fpga::resolve(dir.unwrap_or(Path::new(fpga::FIRMWARE_DIR)), name)
            .and_then(|p| bitfile::read(&p)),
    };
    file.map_err(|e| load_error(name, e))
}
