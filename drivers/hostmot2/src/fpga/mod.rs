//! Loading an FPGA from a bitfile: the PCI cards without flash (5i20,
//! 5i21, 5i22, 5i23, 4i65, 4i68, 4i69, 3x20) forget their firmware at
//! power-off, and LinuxCNC configures them at every load from the file
//! the config string's `firmware=` names (hardware.md 5.1, 5.7 step 3).
//!
//! `firmware=hm2/5i20/SVST8_4.BIT` names a file under the firmware
//! directory, `/lib/firmware` as LinuxCNC finds it ([`FIRMWARE_DIR`];
//! `hm2_pci`'s parameter `firmware_dir=` points elsewhere, for tests and
//! for firmware kept out of the system directory). The name must be
//! relative and stay inside the directory (no `..`). The file is parsed
//! ([`bitfile`]), its part checked against the card's, and its bitstream
//! clocked in through the bridge ([`plx`]). Every failure names the step.

pub mod bitfile;
pub mod plx;

use std::path::{Component, Path, PathBuf};

use thiserror::Error;

pub use bitfile::BitFile;
pub use plx::{Bridge, PlxPorts};

/// Where LinuxCNC's loader finds `firmware=` files.
pub const FIRMWARE_DIR: &str = "/lib/firmware";

/// Longest `firmware=` name accepted.
pub const MAX_NAME: usize = 255;

/// A step of the load, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgramStep {
    /// The bridge's local-bus setup before any load.
    BridgeSetup,
    /// The /PROGRAM pulse that clears the FPGA.
    Reset,
    /// Waiting for the FPGA to finish clearing (/INIT high).
    WaitInit,
    /// Streaming the bitstream.
    Load,
    /// The DONE and /INIT checks after the bitstream.
    CheckDone,
}

impl std::fmt::Display for ProgramStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ProgramStep::BridgeSetup => "bridge setup",
            ProgramStep::Reset => "reset (/PROGRAM pulse)",
            ProgramStep::WaitInit => "waiting for /INIT",
            ProgramStep::Load => "bitstream load",
            ProgramStep::CheckDone => "DONE check",
        })
    }
}

/// Why a bitfile could not be read or loaded.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FpgaError {
    /// The `firmware=` name is not a relative path inside the directory.
    #[error("firmware name \"{name}\": {reason}")]
    BadName {
        /// The name given.
        name: String,
        /// Why it is refused.
        reason: &'static str,
    },
    /// The file could not be read.
    #[error("cannot read the bitfile {}: {reason}", path.display())]
    BitfileRead {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The file ends inside a field.
    #[error(
        "bitfile cut short: {what} at byte {offset} needs {needed} bytes, only {left} are left"
    )]
    BitfileTruncated {
        /// The field being read.
        what: &'static str,
        /// Where it starts.
        offset: usize,
        /// Bytes it needs.
        needed: usize,
        /// Bytes there are.
        left: usize,
    },
    /// The header's framing is wrong.
    #[error("not a Xilinx bitfile: {reason}")]
    BitfileHeader {
        /// What is wrong.
        reason: String,
    },
    /// A section is wrong.
    #[error("bitfile section '{key}' {reason}")]
    BitfileField {
        /// The section's key.
        key: char,
        /// What is wrong.
        reason: String,
    },
    /// The bitfile is for another FPGA.
    #[error("bitfile is for the FPGA part '{file}', but this board has a '{board}'")]
    WrongPart {
        /// The part the bitfile names.
        file: String,
        /// The board's part.
        board: String,
    },
    /// The board cannot be programmed (it has flash, or no bridge lines).
    #[error("this board cannot be programmed with firmware= ({reason})")]
    NotProgrammable {
        /// Why.
        reason: String,
    },
    /// A programming step failed.
    #[error("FPGA programming failed at the {step} step: {reason}")]
    Program {
        /// The step.
        step: ProgramStep,
        /// Why.
        reason: String,
    },
}

/// The path of firmware `name` under `dir`, refusing names that are
/// empty, too long, absolute or leave the directory.
pub fn resolve(dir: &Path, name: &str) -> Result<PathBuf, FpgaError> {
    let bad = |reason| FpgaError::BadName {
        name: name.to_string(),
        reason,
    };
    if name.is_empty() {
        return Err(bad("empty"));
    }
    if name.len() > MAX_NAME {
        return Err(bad("longer than 255 bytes"));
    }
    let rel = Path::new(name);
    for c in rel.components() {
        match c {
            Component::Normal(_) | Component::CurDir => {}
            Component::ParentDir => return Err(bad("'..' would leave the firmware directory")),
            Component::RootDir | Component::Prefix(_) => {
                return Err(bad("must be relative to the firmware directory"))
            }
        }
    }
    Ok(dir.join(rel))
}

/// Checks that `file` is for `part` (the board's FPGA, as its llio
/// names it).
pub fn check_part(file: &BitFile, part: &str) -> Result<(), FpgaError> {
    if file.part != part {
        return Err(FpgaError::WrongPart {
            file: file.part.clone(),
            board: part.to_string(),
        });
    }
    Ok(())
}

/// The log line for a loaded bitfile, as LinuxCNC's loader prints its header.
pub fn describe(name: &str, file: &BitFile) -> String {
    format!(
        "firmware {name}: design '{}', part '{}', built {} {}, {} bytes of bitstream",
        file.design,
        file.part,
        file.date,
        file.time,
        file.bitstream.len()
    )
}

/// Reads `name` under `dir`, checks it is for `part`, and programs it
/// through `ports`. Returns the bitfile, for the log.
pub fn load(
    dir: &Path,
    name: &str,
    part: &str,
    ports: &PlxPorts<'_>,
) -> Result<BitFile, FpgaError> {
    let path = resolve(dir, name)?;
    let file = bitfile::read(&path)?;
    check_part(&file, part)?;
    plx::program(ports, &file.bitstream)?;
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stay_inside_the_firmware_directory() {
        let d = Path::new("/lib/firmware");
        assert_eq!(
            resolve(d, "hm2/5i20/SVST8_4.BIT").unwrap(),
            Path::new("/lib/firmware/hm2/5i20/SVST8_4.BIT")
        );
        for (name, why) in [
            ("", "empty"),
            ("../etc/passwd", "'..'"),
            ("hm2/../../x", "'..'"),
            ("/etc/passwd", "relative"),
        ] {
            let e = resolve(d, name).unwrap_err().to_string();
            assert!(e.contains(why), "{name}: {e}");
        }
        let long = "a".repeat(256);
        assert!(resolve(d, &long).is_err());
    }

    #[test]
    fn a_bitfile_for_another_part_is_refused() {
        let f = bitfile::parse(&bitfile::build("x.ncd", "3s400pq208", "", "", &[1])).unwrap();
        assert!(check_part(&f, "3s400pq208").is_ok());
        let e = check_part(&f, "2s200pq208").unwrap_err().to_string();
        assert!(
            e.contains("'3s400pq208'") && e.contains("'2s200pq208'"),
            "{e}"
        );
    }
}
