//! `mesambccc`'s command line (clap), in the library so the man page is
//! built from it (tools/cli/tests/man_pages.rs). LinuxCNC's options:
//! `-o`/`--output`, `-v`/`--verbose`, `-h`/`--help`, one source file.

use std::path::PathBuf;

use clap::Parser;

const EXAMPLES: &str = "\
Examples:
  mesambccc -o spindle.mbccb spindle.mbccs
  mesambccc -v relays.mbccs          # writes mesamodbus.output.mbccb

Then, after the board driver:
  loadrt hm2_modbus ports=hm2_7i96s.0.pktuart.0 mbccbs=spindle.mbccb

The source is LinuxCNC's XML format (see hm2_modbus(9)): <mesamodbus>
with the line settings, <devices>, <initlist> and <commands>. Errors and
warnings name the line and column; on an error nothing is written.";

/// Compiles an hm2_modbus command source (.mbccs, XML) into the binary
/// command file (.mbccb) hm2_modbus loads.
#[derive(Parser, Debug)]
#[command(name = "mesambccc", version, after_help = EXAMPLES)]
pub struct Cli {
    /// Where to write the compiled file.
    #[arg(short, long, default_value = "mesamodbus.output.mbccb")]
    pub output: PathBuf,
    /// List the settings, devices, commands and pins.
    #[arg(short, long)]
    pub verbose: bool,
    /// The source file.
    pub source: PathBuf,
}
