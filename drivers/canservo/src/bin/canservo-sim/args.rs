//! `canservo-sim`'s command line (clap), in a file of its own so its man
//! page is built from it too (tools/cli/tests/man_pages.rs includes it).

use clap::Parser;

/// Simulated CiA 402 servo drives on a CAN interface.
#[derive(Parser, Debug)]
#[command(
    name = "canservo-sim",
    version,
    after_help = "Examples:\n  \
        sudo ip link add dev vcan0 type vcan && sudo ip link set vcan0 up\n  \
        canservo-sim --iface vcan0 --nodes 1,2,3\n  \
        canservo-sim --iface can1 --nodes 5 --home 20000\n\n\
        Each drive boots (sends its boot-up message) at start and then answers NMT, SDO, SYNC \
        and RPDOs like a CiA 402 servo drive with a motor on it. Stop with Ctrl-C or SIGTERM; \
        each drive's last controlword and power state are printed then."
)]
pub struct Args {
    /// CAN interface.
    #[arg(long, default_value = "vcan0")]
    pub iface: String,
    /// Node ids of the drives, comma separated (1..127).
    #[arg(long, value_delimiter = ',', required = true, value_parser = clap::value_parser!(u8).range(1..=127))]
    pub nodes: Vec<u8>,
    /// Motor position (counts) from which each drive's home switch is closed.
    #[arg(long, default_value_t = 5000, allow_negative_numbers = true)]
    pub home: i64,
    /// Longest wait for a frame before the drives' time moves on (µs).
    #[arg(long, default_value_t = 1000)]
    pub step_us: u64,
    /// Pause after each frame received (µs) once SIGUSR1 arrives: a
    /// receiver turned slow, whose socket queue overflows under a flood
    /// of frames (for testing a master's safe state).
    #[arg(long, default_value_t = 0)]
    pub read_delay_us: u64,
}
