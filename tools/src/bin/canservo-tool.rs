//! `canservo-tool`: bring up CANopen CiA 402 servo drives: scan the bus,
//! read and write objects, show and step the power state, send NMT
//! commands, watch the traffic decoded. Exit status: 0 done, 1 the
//! drive or bus said no (the message says what), 2 usage.

use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, Subcommand};
use hal_tools::canservo_tool::{Step, Tool, WatchOptions, STEPS};

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
struct Cli {
    /// CAN interface.
    #[arg(long, default_value = "can0", global = true)]
    iface: String,
    /// Use simulated drives at these node ids instead of an interface.
    #[arg(long, value_delimiter = ',', global = true, value_parser = clap::value_parser!(u8).range(1..=127))]
    sim: Vec<u8>,
    /// How long to wait for each answer (ms).
    #[arg(long, default_value_t = 500, global = true)]
    timeout_ms: u64,
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
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

fn run(cli: Cli) -> Result<Vec<String>, String> {
    let timeout = Duration::from_millis(cli.timeout_ms.max(1));
    let tool = if cli.sim.is_empty() {
        Tool::socket(&cli.iface, timeout)?
    } else {
        Tool::sim(&cli.sim, timeout)
    };
    match cli.command {
        Cmd::Scan { reset } => tool.scan(reset),
        Cmd::Read { node, object, ty } => tool.read(node, &object, ty.as_deref()).map(|l| vec![l]),
        Cmd::Write {
            node,
            object,
            ty,
            value,
        } => tool.write(node, &object, &ty, &value).map(|l| vec![l]),
        Cmd::Status { node } => tool.status(node),
        Cmd::Power { node, step } => {
            let s =
                Step::parse(&step).ok_or_else(|| format!("'{step}' is not a step ({STEPS})"))?;
            tool.power(node, s).map(|states| vec![states.join(" -> ")])
        }
        Cmd::Nmt { node, command } => tool.nmt(node, &command).map(|l| vec![l]),
        Cmd::Watch {
            nodes,
            read_mapping,
            start,
            sync_ms,
            count,
            seconds,
        } => {
            if count.is_none() && seconds.is_none() && !cli.sim.is_empty() {
                return Err("with --sim, give --count or --seconds".into());
            }
            let opts = WatchOptions {
                nodes,
                read_mapping,
                start,
                sync: sync_ms.map(Duration::from_millis),
                count,
                duration: seconds.map(Duration::from_secs_f64),
            };
            tool.watch(&opts, |line| println!("{line}"))?;
            Ok(Vec::new())
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(lines) => {
            for l in lines {
                println!("{l}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("canservo-tool: {e}");
            ExitCode::from(1)
        }
    }
}
