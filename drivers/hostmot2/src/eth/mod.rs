//! `hm2_eth`: Mesa's Ethernet cards (7I76E, 7I96S, 7I92, 7I95, 7I97, ...)
//! over LBP16 on UDP (hostmot2-more.md 1), or simulated ones in process
//! (`sim=`).
//!
//! ```text
//! loadrt hostmot2
//! loadrt hm2_eth board_ip=192.168.1.121 config="num_encoders=1 num_stepgens=5"
//! addf hm2_7i96s.0.read-request servo-thread
//! addf hm2_7i96s.0.read servo-thread
//! ...
//! addf hm2_7i96s.0.write servo-thread
//! ```
//!
//! # Parameters
//!
//! LinuxCNC's: `board_ip` (up to four boards, comma-separated; only the
//! listed boards are probed, there is no default address), `config` (the
//! hostmot2 config string of each board), `board_rtnet` (`posix`, the
//! only kind of socket here; `evl` is refused), `firewall` (accepted:
//! `auto`, `iptables`, `nft`, `nftables`, `none`; see below) and `debug`.
//! An address may carry a port (`board_ip=127.0.0.1:40123`): the boards
//! listen on 27181, a simulator may listen elsewhere, and tests run
//! several side by side.
//!
//! Ours besides: `sim` (one item per board, comma-separated like
//! `board_ip`: `7i96s`, `7i76e`, `7i93`, `7i92` or `7i95`, the boards of
//! [`crate::sim::boards`]) puts a simulated board inside the HAL process
//! in place of each network board. The transport is the same, its
//! datagrams byte for byte as on the wire, but each goes to the
//! simulated board's LBP16 handler instead of a socket ([`link`]); the
//! board names itself as the real card does (`7I93`, so `hm2_7i93.0`),
//! runs its machine ([`crate::sim::machine::preset`]) one thread period
//! per cycle, and is published for tests under its HAL name
//! ([`link::SharedEthBoard`]). `board_ip` may stay as the configuration
//! has it: its addresses only name the boards in messages (and sit in
//! their EEPROM), nothing is sent; given both, they must have as many
//! items. Without `board_ip` the simulated boards are named
//! 192.168.1.121, .122, ... A LinuxCNC configuration so runs with one
//! word added to its driver line:
//!
//! ```text
//! [HOSTMOT2]
//! DRIVER=hm2_eth sim=7i93
//! BOARD_IP=192.168.1.121
//! ```
//!
//! An empty item (`sim=`, `sim=7i93,`) or an unknown board is refused
//! with the list of boards; the separate `hm2-eth-sim` tool serves the
//! same boards on a UDP port instead, with injected faults.
//!
//! # Names and functions
//!
//! The board's space-7 name selects its entry of the board table
//! ([`boards::BOARDS`]): `hm2_7i96s.0`, `hm2_7i76e.0`, counted per type.
//! Each board exports `read-request`, `read` and `write` (no
//! `read_gpio`/`write_gpio`: the transport is not thread-safe), and the
//! packet-error pins and params of [`errors`]. With several boards, add
//! every `read-request` first, then every `read`, so the round trips
//! overlap.
//!
//! # The host's network
//!
//! LinuxCNC's hm2_eth changes the host at load: a permanent ARP entry
//! for each board (read from the board's EEPROM: so no ARP exchange
//! happens in a realtime cycle), and firewall rules (an iptables chain
//! `hm2-eth-rules-output` or an nftables table `inet hm2_eth`) that let
//! only the driver's packets to the board leave the board's interface,
//! drop ICMP there and reject the rest, all removed at unload. It needs
//! CAP_NET_ADMIN for both and warns when it cannot.
//!
//! This driver changes nothing on the host, ever: no capability is
//! needed and a crash leaves nothing behind. The same effect is a setup
//! step, done once by the administrator for the board's dedicated wired
//! interface (say `enp3s0`, the host at 192.168.1.1/24, the board at
//! 192.168.1.121; the MAC is in `hal-board idrom` and the load log):
//!
//! ```text
//! # the link: a static address, no interrupt coalescing
//! sudo ip addr add 192.168.1.1/24 dev enp3s0
//! sudo ethtool -C enp3s0 rx-usecs 0
//! # a permanent ARP entry: no ARP exchange in a realtime cycle
//! sudo ip neigh replace 192.168.1.121 lladdr 00:60:1b:16:00:01 nud permanent dev enp3s0
//! # nothing but the board's traffic on that interface
//! sudo nft add table inet hm2_eth
//! sudo nft add chain inet hm2_eth output '{ type filter hook output priority 0; policy accept; }'
//! sudo nft add rule inet hm2_eth output oif enp3s0 ip daddr 192.168.1.121 udp dport 27181 accept
//! sudo nft add rule inet hm2_eth output oif enp3s0 ip protocol icmp drop
//! sudo nft add rule inet hm2_eth output oif enp3s0 reject with icmp type admin-prohibited
//! ```
//!
//! (`sudo nft delete table inet hm2_eth` undoes the rules; make them
//! permanent with the distribution's network and nftables
//! configuration.) The `firewall` parameter is accepted for
//! compatibility and changes nothing; for a board off the loopback the
//! load says (at info level) that the host was left alone. Nothing is
//! needed for a simulator on 127.0.0.1, where LinuxCNC too adds nothing.
//!
//! # Modules
//!
//! [`boards`] (the table), [`errors`] (packet errors), [`transport`] (the
//! LBP16 transport), [`link`] (its UDP socket or in-process simulated
//! board), [`hal`] (the `loadrt` module).

pub mod boards;
pub mod errors;
pub mod hal;
pub mod link;
pub mod transport;

pub use transport::EthTransport;
