//! The CAN bus the driver talks through: one small trait, [`CanBus`], in
//! the shared driver layer's shape (`&self` accessors that never fail
//! visibly, an `errors()` count, `tick` for a simulator's time), with a
//! real backend and a simulated one:
//!
//! | backend | what it is |
//! |---|---|
//! | [`SocketCanBus`] | a non-blocking `CAN_RAW` socket on `can0`, `vcan0`, ... (the `socketcan` crate) |
//! | [`SimEndpoint`] | an endpoint of a [`SimBus`]: an in-process bus with simulated CiA 402 drives on it |
//!
//! A `CanBus` value is one endpoint, like one socket: it sees the frames
//! its [`Filters`] let through and sends frames the other endpoints and
//! the drives receive. The realtime functions own one endpoint and call
//! only [`send`](CanBus::send), [`try_recv`](CanBus::try_recv) and
//! [`tick`](CanBus::tick), none of which blocks. Start-up, the
//! diagnostics helper and the bring-up tool own others and may wait
//! with [`recv_timeout`](CanBus::recv_timeout).

mod sim;
mod socket;

use std::time::Duration;

pub use sim::{BusStats, SimBus, SimEndpoint, WallClock};
pub use socket::SocketCanBus;

use crate::frame::{Frame, CAN_EFF_FLAG, CAN_RTR_FLAG, CAN_SFF_MASK};
use crate::regs::{cob, err};

/// One endpoint on a CAN bus.
pub trait CanBus: Send + Sync {
    /// Queues `frame` for transmission without blocking. False when it
    /// could not be queued (bus off, transmit queue full, interface
    /// down); the failure is counted in [`errors`](Self::errors).
    fn send(&self, frame: &Frame) -> bool;

    /// The next received frame, without blocking; None when there is
    /// none now (or the receive failed, which is counted).
    fn try_recv(&self) -> Option<Frame>;

    /// The next received frame, waiting up to `timeout`. Not for
    /// realtime code.
    fn recv_timeout(&self, timeout: Duration) -> Option<Frame>;

    /// Waits up to `timeout` for room to queue a frame, after a send
    /// failed; returns early when there may be room. Not for realtime
    /// code. The default pauses a millisecond (at most `timeout`).
    fn wait_writable(&self, timeout: Duration) {
        std::thread::sleep(timeout.min(Duration::from_millis(1)));
    }

    /// Failed sends and receives so far.
    fn errors(&self) -> u64;

    /// What the endpoint is, for messages ("SocketCAN vcan0").
    fn describe(&self) -> String;

    /// The HAL thread's time, once per cycle from the `read` function:
    /// real interfaces ignore it; the simulated bus advances its drives
    /// and delivers the frames due by then.
    fn tick(&self, now_ns: u64) {
        let _ = now_ns;
    }
}

/// One receive filter, with the kernel's semantics: a frame passes when
/// `can_id & mask == id & mask` (`can_id` with its flag bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Filter {
    /// Identifier and flag bits to match.
    pub id: u32,
    /// Which bits must match.
    pub mask: u32,
}

impl Filter {
    /// Exactly the standard data frame with identifier `cob`.
    pub const fn exact(cob: u16) -> Filter {
        Filter {
            id: cob as u32,
            mask: CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG,
        }
    }

    /// Every frame.
    pub const fn all() -> Filter {
        Filter { id: 0, mask: 0 }
    }

    /// Whether `frame` (not an error frame) passes.
    pub fn matches(&self, frame: &Frame) -> bool {
        frame.can_id() & self.mask == self.id & self.mask
    }
}

/// An endpoint's receive filters and the error classes it wants as
/// error frames.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Filters {
    /// Data and remote frames passing any of these are received.
    pub frames: Vec<Filter>,
    /// Error classes (`regs::err`) received as error frames; 0 = none.
    pub error_mask: u32,
}

impl Filters {
    /// Everything, with every error class.
    pub fn everything() -> Filters {
        Filters {
            frames: vec![Filter::all()],
            error_mask: crate::frame::CAN_EFF_MASK,
        }
    }

    /// The realtime endpoint's filters for drives `nodes` (§6.11 step 1):
    /// TPDO1, TPDO2, EMCY and heartbeat of each node, and the error
    /// classes bus-off, controller, restarted, no-ACK and TX timeout.
    pub fn realtime(nodes: &[u8]) -> Filters {
        Filters {
            frames: nodes
                .iter()
                .flat_map(|&n| {
                    let n = u16::from(n);
                    [
                        Filter::exact(cob::TPDO[0] + n),
                        Filter::exact(cob::TPDO[1] + n),
                        Filter::exact(cob::EMCY + n),
                        Filter::exact(cob::HEARTBEAT + n),
                    ]
                })
                .collect(),
            error_mask: err::MASTER_MASK,
        }
    }

    /// A setup endpoint's filters (start-up, restarts, diagnostics):
    /// SDO answers and boot-up/heartbeat of each of `nodes`.
    pub fn setup(nodes: &[u8]) -> Filters {
        Filters {
            frames: nodes
                .iter()
                .flat_map(|&n| {
                    let n = u16::from(n);
                    [
                        Filter::exact(cob::SDO_TX + n),
                        Filter::exact(cob::HEARTBEAT + n),
                    ]
                })
                .collect(),
            error_mask: 0,
        }
    }

    /// Whether an endpoint with these filters receives `frame`.
    pub fn accepts(&self, frame: &Frame) -> bool {
        match frame.kind {
            crate::frame::FrameKind::Error => frame.id & self.error_mask != 0,
            _ => self.frames.iter().any(|f| f.matches(frame)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_follow_the_kernel() {
        let f = Filters {
            frames: vec![Filter::exact(0x181)],
            error_mask: crate::regs::err::BUSOFF,
        };
        assert!(f.accepts(&Frame::new(0x181, &[1])));
        assert!(!f.accepts(&Frame::new(0x182, &[1])));
        assert!(!f.accepts(&Frame::remote(0x181, 1)));
        assert!(f.accepts(&Frame::error(crate::regs::err::BUSOFF, [0; 8])));
        assert!(!f.accepts(&Frame::error(crate::regs::err::ACK, [0; 8])));
        assert!(Filters::everything().accepts(&Frame::remote(0x7FF, 0)));
    }
}
