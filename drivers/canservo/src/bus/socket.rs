//! [`SocketCanBus`]: a `CAN_RAW` socket through the `socketcan` crate,
//! bound to one interface, non-blocking.
//!
//! Why non-blocking and no helper thread: the `write` function must put
//! the RPDOs and then SYNC on the bus at the start of the servo period it
//! runs in; a helper thread would move the SYNC to whenever that thread
//! is scheduled, which is jitter the drives' interpolation sees. A
//! non-blocking `write()` on a raw CAN socket only copies the frame into
//! the interface's queue (or fails at once with `ENOBUFS` when the queue
//! is full or the controller is bus-off), and a non-blocking `read()`
//! returns `EAGAIN` when nothing is there, so neither can hold the cycle.

use std::io;
use std::os::fd::AsFd;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::time::Duration;

use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use socketcan::{CanFilter, CanFrame, CanSocket, Socket, SocketOptions};

use super::{CanBus, Filters};
use crate::error::Error;
use crate::frame::Frame;

/// A non-blocking SocketCAN endpoint.
#[derive(Debug)]
pub struct SocketCanBus {
    sock: CanSocket,
    iface: String,
    errors: AtomicU64,
}

/// `IFF_UP` in `/sys/class/net/<if>/flags`.
const IFF_UP: u32 = 0x1;

impl SocketCanBus {
    /// Opens `iface` with `filters`: checks that the interface exists,
    /// is a CAN interface and is up, then binds a raw socket, installs
    /// the filters and makes it non-blocking.
    pub fn open(iface: &str, filters: &Filters) -> Result<SocketCanBus, Error> {
        let bad = |op: &'static str| {
            move |source: io::Error| Error::Socket {
                iface: iface.to_string(),
                op,
                source,
            }
        };
        check_interface(iface)?;
        let sock = CanSocket::open(iface).map_err(bad("opening a CAN_RAW socket"))?;
        let kernel_filters: Vec<CanFilter> = filters
            .frames
            .iter()
            .map(|f| CanFilter::new(f.id, f.mask))
            .collect();
        if kernel_filters.is_empty() {
            sock.set_filter_drop_all()
        } else {
            sock.set_filters(&kernel_filters)
        }
        .map_err(bad("setting receive filters"))?;
        sock.set_error_filter(filters.error_mask)
            .map_err(bad("setting the error-frame filter"))?;
        sock.set_nonblocking(true)
            .map_err(bad("making the socket non-blocking"))?;
        Ok(SocketCanBus {
            sock,
            iface: iface.to_string(),
            errors: AtomicU64::new(0),
        })
    }

    /// The interface name.
    pub fn iface(&self) -> &str {
        &self.iface
    }

    fn to_kernel(frame: &Frame) -> CanFrame {
        let mut raw = socketcan::frame::can_frame_default();
        raw.can_id = frame.can_id();
        raw.can_dlc = frame.len.min(8);
        raw.data = frame.data;
        CanFrame::from(raw)
    }
}

/// Checks through sysfs that `iface` exists, is CAN (type 280) and is up.
fn check_interface(iface: &str) -> Result<(), Error> {
    let iface_name = || iface.to_string();
    if iface.is_empty() || iface.contains('/') || iface.len() > 15 {
        return Err(Error::BadInterfaceName {
            iface: iface_name(),
        });
    }
    let dir = std::path::Path::new("/sys/class/net").join(iface);
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).map(|s| s.trim().to_string());
    let Ok(kind) = read("type") else {
        return Err(Error::NoInterface {
            iface: iface_name(),
        });
    };
    if kind != "280" {
        return Err(Error::NotCan {
            iface: iface_name(),
            kind,
        });
    }
    let flags = read("flags")
        .ok()
        .and_then(|f| u32::from_str_radix(f.trim_start_matches("0x"), 16).ok())
        .unwrap_or(0);
    if flags & IFF_UP == 0 {
        return Err(Error::InterfaceDown {
            iface: iface_name(),
        });
    }
    Ok(())
}

impl CanBus for SocketCanBus {
    fn send(&self, frame: &Frame) -> bool {
        match self.sock.write_frame(&Self::to_kernel(frame)) {
            Ok(()) => true,
            Err(_) => {
                self.errors.fetch_add(1, Relaxed);
                false
            }
        }
    }

    fn try_recv(&self) -> Option<Frame> {
        match self.sock.read_raw_frame() {
            Ok(raw) => Some(Frame::from_raw(raw.can_id, raw.can_dlc, raw.data)),
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => None,
            Err(_) => {
                self.errors.fetch_add(1, Relaxed);
                None
            }
        }
    }

    fn recv_timeout(&self, timeout: Duration) -> Option<Frame> {
        if let Some(f) = self.try_recv() {
            return Some(f);
        }
        let end = std::time::Instant::now() + timeout;
        loop {
            let left = end.saturating_duration_since(std::time::Instant::now());
            if left.is_zero() {
                return None;
            }
            let ms = left.as_millis().clamp(1, i32::MAX as u128) as i32;
            let mut fds = [PollFd::new(self.sock.as_fd(), PollFlags::POLLIN)];
            match poll(
                &mut fds,
                PollTimeout::try_from(ms).unwrap_or(PollTimeout::MAX),
            ) {
                Ok(_) | Err(nix::errno::Errno::EINTR) => {}
                Err(_) => {
                    self.errors.fetch_add(1, Relaxed);
                    return None;
                }
            }
            if let Some(f) = self.try_recv() {
                return Some(f);
            }
        }
    }

    /// Waits for the socket's send buffer to have room (a full one makes
    /// the non-blocking write fail with EAGAIN). A full queue of the
    /// interface (ENOBUFS) does not show in poll, so the wait lasts at
    /// least a millisecond (or `timeout`, if shorter) either way.
    fn wait_writable(&self, timeout: Duration) {
        let began = std::time::Instant::now();
        let ms = timeout.as_millis().clamp(1, i32::MAX as u128) as i32;
        let mut fds = [PollFd::new(self.sock.as_fd(), PollFlags::POLLOUT)];
        let _ = poll(
            &mut fds,
            PollTimeout::try_from(ms).unwrap_or(PollTimeout::MAX),
        );
        let least = timeout.min(Duration::from_millis(1));
        if let Some(rest) = least.checked_sub(began.elapsed()) {
            std::thread::sleep(rest);
        }
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        format!("SocketCAN {}", self.iface)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_interfaces_are_named_with_a_hint() {
        let e = SocketCanBus::open("nocan9", &Filters::everything()).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("nocan9") && m.contains("ip link add"), "{m}");
        let e = SocketCanBus::open("a/b", &Filters::everything()).unwrap_err();
        assert!(e.to_string().contains("not a valid interface name"));
        // The loopback interface exists everywhere and is not CAN.
        let e = SocketCanBus::open("lo", &Filters::everything()).unwrap_err();
        assert!(e.to_string().contains("not a CAN interface"), "{e}");
    }
}
