//! `hm2-eth-sim`'s command line (clap), in the library so the man page is built
//! from it (tools/cli/tests/man_pages.rs).

use std::net::SocketAddr;

use clap::Parser;

const EXAMPLES: &str = "\
Examples:
  hm2-eth-sim --board 7i96s                     # on 127.0.0.1:27181
  hm2-eth-sim --board 7i76e --listen 127.0.0.1:0   # a free port, printed
  hm2-eth-sim --drop-replies 0.01 --delay 0.01 --delay-us 2000 --seed 7

In a HAL file (loadusr -W waits until it listens; it exits with the HAL):
  loadusr -W hm2-eth-sim --hal --board 7i96s
  loadrt hostmot2
  loadrt hm2_eth board_ip=127.0.0.1 config=\"num_stepgens=3\"

Boards: 7i96s (5 step generators, 3 encoders, 3 PWM generators, Smart
Serial on P1, a PktUART for hm2_modbus with nothing on its line), 7i76e (the on-card 7i76's step generators and Smart
Serial), 7i93 (two 50-pin headers: 4 servo channels on P2, 8 step
generators on P1), 7i92 (per header 5 step generators and an encoder),
7i95 (6 step generators, 3 encoders); on the boards with Smart Serial a
simulated 7I76 (--remote 7i77: a 7I77, --remote none). The machine at the
connectors: stepper axes of 100 steps per unit on every step generator,
home switches closing at +10 units for axes 0..2 (7i96s: I/O 34..36,
7i76e: I/O 17..19, 7i92: 13..15, 7i95: 29..31); servos (PWM generator k
driving a motor with encoder k on its shaft, leads swapped as LinuxCNC's
hm2-servo samples expect) on the 7i96s's and 7i93's servo channels.
Simulated time moves one --period-ns per cycle's read request, so every
run is the same; --wall-clock follows the host's time.

The same boards run inside the HAL process with loadrt hm2_eth sim=BOARD
(no network, no hm2-eth-sim).";

/// A simulated Mesa Ethernet board (LBP16 over UDP).
#[derive(Parser, Debug)]
#[command(name = "hm2-eth-sim", version, after_help = EXAMPLES)]
pub struct Cli {
    /// The board: 7i96s, 7i76e, 7i93, 7i92 or 7i95.
    #[arg(long, default_value = "7i96s")]
    pub board: String,
    /// What is plugged into Smart Serial port 0: 7i76 (channel 0; the
    /// default on the boards with Smart Serial, 7i96s and 7i76e), 7i77
    /// (channels 0 and 1) or none.
    #[arg(long)]
    pub remote: Option<String>,
    /// Address to answer on (port 0: one the system picks).
    #[arg(long, default_value = "127.0.0.1:27181")]
    pub listen: SocketAddr,
    /// Simulated time per cycle's read request, ns.
    #[arg(long, default_value_t = 1_000_000)]
    pub period_ns: u64,
    /// Let the host's time pass instead (not repeatable).
    #[arg(long)]
    pub wall_clock: bool,
    /// Join the HAL instance ($HAL_INSTANCE) as component hm2-eth-sim once
    /// listening (for loadusr -W), and exit when it goes away.
    #[arg(long)]
    pub hal: bool,
    /// Probability that a request with reads is lost.
    #[arg(long, default_value_t = 0.0)]
    pub drop_requests: f64,
    /// Probability that a datagram of writes is lost.
    #[arg(long, default_value_t = 0.0)]
    pub drop_writes: f64,
    /// Probability that a reply is lost.
    #[arg(long, default_value_t = 0.0)]
    pub drop_replies: f64,
    /// Probability that a reply is delayed by --delay-us.
    #[arg(long, default_value_t = 0.0)]
    pub delay: f64,
    /// How long a delayed reply is held back, us.
    #[arg(long, default_value_t = 2000)]
    pub delay_us: u64,
    /// Probability that a reply is sent twice.
    #[arg(long, default_value_t = 0.0)]
    pub duplicate: f64,
    /// Seed of the fault generator.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}
