//! hm2-eth-sim: a simulated Mesa Ethernet board answering LBP16 on UDP,
//! in a process of its own, so `loadrt hm2_eth` talks to it exactly as
//! to a card on the network.

use std::net::UdpSocket;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;
use std::time::Duration;

use clap::Parser;
use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};
use hostmot2::regs::gtag;
use hostmot2::sim::boards;
use hostmot2::sim::eth::{preset_board, EthIdentity};
use hostmot2::sim::eth_server::{Faults, Server};

use hostmot2::eth_sim_args::Cli;
use hostmot2::ToolError;

fn main() {
    let cli = Cli::parse();
    if let Err(e) = run(cli) {
        eprintln!("hm2-eth-sim: {e}");
        std::process::exit(1);
    }
}

/// A fault rate given as `--option`: a probability.
fn rate(option: &'static str, value: f64) -> Result<f64, ToolError> {
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        Err(ToolError::NotAProbability { option, value })
    }
}

fn run(cli: Cli) -> Result<(), ToolError> {
    let mut spec = boards::preset(&cli.board)
        .filter(|_| boards::eth_name(&cli.board).is_some())
        .ok_or_else(|| ToolError::NotAnEthBoard {
            board: cli.board.clone(),
            boards: boards::ETH_PRESETS.join(", "),
        })?;
    let sserial = spec.modules.iter().any(|m| m.gtag == gtag::SSERIAL);
    let remote = cli.remote.as_deref();
    spec.remotes = match remote.unwrap_or(if sserial { "7i76" } else { "none" }) {
        "7i76" | "7i77" if !sserial => {
            return Err(ToolError::NoSmartSerial {
                remote: remote.unwrap_or_default().to_string(),
                board: cli.board.clone(),
            })
        }
        "7i76" => vec![boards::seven_i76_on(0, 0)],
        "7i77" if cli.board == "7i96s" => boards::seven_i77_on(0, 0).to_vec(),
        "7i77" => return Err(ToolError::RemoteNeedsTwoChannels),
        "none" => Vec::new(),
        other => {
            return Err(ToolError::NotARemote {
                remote: other.to_string(),
            })
        }
    };
    let faults = Faults {
        drop_requests: rate("drop-requests", cli.drop_requests)?,
        drop_writes: rate("drop-writes", cli.drop_writes)?,
        drop_replies: rate("drop-replies", cli.drop_replies)?,
        delay_rate: rate("delay", cli.delay)?,
        delay: Duration::from_micros(cli.delay_us),
        duplicate: rate("duplicate", cli.duplicate)?,
        seed: cli.seed,
    };
    let board = preset_board(&cli.board, spec, EthIdentity::new("").ip).ok_or_else(|| {
        ToolError::NotAnEthBoard {
            board: cli.board.clone(),
            boards: boards::ETH_PRESETS.join(", "),
        }
    })?;
    let name = board.identity().name.clone();
    let board = if cli.wall_clock {
        board.with_wall_clock()
    } else {
        board.with_period(cli.period_ns)
    };
    let socket = UdpSocket::bind(cli.listen).map_err(|source| ToolError::Socket {
        addr: cli.listen,
        source,
    })?;
    let server = Server::new(socket, board, faults);
    let addr = server.local_addr().map_err(|source| ToolError::Socket {
        addr: cli.listen,
        source,
    })?;
    let exit = ExitSignals::install().map_err(|source| ToolError::Signals { source })?;
    let hal = if cli.hal {
        let inst = Instance::attach(&hal_core::instance_from_env())?;
        let comp = inst.new_component("hm2-eth-sim", ComponentKind::User)?;
        Some((inst, comp))
    } else {
        None
    };
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let serving = std::thread::spawn(move || server.run(&flag));
    let line = format!(
        "hm2-eth-sim: {name} (simulated {}) answering on {addr}",
        cli.board
    );
    if cli.hal {
        // Inside a HAL file stdout is the HAL session's output.
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
    if let Some((_, comp)) = &hal {
        comp.ready()?;
    }
    while !exit.requested() && !serving.is_finished() {
        if let Some((inst, _)) = &hal {
            if !inst.host_alive() {
                break;
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    stop.store(true, Relaxed);
    let result = serving.join().map_err(|_| ToolError::ServerPanicked)?;
    drop(hal);
    result.map_err(|source| ToolError::Socket { addr, source })
}
