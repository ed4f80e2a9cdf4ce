//! How frames travel between the master and a segment: a [`Link`] sends
//! a whole Ethernet frame and receives the ones that come back.
//!
//! * [`InProcess`]: straight into a [`Segment`] in this process, on the
//!   monotonic clock (`backend=sim`, unit tests, the benchmark).
//! * [`RawSocket`]: an AF_PACKET socket bound to an interface for the
//!   EtherCAT EtherType (a NIC, or one end of a veth pair with
//!   `ethercat-sim` on the other). It needs CAP_NET_RAW, which the `hal`
//!   group's set-up grants as a file capability; never setuid.

use std::collections::VecDeque;
use std::io;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::sim::{Outcome, Segment};

/// A way to a segment.
pub trait Link: Send {
    /// Sends one Ethernet frame.
    fn send(&mut self, frame: &[u8]) -> io::Result<()>;
    /// Receives one frame into `buf`, waiting up to `timeout`; None if
    /// none came.
    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>>;
    /// Whether the link is up (carrier), as far as the link knows.
    fn is_up(&self) -> bool {
        true
    }
    /// "sim", "eth0": for messages.
    fn describe(&self) -> String;
}

/// A segment shared between the link and whoever injects faults.
pub type SharedSegment = Arc<Mutex<Segment>>;

/// A link to a segment in this process.
#[derive(Debug)]
pub struct InProcess {
    segment: SharedSegment,
    replies: VecDeque<Vec<u8>>,
    epoch: Instant,
}

impl InProcess {
    /// A link to `segment`.
    pub fn new(segment: SharedSegment) -> InProcess {
        InProcess {
            segment,
            replies: VecDeque::new(),
            epoch: Instant::now(),
        }
    }
}

impl Link for InProcess {
    fn send(&mut self, frame: &[u8]) -> io::Result<()> {
        let mut f = frame.to_vec();
        let now = self.epoch.elapsed().as_nanos() as u64;
        let outcome = match self.segment.lock() {
            Ok(mut s) => s.process(&mut f, now),
            Err(poisoned) => poisoned.into_inner().process(&mut f, now),
        };
        if outcome == Outcome::Returned {
            self.replies.push_back(f);
        }
        Ok(())
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>> {
        match self.replies.pop_front() {
            Some(f) => {
                let n = f.len().min(buf.len());
                buf[..n].copy_from_slice(&f[..n]);
                Ok(Some(n))
            }
            None => {
                // Nothing is in flight: a frame that was lost stays lost.
                if !timeout.is_zero() {
                    std::thread::sleep(timeout.min(Duration::from_micros(50)));
                }
                Ok(None)
            }
        }
    }

    fn describe(&self) -> String {
        "sim".into()
    }
}

pub use raw::RawSocket;

#[allow(unsafe_code)]
mod raw {
    //! The AF_PACKET socket: the one place this crate calls the C
    //! library, each call with its SAFETY note.

    use std::ffi::CString;
    use std::io;
    use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
    use std::time::Duration;

    use super::Link;
    use crate::wire::frame::ETHERTYPE;

    /// Linux's PACKET_IGNORE_OUTGOING (not in every libc version).
    const PACKET_IGNORE_OUTGOING: libc::c_int = 23;

    /// A raw socket on one interface, for EtherCAT frames only.
    #[derive(Debug)]
    pub struct RawSocket {
        fd: OwnedFd,
        iface: String,
        index: libc::c_int,
    }

    fn os(what: &str, iface: &str) -> io::Error {
        let e = io::Error::last_os_error();
        io::Error::new(e.kind(), format!("{what} on '{iface}': {e}"))
    }

    impl RawSocket {
        /// Opens a socket bound to `iface`. Frames this socket sends are
        /// not received back by it.
        pub fn open(iface: &str) -> io::Result<RawSocket> {
            let name = CString::new(iface).map_err(|_| {
                io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "interface name holds a NUL byte",
                )
            })?;
            // SAFETY: if_nametoindex reads a NUL-terminated string we own.
            let index = unsafe { libc::if_nametoindex(name.as_ptr()) } as libc::c_int;
            if index == 0 {
                return Err(os("no such interface", iface));
            }
            let proto = (ETHERTYPE).to_be() as libc::c_int;
            // SAFETY: plain socket(2) call; the result is checked.
            let fd = unsafe {
                libc::socket(libc::AF_PACKET, libc::SOCK_RAW | libc::SOCK_CLOEXEC, proto)
            };
            if fd < 0 {
                let e = io::Error::last_os_error();
                let hint = if e.raw_os_error() == Some(libc::EPERM) {
                    " (raw sockets need CAP_NET_RAW: run the host as a member of the hal group after the installer's setcap, or as root)"
                } else {
                    ""
                };
                return Err(io::Error::new(
                    e.kind(),
                    format!("raw socket on '{iface}': {e}{hint}"),
                ));
            }
            // SAFETY: fd is a fresh descriptor we own from here on.
            let fd = unsafe { OwnedFd::from_raw_fd(fd) };
            // SAFETY: an all-zero sockaddr_ll is a valid value to fill in.
            let mut addr: libc::sockaddr_ll = unsafe { std::mem::zeroed() };
            addr.sll_family = libc::AF_PACKET as u16;
            addr.sll_protocol = ETHERTYPE.to_be();
            addr.sll_ifindex = index;
            // SAFETY: addr is a sockaddr_ll of the size given.
            let r = unsafe {
                libc::bind(
                    fd.as_raw_fd(),
                    (&addr as *const libc::sockaddr_ll).cast(),
                    std::mem::size_of::<libc::sockaddr_ll>() as u32,
                )
            };
            if r < 0 {
                return Err(os("bind", iface));
            }
            let one: libc::c_int = 1;
            // SAFETY: setsockopt with a c_int value of the size given.
            unsafe {
                libc::setsockopt(
                    fd.as_raw_fd(),
                    libc::SOL_PACKET,
                    PACKET_IGNORE_OUTGOING,
                    (&one as *const libc::c_int).cast(),
                    std::mem::size_of::<libc::c_int>() as u32,
                );
            }
            Ok(RawSocket {
                fd,
                iface: iface.to_string(),
                index,
            })
        }
    }

    impl Link for RawSocket {
        fn send(&mut self, frame: &[u8]) -> io::Result<()> {
            // SAFETY: the buffer is valid for frame.len() bytes.
            let n =
                unsafe { libc::send(self.fd.as_raw_fd(), frame.as_ptr().cast(), frame.len(), 0) };
            if n < 0 {
                return Err(os("send", &self.iface));
            }
            Ok(())
        }

        fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>> {
            let mut pfd = libc::pollfd {
                fd: self.fd.as_raw_fd(),
                events: libc::POLLIN,
                revents: 0,
            };
            let ms = timeout.as_micros().div_ceil(1000).min(i32::MAX as u128) as libc::c_int;
            // SAFETY: one pollfd, valid for the call.
            let r = unsafe { libc::poll(&mut pfd, 1, ms) };
            if r < 0 {
                let e = io::Error::last_os_error();
                return if e.kind() == io::ErrorKind::Interrupted {
                    Ok(None)
                } else {
                    Err(e)
                };
            }
            if r == 0 {
                return Ok(None);
            }
            // SAFETY: the buffer is valid for buf.len() bytes.
            let n = unsafe {
                libc::recv(
                    self.fd.as_raw_fd(),
                    buf.as_mut_ptr().cast(),
                    buf.len(),
                    libc::MSG_DONTWAIT,
                )
            };
            if n < 0 {
                let e = io::Error::last_os_error();
                return if e.kind() == io::ErrorKind::WouldBlock {
                    Ok(None)
                } else {
                    Err(e)
                };
            }
            Ok(Some(n as usize))
        }

        fn is_up(&self) -> bool {
            let path = format!("/sys/class/net/{}/carrier", self.iface);
            std::fs::read_to_string(path)
                .map(|s| s.trim() == "1")
                .unwrap_or(true)
        }

        fn describe(&self) -> String {
            format!("{} (ifindex {})", self.iface, self.index)
        }
    }
}
