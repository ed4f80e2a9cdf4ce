//! hm2-eth-sim: a simulated Mesa Ethernet board answering LBP16 on UDP,
//! in a process of its own, so `loadrt hm2_eth` talks to it exactly as
//! to a card on the network.

use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;
use std::time::Duration;

use clap::Parser;
use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};
use hostmot2::sim::boards;
use hostmot2::sim::eth::{EthBoard, EthIdentity};
use hostmot2::sim::eth_server::{Faults, Server};
use hostmot2::sim::{machine, Hm2Model};

const EXAMPLES: &str = "\
Examples:
  hm2-eth-sim --board 7i96s                     # on 127.0.0.1:27181
  hm2-eth-sim --board 7i76e --listen 127.0.0.1:0   # a free port, printed
  hm2-eth-sim --drop-replies 0.01 --delay 0.01 --delay-us 2000 --seed 7

In a HAL file (loadusr -W waits until it listens; it exits with the HAL):
  loadusr -W hm2-eth-sim --hal --board 7i96s
  loadrt hostmot2
  loadrt hm2_eth board_ip=127.0.0.1 config=\"num_stepgens=3\"

Boards: 7i96s (5 step generators, 1 encoder, Smart Serial on P1), 7i76e
(the on-card 7i76's step generators and Smart Serial); a simulated 7I76
on Smart Serial (--remote 7i77: a 7I77, --remote none). The machine at the
connectors: stepper axes of 100 steps per unit on every step generator,
home switches closing at +10 units for axes 0..2 (7i96s: I/O 34..36,
7i76e: I/O 17..19). Simulated time moves one --period-ns per cycle's read
request, so every run is the same; --wall-clock follows the host's time.";

/// A simulated Mesa Ethernet board (LBP16 over UDP).
#[derive(Parser, Debug)]
#[command(name = "hm2-eth-sim", version, after_help = EXAMPLES)]
struct Cli {
    /// The board: 7i96s or 7i76e.
    #[arg(long, default_value = "7i96s")]
    board: String,
    /// What is plugged into Smart Serial port 0: 7i76 (channel 0), 7i77
    /// (channels 0 and 1) or none.
    #[arg(long, default_value = "7i76")]
    remote: String,
    /// Address to answer on (port 0: one the system picks).
    #[arg(long, default_value = "127.0.0.1:27181")]
    listen: SocketAddr,
    /// Simulated time per cycle's read request, ns.
    #[arg(long, default_value_t = 1_000_000)]
    period_ns: u64,
    /// Let the host's time pass instead (not repeatable).
    #[arg(long)]
    wall_clock: bool,
    /// Join the HAL instance ($HAL_INSTANCE) as component hm2-eth-sim once
    /// listening (for loadusr -W), and exit when it goes away.
    #[arg(long)]
    hal: bool,
    /// Probability that a request with reads is lost.
    #[arg(long, default_value_t = 0.0)]
    drop_requests: f64,
    /// Probability that a datagram of writes is lost.
    #[arg(long, default_value_t = 0.0)]
    drop_writes: f64,
    /// Probability that a reply is lost.
    #[arg(long, default_value_t = 0.0)]
    drop_replies: f64,
    /// Probability that a reply is delayed by --delay-us.
    #[arg(long, default_value_t = 0.0)]
    delay: f64,
    /// How long a delayed reply is held back, us.
    #[arg(long, default_value_t = 2000)]
    delay_us: u64,
    /// Probability that a reply is sent twice.
    #[arg(long, default_value_t = 0.0)]
    duplicate: f64,
    /// Seed of the fault generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = run(cli) {
        eprintln!("hm2-eth-sim: {e}");
        std::process::exit(1);
    }
}

fn rate(name: &str, p: f64) -> Result<f64, String> {
    if (0.0..=1.0).contains(&p) {
        Ok(p)
    } else {
        Err(format!("--{name} {p}: a probability is between 0 and 1"))
    }
}

fn run(cli: Cli) -> Result<(), String> {
    let mut spec = boards::preset(&cli.board)
        .filter(|_| boards::eth_name(&cli.board).is_some())
        .ok_or_else(|| {
            format!(
                "--board {}: not a simulated Ethernet board ({})",
                cli.board,
                boards::ETH_PRESETS.join(", ")
            )
        })?;
    spec.remotes = match cli.remote.as_str() {
        "7i76" => vec![boards::seven_i76_on(0, 0)],
        "7i77" if cli.board == "7i96s" => boards::seven_i77_on(0, 0).to_vec(),
        "7i77" => return Err("--remote 7i77 needs two channels: --board 7i96s".into()),
        "none" => Vec::new(),
        other => return Err(format!("--remote {other}: 7i76, 7i77 or none")),
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
    let name = boards::eth_name(&cli.board).expect("an Ethernet preset");
    let model = Hm2Model::with_world(spec, Box::new(machine::preset(&cli.board)));
    let board = EthBoard::new(model, EthIdentity::new(name));
    let board = if cli.wall_clock {
        board.with_wall_clock()
    } else {
        board.with_period(cli.period_ns)
    };
    let socket = UdpSocket::bind(cli.listen).map_err(|e| format!("{}: {e}", cli.listen))?;
    let server = Server::new(socket, board, faults);
    let addr = server.local_addr().map_err(|e| e.to_string())?;
    let exit = ExitSignals::install().map_err(|e| e.to_string())?;
    let hal = if cli.hal {
        let inst = Instance::attach(&hal_core::instance_from_env()).map_err(|e| e.to_string())?;
        let comp = inst
            .new_component("hm2-eth-sim", ComponentKind::User)
            .map_err(|e| e.to_string())?;
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
        comp.ready().map_err(|e| e.to_string())?;
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
    let result = serving
        .join()
        .map_err(|_| "the server thread panicked".to_string())?;
    drop(hal);
    result.map_err(|e| format!("{addr}: {e}"))
}
