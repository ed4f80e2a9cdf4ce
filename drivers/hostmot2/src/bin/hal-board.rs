//! hal-board: bring up a board. Lists the PCI boards the suite's drivers
//! know (HostMot2 with their IDROM's name, MOTENC with their version and
//! board ID; and the simulated ones), prints a HostMot2 board's IDROM,
//! module list and pin-out as `mesaflash --readhmid` does (PCI, Ethernet by
//! address, simulated), its Smart Serial cards with their process data,
//! reads and writes single registers, and watches a module's registers
//! live. For the ISA Servo-To-Go, `probe` reports the model at a base
//! address.

use std::io::{IsTerminal, Write};
use std::time::Duration;

use clap::Parser;
use hal_core::userspace::ExitSignals;
use hal_driver::pci::Sysfs;
use hal_stg::port_probe;
use hostmot2::board_tool::{self, Board};
use hostmot2::ToolError;

use hostmot2::board_args::{Cli, Command};

fn main() {
    let cli = Cli::parse();
    if let Err(e) = run(cli) {
        eprintln!("hal-board: {e}");
        std::process::exit(1);
    }
}

fn run(cli: Cli) -> Result<(), ToolError> {
    let sysfs = Sysfs::at(&cli.sysfs);
    match cli.command {
        Command::List => {
            for line in board_tool::list(&sysfs) {
                hal_core::outln!("{line}");
            }
        }
        Command::Idrom { board } => {
            let b = Board::open(&board, &sysfs)?;
            hal_core::out!("{}", board_tool::idrom(&b)?);
        }
        Command::Read { board, addr } => {
            let addr = board_tool::parse_address(&addr)?;
            let b = Board::open(&board, &sysfs)?;
            hal_core::outln!("{:08X}", board_tool::read(&b, addr)?);
        }
        Command::Write { board, addr, value } => {
            let addr = board_tool::parse_address(&addr)?;
            let value = board_tool::parse_value(&value)?;
            let b = Board::open(&board, &sysfs)?;
            board_tool::write(&b, addr, value)?;
        }
        Command::Sserial { board, config } => {
            let b = Board::open(&board, &sysfs)?;
            print!("{}", board_tool::sserial(&b, &config)?);
        }
        Command::Watch {
            board,
            module,
            interval,
            count,
        } => {
            let b = Board::open(&board, &sysfs)?;
            let m = board_tool::find_module(&b, &module)?;
            let exit = ExitSignals::install().map_err(|source| ToolError::Signals { source })?;
            let tty = std::io::stdout().is_terminal();
            let mut shown = 0;
            while count.is_none_or(|n| shown < n) && !exit.requested() {
                if shown > 0 {
                    std::thread::sleep(Duration::from_millis(interval));
                    b.advance(interval * 1_000_000);
                }
                let frame = board_tool::module_frame(&b, &m)?;
                if tty {
                    // Redraw in place: home the cursor, clear the screen.
                    hal_core::out!("\x1b[H\x1b[2J{frame}");
                    let _ = std::io::stdout().flush();
                } else {
                    hal_core::outln!("{frame}");
                }
                shown += 1;
            }
        }
        Command::Probe { base, via } => {
            let via = port_probe::parse_via(&via)?;
            let base = base.as_deref().map(port_probe::parse_base).transpose()?;
            for line in port_probe::probe(base, via)? {
                println!("{line}");
            }
        }
    }
    Ok(())
}
