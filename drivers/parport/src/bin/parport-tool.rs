//! parport-tool: bring up a parallel port. List the ports, watch the
//! inputs live, drive outputs pin by pin, or check a loopback test plug.
//! A port is given as in hal_parport's cfg: `0`, `0x378`, `"0 x raw"`,
//! `"0 simloop"` (the simulator with the plug, to try the tool).

use std::io::{IsTerminal, Write};
use std::time::Duration;

use clap::Parser;
use hal_core::userspace::ExitSignals;
use hal_parport::tool::{format_inputs, list, open, outputs_for, parse_level, selftest};
use hal_parport::tool_args::{Cli, Command};
use hal_parport::PortError;

fn main() {
    let cli = Cli::parse();
    let code = match run(cli.command) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("parport-tool: {e}");
            1
        }
    };
    std::process::exit(code);
}

fn run(command: Command) -> Result<i32, PortError> {
    match command {
        Command::List => {
            let ports = list();
            if ports.is_empty() {
                hal_core::outln!("no parallel ports registered with Linux (is parport_pc loaded?)");
            }
            for p in ports {
                hal_core::outln!("{p}");
            }
            Ok(0)
        }
        Command::Watch { port, count } => {
            let port = open(&port)?;
            let exit = ExitSignals::install().map_err(|source| PortError::Signals { source })?;
            let tty = std::io::stdout().is_terminal();
            hal_core::outln!(
                "{} ({} mode): pin:level",
                port.description,
                port.mode.name()
            );
            let mut shown = 0;
            while count.is_none_or(|n| shown < n) && !exit.requested() {
                let line = format_inputs(port.mode, &port.driver.read());
                if tty {
                    hal_core::out!("\r{line}");
                    let _ = std::io::stdout().flush();
                } else {
                    hal_core::outln!("{line}");
                }
                shown += 1;
                std::thread::sleep(Duration::from_millis(100));
            }
            if tty {
                hal_core::outln!();
            }
            Ok(0)
        }
        Command::Set {
            port,
            levels: wanted,
        } => {
            let port = open(&port)?;
            let levels = wanted
                .iter()
                .map(|a| parse_level(a, port.mode))
                .collect::<Result<Vec<_>, _>>()?;
            port.driver.write(&outputs_for(&levels));
            hal_core::outln!("{}: outputs set; other outputs low", port.description);
            Ok(0)
        }
        Command::Selftest { port } => {
            let port = open(&port)?;
            let results = selftest(&port);
            if results.is_empty() {
                return Err(PortError::NothingToTest {
                    mode: port.mode.name(),
                });
            }
            let mut failed = 0;
            for w in &results {
                hal_core::outln!(
                    "pin {:02} -> pin {:02}: {}",
                    w.out_pin,
                    w.in_pin,
                    if w.ok { "ok" } else { "FAILED" }
                );
                failed += usize::from(!w.ok);
            }
            hal_core::outln!("{} passed, {failed} failed", results.len() - failed);
            Ok(i32::from(failed > 0))
        }
    }
}
