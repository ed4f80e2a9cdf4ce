//! `ethercat-tool`'s command line (clap), in the library so its man page
//! is built from it (tools/cli/tests/man_pages.rs).

use clap::{Parser, Subcommand};

use crate::Error;

const EXAMPLES: &str = "\
Examples:
  ethercat-tool --iface eth1 slaves
  ethercat-tool --iface eth1 slaves -v                # identity and AL status code too
  ethercat-tool --iface eth1 master
  ethercat-tool --iface eth1 states -p 3 OP
  ethercat-tool --iface eth1 sii-read -p 2 > el2008.sii
  ethercat-tool --iface eth1 sii-read -p 2 -v         # decoded
  ethercat-tool --iface eth1 pdos -p 5
  ethercat-tool --iface eth1 upload -p 7 0x1018 1 -t uint32
  ethercat-tool --iface eth1 upload -p 7 0x1008 0     # device name (segmented upload)
  ethercat-tool --iface eth1 download -p 7 0x6060 0 8 -t int8
  ethercat-tool --sim segment.txt slaves               # a simulated segment, no interface

Numbers are decimal or 0x hexadecimal. Types: bool, int8, int16, int32, int64, uint8,
uint16, uint32, uint64, float, double, string, octet_string (hex pairs). The tool is a
master of its own: it scans the segment and brings it to PRE-OP, so do not run it on an
interface a running lcec owns. Raw sockets need CAP_NET_RAW (the hal group's setup).";

/// Bring-up tool for an EtherCAT segment, modelled on IgH's `ethercat`.
#[derive(Parser, Debug)]
#[command(name = "ethercat-tool", version, after_help = EXAMPLES)]
pub struct Cli {
    /// Network interface the segment is on.
    #[arg(long, default_value = "eth0", global = true)]
    pub iface: String,
    /// Run against a simulated segment described by this file (as
    /// ethercat-sim reads it) instead of an interface.
    #[arg(long, global = true)]
    pub sim: Option<std::path::PathBuf>,
    /// What to do.
    #[command(subcommand)]
    pub command: Cmd,
}

/// ethercat-tool's subcommands.
#[derive(Subcommand, Debug)]
pub enum Cmd {
    /// List the slaves: position, alias:position, state, error flag, name.
    Slaves {
        /// Identity, station address and AL status code too.
        #[arg(short, long)]
        verbose: bool,
    },
    /// Show the master: interface, link, slaves, frame counters.
    Master,
    /// Request an AL state (INIT, PREOP, BOOT, SAFEOP, OP) of one slave or all.
    States {
        /// Slave position (default: every slave).
        #[arg(short, long, value_parser = parse_u16)]
        position: Option<u16>,
        /// The state.
        state: String,
    },
    /// Output a slave's SII: the raw image, or decoded with -v.
    SiiRead {
        /// Slave position.
        #[arg(short, long, value_parser = parse_u16)]
        position: u16,
        /// Decoded instead of raw bytes.
        #[arg(short, long)]
        verbose: bool,
    },
    /// Show the sync managers, PDOs and PDO entries of one slave or all (from the SII).
    Pdos {
        /// Slave position (default: every slave).
        #[arg(short, long, value_parser = parse_u16)]
        position: Option<u16>,
    },
    /// Read an SDO.
    Upload {
        /// Slave position.
        #[arg(short, long, value_parser = parse_u16)]
        position: u16,
        /// Data type (default: by size).
        #[arg(short, long = "type")]
        ty: Option<String>,
        /// Object index.
        #[arg(value_parser = parse_u16)]
        index: u16,
        /// Sub-index.
        #[arg(value_parser = parse_u8)]
        sub: u8,
    },
    /// Write an SDO (segmented when it does not fit the mailbox).
    Download {
        /// Slave position.
        #[arg(short, long, value_parser = parse_u16)]
        position: u16,
        /// Data type.
        #[arg(short, long = "type")]
        ty: String,
        /// Object index.
        #[arg(value_parser = parse_u16)]
        index: u16,
        /// Sub-index.
        #[arg(value_parser = parse_u8)]
        sub: u8,
        /// The value.
        #[arg(allow_hyphen_values = true)]
        value: String,
    },
}

/// A decimal or `0x` hexadecimal number.
fn parse_number(s: &str) -> Result<u64, Error> {
    let r = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(h) => u64::from_str_radix(h, 16),
        None => s.parse(),
    };
    r.map_err(|source| Error::NotANumber {
        given: s.to_string(),
        source,
    })
}

/// The refusal of `given`, larger than its field's `max`.
fn too_large(given: &str, max: u64) -> Error {
    Error::NumberTooLarge {
        given: given.to_string(),
        max,
    }
}

fn parse_u16(s: &str) -> Result<u16, Error> {
    u16::try_from(parse_number(s)?).map_err(|_| too_large(s, u16::MAX.into()))
}

fn parse_u8(s: &str) -> Result<u8, Error> {
    u8::try_from(parse_number(s)?).map_err(|_| too_large(s, u8::MAX.into()))
}
