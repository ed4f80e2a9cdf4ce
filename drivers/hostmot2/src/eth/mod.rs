//! `hm2_eth`: Mesa's Ethernet cards (7I76E, 7I96S, 7I92, 7I95, 7I97, ...)
//! over LBP16 on UDP (hostmot2-more.md 1).
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
//! LinuxCNC's hm2_eth changes the host: a permanent ARP entry for each
//! board (so no ARP exchange happens in a realtime cycle) and firewall
//! rules that reject every other packet on the board's interface (so
//! nothing else adds latency there). This driver changes nothing on the
//! host: those are setup steps, done once by the administrator
//! (hostmot2 crate documentation, "Ethernet boards"), and the `firewall`
//! parameter is accepted for compatibility only. Nothing is needed for a
//! simulator on 127.0.0.1.
//!
//! # Modules
//!
//! [`boards`] (the table), [`errors`] (packet errors), [`transport`] (the
//! UDP transport), [`hal`] (the `loadrt` module).

pub mod boards;
pub mod errors;
pub mod hal;
pub mod transport;

pub use transport::EthTransport;
