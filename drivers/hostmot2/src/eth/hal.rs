//! The `hm2_eth` loadrt module: probes the boards listed in `board_ip`,
//! identifies each from its space-7 name and registers it with the
//! hostmot2 core over an [`EthTransport`].

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::HalError;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;
use hal_driver::ForModule;

use super::boards::{self, LEDS};
use super::transport::EthTransport;
use crate::error::Hm2Error;
use crate::hal::{core, export_boards, Boards, Candidate, Source};
use crate::lbp16::{self, addr, space};
use crate::llio::Llio;
use crate::transport::{Transport, TransportError};

/// Most boards one `hm2_eth` load drives (LinuxCNC's `MAX_ETH_BOARDS`).
pub const MAX_ETH_BOARDS: usize = 4;

const HM2_ETH: &str = "hm2_eth";

/// hm2_eth's module parameters (one table, read by both hosts); the
/// arrays hold [`MAX_ETH_BOARDS`] items.
#[macro_export]
macro_rules! hm2_eth_params {
    ($($then:tt)*) => { $($then)*! {
        board_ip: StrArray(4) = "the boards' IP addresses (optionally :port), comma-separated",
        config: StrArray(4) = "hostmot2 config strings, one per board (see hostmot2(9))",
        board_rtnet: StrArray(4) = "socket kind per board: posix (the only one supported)",
        firewall: Str = "accepted for compatibility (auto, iptables, nft, nftables, none): the host's firewall is never changed",
        debug: Int = "LinuxCNC logs every packet; here use tcpdump -X udp port 27181",
    } };
}

/// The `hm2_eth` driver.
#[derive(Debug)]
pub struct HalHm2Eth;

/// The `hm2_eth` module.
pub static HM2_ETH_MODULE: ModuleDef = module::module_def::<HalHm2Eth>();

impl DriverModule for HalHm2Eth {
    const NAME: &'static str = HM2_ETH;
    const HELP: &'static str =
        "Mesa Ethernet Anything I/O boards with HostMot2 firmware (LBP16 over UDP)";
    const PARAMS: &'static [ParamDecl] = hm2_eth_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        open_eth(args, env)
    }

    fn export<H: DriverHost>(found: Boards, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        export_boards(found, ex)
    }
}

/// Parses one `board_ip` item: an IPv4 or IPv6 address, optionally with
/// a port (`192.168.1.121`, `127.0.0.1:40123`, `[::1]:40123`).
pub fn parse_board_address(s: &str) -> Result<SocketAddr, Hm2Error> {
    if let Ok(ip) = s.parse::<IpAddr>() {
        return Ok(SocketAddr::new(ip, lbp16::UDP_PORT));
    }
    s.parse::<SocketAddr>().map_err(|_| Hm2Error::NotAnAddress)
}

/// What a probe learned about a board.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Probe {
    /// The space-7 name.
    pub name: String,
    /// The MAC address.
    pub mac: [u8; 6],
}

/// Reads the board's name (space 7) and MAC (space 2).
pub fn probe(t: &mut EthTransport) -> Result<Probe, TransportError> {
    let mut name = [0u16; 8];
    t.read16(space::BOARD_INFO, false, addr::INFO_NAME, &mut name)?;
    let raw: Vec<u8> = name.iter().flat_map(|w| w.to_le_bytes()).collect();
    let mut mac_words = [0u16; 3];
    t.read16(space::ETH_EEPROM, false, addr::EEPROM_MAC, &mut mac_words)?;
    let b: Vec<u8> = mac_words.iter().flat_map(|w| w.to_le_bytes()).collect();
    Ok(Probe {
        name: boards::name_text(&raw),
        mac: [b[5], b[4], b[3], b[2], b[1], b[0]],
    })
}

/// The llio of a board the table does not know: connectors and pins
/// from its IDROM.
pub fn llio_from_idrom(t: &mut EthTransport, name: &str, n: usize) -> Result<Llio, TransportError> {
    let mut w = [0u32; 1];
    t.read(crate::regs::IDROM_OFFSET_ADDR as u32, &mut w)?;
    let idrom = w[0] & 0xFFFF;
    let mut ports = [0u32; 3];
    t.read(idrom + crate::regs::idrom::IO_PORTS as u32, &mut ports)?;
    Ok(boards::unknown_llio(
        name,
        n,
        ports[0].clamp(1, 8),
        ports[2].max(1),
    ))
}

/// Probes the boards `args` list.
fn open_eth(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
    let debug = core(env, HM2_ETH)?;
    let params = Params::new(HM2_ETH, args);
    let log = env.log();
    log.info(format_args!(
        "hm2_eth: loading Mesa AnyIO HostMot2 ethernet driver version 0.2"
    ));
    let ips = args.str_array("board_ip");
    if ips.is_empty() {
        return Err(params
            .error(
                "board_ip",
                "no board given: hm2_eth probes only the listed boards (board_ip=192.168.1.121)",
            )
            .into_hal(HM2_ETH));
    }
    for (i, r) in args.str_array("board_rtnet").iter().enumerate() {
        if !r.is_empty() && r != "posix" {
            return Err(params
                .item_error("board_rtnet", i, r, "only posix sockets are supported")
                .into_hal(HM2_ETH));
        }
    }
    let firewall = params
        .choice("firewall", &["auto", "iptables", "nft", "nftables", "none"])
        .for_module(HM2_ETH)?;
    if params.int_or("debug", 0) != 0 {
        log.info(format_args!(
            "hm2_eth: debug: packets are not logged here; capture them with tcpdump -X udp port {}",
            lbp16::UDP_PORT
        ));
    }
    let mut counts: HashMap<String, usize> = HashMap::new();
    let mut next = |board: &str| {
        let n = counts.entry(board.to_string()).or_insert(0);
        *n += 1;
        *n - 1
    };
    // Every address is read and checked before any board is probed.
    let mut peers: Vec<SocketAddr> = Vec::with_capacity(ips.len());
    for (i, ip) in ips.iter().enumerate() {
        let peer = parse_board_address(ip)
            .map_err(|reason| params.item_error("board_ip", i, ip, reason))
            .for_module(HM2_ETH)?;
        if let Some(first) = peers.iter().position(|&earlier| earlier == peer) {
            return Err(params
                .item_error("board_ip", i, ip, Hm2Error::SameBoardTwice { first, peer })
                .into_hal(HM2_ETH));
        }
        peers.push(peer);
    }
    let mut candidates = Vec::new();
    for (ip, &peer) in ips.iter().zip(&peers) {
        let refuse = |e: TransportError| {
            log.err(format_args!("hm2_eth: board at {peer}: {e}"));
            HalError::module_failed(
                HM2_ETH,
                Hm2Error::EthBoard {
                    address: ip.to_string(),
                    peer,
                    source: e,
                },
            )
        };
        let mut t = EthTransport::connect(peer).map_err(refuse)?;
        let found = probe(&mut t).map_err(refuse)?;
        log.info(format_args!("hm2_eth: discovered {}", found.name));
        let llio = match boards::lookup(&found.name) {
            Some(kind) => kind.llio(next(kind.board)),
            None => {
                log.err(format_args!(
                    "hm2_eth: Unrecognized ethernet board found: {} -- port names will be wrong",
                    found.name
                ));
                let short = boards::unknown_llio(&found.name, 0, 1, 1).name;
                let board = short
                    .trim_start_matches("hm2_")
                    .trim_end_matches(".0")
                    .to_string();
                llio_from_idrom(&mut t, &found.name, next(&board)).map_err(refuse)?
            }
        };
        if !peer.ip().is_loopback() {
            let m = found.mac;
            log.info(format_args!(
                "hm2_eth: {} ({}, MAC {:02x}:{:02x}:{:02x}:{:02x}:{:02x}:{:02x}): the host's ARP table and firewall are left as they are (firewall={}); see the hostmot2 documentation for the dedicated-interface setup",
                llio.name,
                peer.ip(),
                m[0], m[1], m[2], m[3], m[4], m[5],
                firewall.unwrap_or("auto")
            ));
        }
        debug_assert!(llio.num_leds <= LEDS);
        t.set_name(&found.name);
        candidates.push(Candidate {
            place: format!("at {peer}"),
            fails: format!("hm2_eth: board at {peer} fails HM2 registration"),
            llio,
            source: Source::Eth(Box::new(t)),
        });
    }
    Ok(Boards::new(
        env,
        HM2_ETH,
        debug,
        candidates,
        args.str_array("config").to_vec(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn board_addresses() {
        assert_eq!(
            parse_board_address("192.168.1.121").unwrap(),
            "192.168.1.121:27181".parse().unwrap()
        );
        assert_eq!(
            parse_board_address("127.0.0.1:4000").unwrap(),
            "127.0.0.1:4000".parse().unwrap()
        );
        assert!(parse_board_address("[::1]:4000").is_ok());
        for bad in ["", "192.168.1", "host.example", "1.2.3.4:99999", "1.2.3.4:"] {
            assert!(parse_board_address(bad).is_err(), "{bad}");
        }
    }
}
