//! `parport-tool`'s command line (clap), in the library so the man page is built
//! from it (tools/cli/tests/man_pages.rs).

use clap::{Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  parport-tool list                         # the ports Linux registered
  parport-tool watch 0                      # inputs of the first port, until Ctrl-C
  parport-tool watch \"0x378 x\" -n 10        # ten snapshots, control lines as inputs
  parport-tool set 0 1=1 14=0 16=1          # these outputs, the others low
  parport-tool selftest 0                   # with the loopback plug in
  parport-tool selftest \"0 simloop\"         # the simulator with the plug

PORT is a hal_parport cfg string for one port, e.g. 0, 0x378, \"0 x\",
\"0x378 x raw\", \"0 simloop\". The selftest plug wires 2-15, 3-13, 4-12,
5-10, 6-11 (checked in out mode) and 7-1, 8-14, 9-16, 6-17 (also checked
in x mode, which needs open-collector control lines). Reaching a real
port needs its I/O ports: see udev/README.md.";

/// Bring up a parallel port: list the ports, watch the inputs live,
/// drive outputs pin by pin, or check a loopback test plug.
#[derive(Parser, Debug)]
#[command(name = "parport-tool", version, after_help = EXAMPLES)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// parport-tool's subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// List the parallel ports registered with Linux.
    List,
    /// Show the input pins' levels, refreshed every 100 ms until Ctrl-C.
    Watch {
        /// The port (a hal_parport cfg string).
        port: String,
        /// Stop after this many snapshots.
        #[arg(short = 'n', long)]
        count: Option<u64>,
    },
    /// Set output pins; the other outputs go low.
    Set {
        /// The port (a hal_parport cfg string).
        port: String,
        /// PIN=0 or PIN=1, for each pin to set.
        levels: Vec<String>,
    },
    /// Check the loopback test plug: each output wire against its input.
    Selftest {
        /// The port (a hal_parport cfg string).
        port: String,
    },
}
