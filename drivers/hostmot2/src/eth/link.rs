//! What an [`EthTransport`](super::EthTransport)'s datagrams travel on:
//! a UDP socket `connect()`ed to one board, or a simulated board in this
//! process (`hm2_eth sim=BOARD`).
//!
//! The simulated link hands each request datagram, byte for byte as it
//! would leave on the network, to the board's LBP16 handler
//! ([`EthBoard::handle`]) and keeps its reply for the next receive, so
//! the transport's packet code (tags, lengths, bookkeeping) runs exactly
//! as over UDP. Nothing is lost, late or duplicated on it: a datagram the
//! board does not answer (writes only, or a malformed one) leaves
//! nothing to receive, and a receive then times out at once instead of
//! waiting for its deadline.

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::os::fd::AsFd;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Instant;

use nix::poll::{ppoll, PollFd, PollFlags};
use nix::sys::time::TimeSpec;

use crate::sim::eth::EthBoard;

/// A simulated Ethernet board as `hm2_eth sim=` shares it: the link
/// drives it, tests and tools find it (`hal_driver::sim::find`) under
/// the board's HAL name.
pub type SharedEthBoard = Mutex<EthBoard>;

/// Bytes a reply may have (LBP16's largest is under 1500).
const REPLY_CAPACITY: usize = 2048;

/// The board end of a datagram's trip.
pub enum Link {
    /// A UDP socket connected to the board.
    Udp(UdpSocket),
    /// A simulated board in this process.
    Sim(SimLink),
}

/// A simulated board and the reply it owes.
pub struct SimLink {
    board: Arc<SharedEthBoard>,
    reply: Vec<u8>,
    pending: bool,
}

impl SimLink {
    /// A link to `board`.
    pub fn new(board: Arc<SharedEthBoard>) -> SimLink {
        SimLink {
            board,
            reply: Vec::with_capacity(REPLY_CAPACITY),
            pending: false,
        }
    }

    /// The board.
    pub fn board(&self) -> &Arc<SharedEthBoard> {
        &self.board
    }

    /// The board, locked. The lock is the simulator's (as in
    /// `hal_driver::sim::SimBoard`): uncontended but for a test looking.
    fn lock(&self) -> MutexGuard<'_, EthBoard> {
        self.board.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn send(&mut self, datagram: &[u8]) -> usize {
        let SimLink {
            board,
            reply,
            pending,
        } = self;
        let mut b = board.lock().unwrap_or_else(|e| e.into_inner());
        // A reply not taken is gone, as a datagram nobody read.
        *pending = b.handle(datagram, reply);
        datagram.len()
    }

    fn receive(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if !std::mem::take(&mut self.pending) {
            return Err(io::ErrorKind::TimedOut.into());
        }
        let n = self.reply.len();
        let Some(dst) = buf.get_mut(..n) else {
            // Longer than any datagram the transport takes: dropped, as
            // the socket would truncate it into a wrong-length reply.
            return Err(io::ErrorKind::TimedOut.into());
        };
        dst.copy_from_slice(&self.reply);
        Ok(n)
    }

    /// Lets the board's time move one `period_ns` per cycle.
    fn set_period(&self, period_ns: u64) {
        self.lock().set_period(period_ns);
    }
}

impl Link {
    /// A UDP socket bound to any local port and connected to `peer`.
    pub fn udp(peer: SocketAddr) -> Result<Link, (&'static str, io::Error)> {
        let local: SocketAddr = if peer.is_ipv4() {
            SocketAddr::from(([0, 0, 0, 0], 0))
        } else {
            SocketAddr::from(([0u16; 8], 0))
        };
        let socket = UdpSocket::bind(local).map_err(|e| ("binding a socket for", e))?;
        socket.connect(peer).map_err(|e| ("connecting to", e))?;
        socket
            .set_nonblocking(true)
            .map_err(|e| ("configuring the socket for", e))?;
        Ok(Link::Udp(socket))
    }

    /// Sends one datagram; returns the bytes sent.
    #[inline]
    pub fn send(&mut self, datagram: &[u8]) -> io::Result<usize> {
        match self {
            Link::Udp(socket) => socket.send(datagram),
            Link::Sim(sim) => Ok(sim.send(datagram)),
        }
    }

    /// Receives one datagram into `buf`, waiting until `deadline` at
    /// most (on the simulated link, not at all).
    pub fn receive_until(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        match self {
            Link::Sim(sim) => sim.receive(buf),
            Link::Udp(socket) => loop {
                match socket.recv(buf) {
                    Ok(n) => return Ok(n),
                    Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e),
                }
                let now = Instant::now();
                if now >= deadline {
                    return Err(io::ErrorKind::TimedOut.into());
                }
                let left = deadline - now;
                let mut fds = [PollFd::new(socket.as_fd(), PollFlags::POLLIN)];
                match ppoll(&mut fds, Some(TimeSpec::from_duration(left)), None) {
                    Ok(_) | Err(nix::errno::Errno::EINTR) => {}
                    Err(e) => return Err(e.into()),
                }
            },
        }
    }

    /// The thread's period: a simulated board moves its time by it per
    /// cycle.
    pub fn set_period(&self, period_ns: i64) {
        if let Link::Sim(sim) = self {
            if period_ns > 0 {
                sim.set_period(period_ns as u64);
            }
        }
    }

    /// The simulated board, if this link is one.
    pub fn sim_board(&self) -> Option<&Arc<SharedEthBoard>> {
        match self {
            Link::Sim(sim) => Some(sim.board()),
            Link::Udp(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lbp16::{addr, space, Request};
    use crate::sim::{boards, eth};

    fn sim_link(name: &str) -> Link {
        let spec = boards::preset(name).unwrap();
        let board = eth::preset_board(name, spec, [10, 10, 10, 10]).unwrap();
        Link::Sim(SimLink::new(Arc::new(Mutex::new(board))))
    }

    #[test]
    fn a_request_is_answered_once_and_writes_not_at_all() {
        let mut link = sim_link("7i93");
        let mut r = Request::new();
        r.read16(space::BOARD_INFO, addr::INFO_NAME, 8).unwrap();
        assert_eq!(link.send(r.bytes()).unwrap(), r.bytes().len());
        let mut buf = [0u8; 2048];
        let n = link.receive_until(&mut buf, Instant::now()).unwrap();
        assert_eq!(n, r.reply_len());
        assert_eq!(&buf[..4], b"7I93");
        let e = link.receive_until(&mut buf, Instant::now()).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::TimedOut, "one reply per request");
        let mut w = Request::new();
        w.hm2_write(0x0200, &[0]).unwrap();
        link.send(w.bytes()).unwrap();
        assert!(link.receive_until(&mut buf, Instant::now()).is_err());
        let board = link.sim_board().unwrap();
        assert_eq!(board.lock().unwrap().identity().ip, [10, 10, 10, 10]);
    }

    #[test]
    fn a_cycle_moves_the_board_by_the_period() {
        let mut link = sim_link("7i96s");
        link.set_period(1_000_000);
        let mut r = Request::new();
        r.write16(space::TIMER, addr::TIMER_READ_TAG, &[1, 0])
            .unwrap();
        r.read16(space::TIMER, addr::TIMER_READ_TAG, 2).unwrap();
        link.send(r.bytes()).unwrap();
        let board = link.sim_board().unwrap().clone();
        assert_eq!(board.lock().unwrap().model().now_ns(), 1_000_000);
        assert_eq!(board.lock().unwrap().cycles(), 1);
    }
}
