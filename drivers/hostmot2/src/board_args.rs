//! `hal-board`'s command line (clap), in the library so the man page is built
//! from it (tools/cli/tests/man_pages.rs).

use std::path::PathBuf;

use clap::{Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  hal-board list
  hal-board idrom 0000:02:00.0              # like mesaflash --readhmid
  hal-board idrom sim:5i25                  # the simulated 5i25
  hal-board read 0000:02:00.0 0x100         # the cookie: 55AACAFE
  hal-board write 0000:02:00.0 0x200 0xC0000000   # both LEDs on
  hal-board watch 0000:02:00.0 stepgen      # refreshes until Ctrl-C
  hal-board watch sim:6i25 encoder -n 3 -i 100
  hal-board probe 0x300                     # which Servo-To-Go is at 0x300
  hal-board probe                           # search 0x3e0 .. 0x200
  hal-board probe 0x300 --via devport       # through /dev/port
  hal-board idrom 192.168.1.121             # an Ethernet board
  hal-board sserial 192.168.1.121           # its Smart Serial cards
  hal-board sserial 127.0.0.1:27181 --config sserial_port_0=2   # hm2-eth-sim

BOARD is a PCI bus address from `hal-board list`, an Ethernet board's IP
address (optionally :port; boards answer on 27181), or sim:5i25,
sim:6i25, sim:5i24, sim:5i25-7i77, sim:5i25-pktuart, sim:7i96s, sim:7i76e,
sim:7i93, sim:7i92, sim:7i95 for a simulated board (fresh for each
command). Reading PCI boards needs access to their
sysfs resource files: see udev/README.md. probe reads ISA ports: it needs
CAP_SYS_RAWIO (--via ioperm or devport); --via sim or sim1 probes a
simulated Model II or I at 0x300.";

/// Bring up a board: list, identify, read and write registers.
#[derive(Parser)]
#[command(name = "hal-board", version, after_help = EXAMPLES)]
pub struct Cli {
    /// Where the PCI devices are (a test's fake sysfs tree).
    #[arg(long, default_value = "/sys/bus/pci/devices", global = true)]
    pub sysfs: PathBuf,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// hal-board's subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// List the boards on the PCI bus that a driver knows, and the simulated ones.
    List,
    /// Print the IDROM, the modules and the pin-out (mesaflash --readhmid).
    #[command(alias = "readhmid")]
    Idrom {
        /// The board.
        board: String,
    },
    /// Read one register; prints its value in hex.
    Read {
        /// The board.
        board: String,
        /// Register address (decimal or 0x hex).
        addr: String,
    },
    /// Write one register.
    Write {
        /// The board.
        board: String,
        /// Register address (decimal or 0x hex).
        addr: String,
        /// Value (decimal or 0x hex).
        value: String,
    },
    /// List the Smart Serial cards with their modes, process data and
    /// globals (resets the ports: not while a HAL runs the board).
    Sserial {
        /// The board.
        board: String,
        /// Channel modes as in the config string (sserial_port_0=2x...).
        #[arg(long, default_value = "")]
        config: String,
    },
    /// Watch a module's registers (stepgen, encoder, pwmgen, ioport, watchdog, led).
    Watch {
        /// The board.
        board: String,
        /// The module.
        module: String,
        /// Refresh interval in milliseconds.
        #[arg(short, long, default_value_t = 500)]
        interval: u64,
        /// Stop after this many snapshots.
        #[arg(short = 'n', long)]
        count: Option<u64>,
    },
    /// Report the Servo-To-Go model at an ISA base address, or search them all.
    Probe {
        /// Base address (0x200, 0x220, ... 0x3e0); none searches them all.
        base: Option<String>,
        /// How to reach the ports: ioperm, devport, sim (Model II at 0x300), sim1.
        #[arg(long, default_value = "ioperm")]
        via: String,
    },
}
