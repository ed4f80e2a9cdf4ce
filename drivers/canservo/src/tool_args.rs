//! `canservo-tool`'s command line (clap), in the library so the man page is built
//! from it (tools/cli/tests/man_pages.rs).

use clap::{Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  canservo-tool --iface can0 scan
  canservo-tool scan --reset                      # NMT reset communication first, list boot-ups
  canservo-tool read 1 1018:01 u32                # vendor-ID of node 1
  canservo-tool read 1 1008:00 str                # device name (segmented upload)
  canservo-tool write 1 6098:00 i8 19             # homing method
  canservo-tool status 2
  canservo-tool power 2 up                        # shutdown, switch on, enable operation
  canservo-tool power 2 quick-stop
  canservo-tool power 2 fault-reset
  canservo-tool nmt 0 start                       # NMT start, all nodes
  canservo-tool watch --nodes 1,2 --count 20
  canservo-tool watch --nodes 1 --read-mapping --start --sync-ms 10 --seconds 2
  canservo-tool --sim 1,2,3 scan                  # simulated drives, no hardware

Objects are INDEX:SUB in hexadecimal (0x optional). Types: u8 u16 u32 i8 i16 i32 (and str
for reading). Power steps: shutdown, switch-on, enable-operation, disable-operation,
disable-voltage, quick-stop, fault-reset, up, down; before enabling, the tool copies the
actual position into the target so the drive does not move. Do not run it on a bus a
running canservo driver owns: two SDO clients on one drive answer each other's requests.";

/// Bring-up tool for CANopen CiA 402 servo drives.
#[derive(Parser, Debug)]
#[command(name = "canservo-tool", version, after_help = EXAMPLES)]
pub struct Cli {
    /// CAN interface.
    #[arg(long, default_value = "can0", global = true)]
    pub iface: String,
    /// Use simulated drives at these node ids instead of an interface.
    #[arg(long, value_delimiter = ',', global = true, value_parser = clap::value_parser!(u8).range(1..=127))]
    pub sim: Vec<u8>,
    /// How long to wait for each answer (ms).
    #[arg(long, default_value_t = 500, global = true)]
    pub timeout_ms: u64,
    /// What to do.
    #[command(subcommand)]
    pub command: Cmd,
}

/// canservo-tool's subcommands.
#[derive(Subcommand, Debug)]
pub enum Cmd {
    /// Find the nodes and show their identity (0x1000, 0x1018, 0x1008).
    Scan {
        /// Send NMT reset communication to all nodes first and list the boot-ups.
        #[arg(long)]
        reset: bool,
    },
    /// Read an object by SDO.
    Read {
        /// Node id.
        #[arg(value_parser = clap::value_parser!(u8).range(1..=127))]
        node: u8,
        /// INDEX:SUB (hex).
        object: String,
        /// u8, u16, u32, i8, i16, i32 or str; default: raw bytes.
        ty: Option<String>,
    },
    /// Write an object by SDO.
    Write {
        /// Node id.
        #[arg(value_parser = clap::value_parser!(u8).range(1..=127))]
        node: u8,
        /// INDEX:SUB (hex).
        object: String,
        /// u8, u16, u32, i8, i16 or i32.
        ty: String,
        /// Decimal or 0x hex; negative for signed types.
        #[arg(allow_hyphen_values = true)]
        value: String,
    },
    /// Show a drive's statusword decoded, its mode, errors and NMT state.
    Status {
        /// Node id.
        #[arg(value_parser = clap::value_parser!(u8).range(1..=127))]
        node: u8,
    },
    /// Step a drive through the CiA 402 power states.
    Power {
        /// Node id.
        #[arg(value_parser = clap::value_parser!(u8).range(1..=127))]
        node: u8,
        /// The step.
        step: String,
    },
    /// Send an NMT command: start, stop, pre-operational, reset, reset-communication.
    Nmt {
        /// Node id, 0 for all.
        #[arg(value_parser = clap::value_parser!(u8).range(0..=127))]
        node: u8,
        /// The command.
        command: String,
    },
    /// Show the bus traffic with decoded fields.
    Watch {
        /// Drives whose PDOs to decode.
        #[arg(long, value_delimiter = ',')]
        nodes: Vec<u8>,
        /// Read the drives' PDO mappings first (default: canservo's layout).
        #[arg(long)]
        read_mapping: bool,
        /// Send NMT start to the drives first.
        #[arg(long)]
        start: bool,
        /// Produce SYNC at this period (ms) while watching.
        #[arg(long)]
        sync_ms: Option<u64>,
        /// Stop after this many frames.
        #[arg(long)]
        count: Option<usize>,
        /// Stop after this long (s).
        #[arg(long)]
        seconds: Option<f64>,
    },
}
