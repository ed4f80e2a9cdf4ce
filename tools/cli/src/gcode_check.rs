//! `gcode-run --check` and `--canon`: a program read by the RS274NGC
//! interpreter task runs ([`rs274ngc`]), without a machine. `--check`
//! lists every refusal, earliest first, as `file:line:column: word:
//! text`; `--canon` prints the canonical calls as LinuxCNC's `rs274`
//! does, in the machine's units. With `--ini`, the machine's interpreter
//! settings, tool table and `[TRAJ]LINEAR_UNITS` are used; without, no
//! tools and millimetres.

use std::io::Write;
use std::path::Path;

use hal_lang::ini::Ini;
use hal_launcher::ProgramConfig;
use rs274ngc::{list_refusals_for_machine, Config, Interp, PrintCanon, Status, ToolEntry};

use crate::ToolsError;

/// The interpreter settings, tool table and machine units per mm of
/// `ini` (without one: defaults, no tools, millimetres).
fn setup(ini: Option<&Path>) -> Result<(Config, Vec<ToolEntry>, f64), ToolsError> {
    let Some(path) = ini else {
        return Ok((Config::default(), Vec::new(), 1.0));
    };
    let ini = Ini::load(path).map_err(|e| ToolsError::usage(e.to_string()))?;
    let machine = ProgramConfig::from_ini(&ini);
    let mut config = machine.interp;
    // A check never writes the machine's parameter file.
    config.parameter_file = None;
    let tools = match ini.get("EMCIO", "TOOL_TABLE") {
        Some(table) => {
            let table = ini.dir().join(table.trim());
            rs274ngc::tooltable::load(&table)
                .map_err(|e| ToolsError::usage(format!("{}: {e}", table.display())))?
                .entries
        }
        None => Vec::new(),
    };
    Ok((config, tools, machine.user_per_mm))
}

/// Every refusal of the program at `file`, as lines; empty when it is
/// accepted.
pub fn check(file: &Path, ini: Option<&Path>) -> Result<Vec<String>, ToolsError> {
    let (config, tools, user_per_mm) = setup(ini)?;
    Ok(list_refusals_for_machine(file, config, tools, user_per_mm)
        .iter()
        .map(ToString::to_string)
        .collect())
}

/// Prints the canonical calls of the program at `file` to `out`, as
/// LinuxCNC's `rs274` does; the first refusal ends it with an error.
pub fn canon(file: &Path, ini: Option<&Path>, out: Box<dyn Write>) -> Result<(), ToolsError> {
    let (config, tools, user_per_mm) = setup(ini)?;
    let mut canon = PrintCanon::new(Some(out), tools);
    canon.external_length_units = user_per_mm;
    let mut interp = Interp::new(config);
    let refused = |interp: &Interp, e: rs274ngc::InterpError| {
        ToolsError::usage(format!("{}: {e}", interp.error_location()))
    };
    let r = (|| {
        interp.init(&mut canon).map_err(|e| refused(&interp, e))?;
        interp
            .open(file, &mut canon)
            .map_err(|e| refused(&interp, e))?;
        loop {
            match interp.read(&mut canon) {
                Ok(Status::EndFile) => break,
                Ok(_) => {}
                Err(e) => return Err(refused(&interp, e)),
            }
            match interp.execute(&mut canon) {
                Ok(Status::Exit) => break,
                Ok(_) => {}
                Err(e) => return Err(refused(&interp, e)),
            }
        }
        Ok(())
    })();
    canon.flush();
    r
}
