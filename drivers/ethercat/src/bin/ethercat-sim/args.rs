//! `ethercat-sim`'s command line (clap), in a file of its own so its man
//! page is built from it too (tools/cli/tests/man_pages.rs includes it).

use clap::Parser;

/// A simulated EtherCAT segment on a network interface.
#[derive(Parser, Debug)]
#[command(
    name = "ethercat-sim",
    version,
    after_help = "Examples:\n  \
        ip link add ecat0 type veth peer name ecat1 && ip link set ecat0 up && ip link set ecat1 up\n  \
        ethercat-sim --iface ecat1 segment.txt\n  \
        echo 'drive-fault 4 0x2310' | ethercat-sim --iface ecat1 segment.txt\n\n\
        The file lists one slave per line: a type (EK1100, EL1008, EL1018, EL2008, EL2088, \
        EL3102, EL4102, EL5101, EL7041, servo, generic) and options (serial=N; for generic \
        vid=, pid=, out=INDEX:SUB:BITS,... and in=...); # starts a comment. Each slave \
        answers every EtherCAT frame on the interface as an ESC does. Standard input takes \
        fault commands, one per line: link down|up, cut N|none, reset N, al-error N CODE, \
        drive-fault N CODE, shaft N COUNTS_PER_S, drift N PPM, clock-step N NS; show N INDEX:SUB prints a slave's object (hexadecimal). Stop with \
        Ctrl-C or SIGTERM. The raw \
        socket needs CAP_NET_RAW."
)]
pub struct Args {
    /// Network interface (one end of a veth pair, or a NIC).
    #[arg(long)]
    pub iface: String,
    /// The segment file.
    pub file: std::path::PathBuf,
}
