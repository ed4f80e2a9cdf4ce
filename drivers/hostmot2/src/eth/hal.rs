//! The `hm2_eth` loadrt module: probes the boards listed in `board_ip`,
//! identifies each from its space-7 name and registers it with the
//! hostmot2 core over an [`EthTransport`].

use std::collections::HashMap;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::{Arc, Mutex};

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::HalError;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;
use hal_driver::{DriverError, ForModule};

use super::boards::{self, LEDS};
use super::transport::EthTransport;
use crate::error::Hm2Error;
use crate::hal::{core, export_boards, Boards, Candidate, Source};
use crate::lbp16::{self, addr, space};
use crate::llio::Llio;
use crate::sim::{boards as sim_boards, eth as sim_eth};
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
        sim: StrArray(4) = "simulated boards in this process instead of the network (7i96s, 7i76e, 7i93, 7i92, 7i95), one per board; board_ip then only names them in messages",
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
        "Mesa Ethernet Anything I/O boards with HostMot2 firmware (LBP16 over UDP; or simulated ones: sim=7i96s)";
    const PARAMS: &'static [ParamDecl] = hm2_eth_params!(hal_driver::param_table);
    type Opened = Boards;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Boards> {
        open_eth(args, env, &EthTransport::connect)
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

/// The address a simulated board without `board_ip` is named by: the
/// boards' factory address 192.168.1.121, the next ones counting up.
fn default_sim_place(i: usize) -> SocketAddr {
    SocketAddr::from(([192, 168, 1, 121 + i as u8], lbp16::UDP_PORT))
}

/// The simulated boards `sim=` names, checked: each item one of
/// [`sim_boards::ETH_PRESETS`], and as many as `board_ip` has addresses
/// when both are given. Empty without `sim`.
pub fn sim_names(args: &ModuleArgs) -> Result<Vec<&'static str>, DriverError> {
    let params = Params::new(HM2_ETH, args);
    let sims = args.str_array("sim");
    let known = sim_boards::ETH_PRESETS.join(", ");
    let names = sims
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if s.is_empty() {
                return Err(params.item_error(
                    "sim",
                    i,
                    s,
                    format!("no board named: sim=BOARD, one of {known}"),
                ));
            }
            sim_boards::ETH_PRESETS
                .iter()
                .find(|&&k| k == s)
                .copied()
                .ok_or_else(|| {
                    params.item_error(
                        "sim",
                        i,
                        s,
                        format!("not a simulated Ethernet board ({known})"),
                    )
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let ips = args.str_array("board_ip");
    if !names.is_empty() && !ips.is_empty() && ips.len() != names.len() {
        return Err(params.error(
            "sim",
            format!(
                "{} simulated boards for {} board_ip addresses: give one sim item per board",
                names.len(),
                ips.len()
            ),
        ));
    }
    Ok(names)
}

/// Where each board is: `board_ip`'s addresses, checked, or for
/// simulated boards without it [`default_sim_place`]s.
fn board_places(args: &ModuleArgs, sims: usize) -> Result<Vec<SocketAddr>, DriverError> {
    let params = Params::new(HM2_ETH, args);
    let ips = args.str_array("board_ip");
    if ips.is_empty() {
        if sims == 0 {
            return Err(params.error(
                "board_ip",
                "no board given: hm2_eth probes only the listed boards (board_ip=192.168.1.121, or sim=BOARD for a simulated one)",
            ));
        }
        return Ok((0..sims).map(default_sim_place).collect());
    }
    let mut peers: Vec<SocketAddr> = Vec::with_capacity(ips.len());
    for (i, ip) in ips.iter().enumerate() {
        let peer = parse_board_address(ip)
            .map_err(|reason| params.item_error("board_ip", i, ip, reason))?;
        if let Some(first) = peers.iter().position(|&earlier| earlier == peer) {
            return Err(params.item_error(
                "board_ip",
                i,
                ip,
                Hm2Error::SameBoardTwice { first, peer },
            ));
        }
        peers.push(peer);
    }
    Ok(peers)
}

/// The transport to simulated board `name` named by `place`: the preset
/// with its machine, its EEPROM holding `place`'s IPv4 address.
fn sim_transport(name: &str, place: SocketAddr) -> Option<EthTransport> {
    let spec = sim_boards::preset(name)?;
    let ip = match place.ip() {
        IpAddr::V4(v4) => v4,
        IpAddr::V6(_) => Ipv4Addr::new(192, 168, 1, 121),
    };
    let board = sim_eth::preset_board(name, spec, ip.octets())?;
    Some(EthTransport::simulated(Arc::new(Mutex::new(board)), place))
}

/// Opens the transport to a network board at an address.
type NetworkOpener = dyn Fn(SocketAddr) -> Result<EthTransport, TransportError>;

/// Loads `hm2_eth` into our `host` with simulated boards only: a board
/// without a `sim=` item is refused before any socket is made (the
/// fuzzers load hm2_eth so).
pub fn load_without_network(host: &hal_core::Host, args: &ModuleArgs) -> hal_core::Result<()> {
    let refuse = |peer: SocketAddr| -> Result<EthTransport, TransportError> {
        Err(TransportError::Socket {
            op: "reaching",
            peer: peer.to_string(),
            reason: "the network is not reached in this load (simulated boards only: sim=)".into(),
        })
    };
    let env = module::env(host);
    let found = open_eth(args, &env, &refuse)?;
    module::load_opened::<HalHm2Eth>(host, found)
}

/// Probes the boards `args` list: network ones through `network`, the
/// `sim` items as simulated ones.
fn open_eth(args: &ModuleArgs, env: &LoadEnv, network: &NetworkOpener) -> hal_core::Result<Boards> {
    let debug = core(env, HM2_ETH)?;
    let params = Params::new(HM2_ETH, args);
    let log = env.log();
    log.info(format_args!(
        "hm2_eth: loading Mesa AnyIO HostMot2 ethernet driver version 0.2"
    ));
    let sims = sim_names(args).for_module(HM2_ETH)?;
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
    // Every address is read and checked before any board is probed.
    let peers = board_places(args, sims.len()).for_module(HM2_ETH)?;
    let mut counts: HashMap<String, usize> = HashMap::new();
    let mut candidates = Vec::with_capacity(peers.len());
    for (i, &peer) in peers.iter().enumerate() {
        let place = Place {
            address: args
                .str_array("board_ip")
                .get(i)
                .cloned()
                .unwrap_or_else(|| peer.ip().to_string()),
            peer,
            sim: sims.get(i).copied(),
        };
        candidates.push(open_board(&place, env, network, &mut counts, firewall)?);
    }
    Ok(Boards::new(
        env,
        HM2_ETH,
        debug,
        candidates,
        args.str_array("config").to_vec(),
    ))
}

/// Where one board is: as given, as an address, and the simulated board
/// that stands in for it.
struct Place {
    /// The `board_ip` item (or the address named for a simulated board).
    address: String,
    /// Its address.
    peer: SocketAddr,
    /// The `sim` item.
    sim: Option<&'static str>,
}

/// Opens and identifies the board at `place`; `counts` numbers the
/// boards of each type.
fn open_board(
    place: &Place,
    env: &LoadEnv,
    network: &NetworkOpener,
    counts: &mut HashMap<String, usize>,
    firewall: Option<&str>,
) -> hal_core::Result<Candidate> {
    let log = env.log();
    let peer = place.peer;
    let refuse = |e: TransportError| {
        log.err(format_args!("hm2_eth: board at {peer}: {e}"));
        HalError::module_failed(
            HM2_ETH,
            Hm2Error::EthBoard {
                address: place.address.clone(),
                peer,
                source: e,
            },
        )
    };
    let mut t = match place.sim {
        // sim_names checked the name: every one has a preset.
        Some(name) => sim_transport(name, peer)
            .ok_or_else(|| TransportError::Socket {
                op: "simulating",
                peer: peer.to_string(),
                reason: format!("no simulated Ethernet board '{name}'"),
            })
            .map_err(refuse)?,
        None => network(peer).map_err(refuse)?,
    };
    let simulated = t.sim_board().is_some();
    let found = probe(&mut t).map_err(refuse)?;
    log.info(format_args!(
        "hm2_eth: discovered {}{}",
        found.name,
        if simulated { " (simulated)" } else { "" }
    ));
    let mut next = |board: &str| {
        let n = counts.entry(board.to_string()).or_insert(0);
        *n += 1;
        *n - 1
    };
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
    if !peer.ip().is_loopback() && !simulated {
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
    Ok(Candidate {
        place: if simulated {
            format!("(simulated at {peer})")
        } else {
            format!("at {peer}")
        },
        fails: format!("hm2_eth: board at {peer} fails HM2 registration"),
        llio,
        source: Source::Eth(Box::new(t)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(words: &[&str]) -> ModuleArgs {
        ModuleArgs::parse(HM2_ETH, HalHm2Eth::PARAMS, words).unwrap()
    }

    fn refused(words: &[&str]) -> String {
        sim_names(&args(words))
            .and_then(|_| board_places(&args(words), 0))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn sim_takes_one_known_board_per_item() {
        assert_eq!(
            sim_names(&args(&[
                "sim=7i93,7i96s",
                "board_ip=10.10.10.10,10.10.10.11"
            ]))
            .unwrap(),
            ["7i93", "7i96s"]
        );
        assert_eq!(sim_names(&args(&["sim=7i92"])).unwrap(), ["7i92"]);
        assert!(sim_names(&args(&["board_ip=10.0.0.1"])).unwrap().is_empty());
        let e = refused(&["sim=7i99"]);
        assert!(
            e.contains("7i99") && e.contains("7i96s, 7i76e, 7i93"),
            "{e}"
        );
        let e = refused(&["sim=5i25"]);
        assert!(e.contains("not a simulated Ethernet board"), "{e}");
        for bare in [&["sim="][..], &["sim=7i93,"], &["sim=,7i93"]] {
            let e = refused(bare);
            assert!(e.contains("no board named: sim=BOARD, one of 7i96s"), "{e}");
        }
        let e = refused(&["sim=7i93,7i93", "board_ip=10.10.10.10"]);
        assert!(
            e.contains("2 simulated boards for 1 board_ip addresses"),
            "{e}"
        );
        let e = refused(&["sim=7i93", "board_ip=10.10.10.10,10.10.10.11"]);
        assert!(e.contains("1 simulated boards for 2"), "{e}");
    }

    #[test]
    fn simulated_boards_are_named_by_board_ip_or_the_factory_address() {
        let a = args(&["sim=7i93,7i93"]);
        assert_eq!(
            board_places(&a, 2).unwrap(),
            [
                "192.168.1.121:27181".parse().unwrap(),
                "192.168.1.122:27181".parse().unwrap()
            ]
        );
        let a = args(&["sim=7i96s", "board_ip=10.10.10.10"]);
        assert_eq!(
            board_places(&a, 1).unwrap(),
            ["10.10.10.10:27181".parse().unwrap()]
        );
        let e = board_places(&args(&["board_ip=10.1.1.1,10.1.1.1"]), 0).unwrap_err();
        assert!(e.to_string().contains("board_ip"), "{e}");
        let e = board_places(&args(&[]), 0).unwrap_err();
        assert!(e.to_string().contains("sim=BOARD"), "{e}");
        let t = sim_transport("7i93", "10.10.10.10:27181".parse().unwrap()).unwrap();
        let board = t.sim_board().unwrap().lock().unwrap();
        assert_eq!(board.identity().ip, [10, 10, 10, 10]);
        assert_eq!(board.identity().name, "7I93");
        assert!(sim_transport("5i25", t.peer()).is_none());
        for name in sim_boards::ETH_PRESETS {
            assert!(sim_transport(name, t.peer()).is_some(), "{name}");
        }
    }

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
